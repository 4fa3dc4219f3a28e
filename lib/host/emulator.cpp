#include "host/emulator.hpp"

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <deque>
#include <functional>
#include <optional>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "device/pulse_record.hpp"
#include "host/transport.hpp"
#include "core/number.hpp"

namespace tp::host {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}
std::uint64_t monotonic_us() {
  return static_cast<std::uint64_t>(monotonic_ns() / 1000);
}

PulseRecorder::PulseRecorder(const std::string& path, const EmulatorSkin& skin)
    : scenario_(skin.scenario) {
  if (!path.empty()) out_.emplace(path, "--record");
  if (scenario_) skin_.emplace(*scenario_, skin.compliance_V);
}

void PulseRecorder::record(const device::DeliveredPulse& p, device::DeviceCore& core) {
  ++pulses_;
  // The peak: the main phase's codes, or a shape's base codes at its strongest phase.
  const double step_mA = p.caps.dac_step_nA * 1e-6 * p.timing.max_units();
  for (std::int16_t c : p.codes) peak_mA_ = std::max(peak_mA_, std::fabs(c * step_mA));
  if ((!out_ || failed_) && !skin_) return;
  // The device's own record (lib/device/pulse_record.hpp), as the firmware's monitor
  // writes it: the balancing phase in whole DAC codes; a shape's phases as configured (the
  // emulator delivers each phase exactly: base codes x units for its duration).
  device::PulseRecord r = device::record_of(p);
  device::ElectricalRecord measured;
  if (skin_) {
    skin_->measure(r, p.start_us, measured);
    core.measured(p.start_us, r, measured);
    r.electrical = &measured;
  }
  if (!out_ || failed_) return;
  char line[device::kMaxElectricalRecordLine];
  const std::size_t n = device::format_record(r, line);
  try {
    out_->write(line, n);
  } catch (const Error&) {
    failed_ = true;
    throw;
  }
}

void PulseRecorder::advance(device::DeviceCore& core, std::uint64_t now_us) {
  const auto sink = [this, &core, now_us](const device::DeliveredPulse& p) {
    if (now_us > p.t_us) latest_us_ = std::max(latest_us_, now_us - p.t_us);
    if (now_us > p.t_us + kLateUs) ++late_;
    record(p, core);
  };
  std::uint64_t first_us = 0;
  if (scenario_ && core.status().state == device::State::running &&
      scenario_->first_stop_input(first_us)) {
    const std::uint64_t stop_us = core.output_start_us() + first_us;
    if (now_us >= stop_us) {
      if (stop_us > 0) core.advance(stop_us - 1, sink);  // the pulses before it
      // Unless one of them ended the output (a guard): that is what the host is told.
      if (core.status().state == device::State::running) core.stop_input(stop_us);
    }
  }
  core.advance(now_us, sink);
}

device::Capabilities emulator_capabilities(device::Capabilities caps, const EmulatorSkin& skin) {
  caps.features |= device::kFeatureShapedPulses;
  if (skin.scenario) {  // it measures every pulse on its skin, and reports its compliance
    caps.features |= device::kFeatureMeasures;
    caps.compliance_V = static_cast<std::uint16_t>(std::lround(skin.compliance_V));
  }
  return caps;
}

// ---------------------------------------------------------------------------------------
// In-process emulator: the device core behind an in-memory link.  Replies are produced
// synchronously on write; pulses are delivered (recorded) whenever the host touches the
// link, each with its scheduled time.

namespace {

class LoopbackTransport final : public Transport {
 public:
  explicit LoopbackTransport(const EmulatorOptions& o)
      : core_(emulator_capabilities(o.caps, o.skin)), recorder_(o.record_path, o.skin) {}
  ~LoopbackTransport() override {
    try {
      advance();
    } catch (const Error&) {
      // The record failed (already reported): the output stops all the same.
    }
    core_.link_lost();
  }
  std::string name() const override { return "emu (in-process emulator)"; }

  void write(const std::uint8_t* data, std::size_t n) override {
    advance();
    std::vector<std::uint8_t> out;
    core_.receive(data, n, monotonic_us(), out);
    rx_.insert(rx_.end(), out.begin(), out.end());
  }

  std::size_t read(std::uint8_t* buf, std::size_t max, int timeout_ms) override {
    advance();
    if (rx_.empty()) {
      // Nothing more will come: the device answers synchronously.  Let time pass.
      std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
      advance();
      return 0;
    }
    std::size_t n = 0;
    while (n < max && !rx_.empty()) {
      buf[n++] = rx_.front();
      rx_.pop_front();
    }
    return n;
  }

 private:
  void advance() {
    try {
      recorder_.advance(core_, monotonic_us());
    } catch (const Error& e) {
      // The record cannot be written (a full disk): the device's output stops at once, as
      // stim-emu's does, and the message says so.
      core_.link_lost();
      failure(std::string(e.what()) + "; output stopped");
    }
  }
  device::DeviceCore core_;
  PulseRecorder recorder_;
  std::deque<std::uint8_t> rx_;
};

}  // namespace

std::unique_ptr<Transport> make_serial_transport(const std::string& path, int baud);
std::unique_ptr<Transport> make_posix_transport(const std::string& path, int baud);
bool is_pseudo_terminal(const std::string& path);

std::unique_ptr<Transport> open_transport(const std::string& port, int baud,
                                          const EmulatorOptions& emu, const std::string& backend) {
  if (port == "emu") return std::make_unique<LoopbackTransport>(emu);
  if (backend == "libserialport") return make_serial_transport(port, baud);
  if (backend == "posix") return make_posix_transport(port, baud);
  if (backend != "auto") bad_input("--backend: expected auto, libserialport or posix");
  return is_pseudo_terminal(port) ? make_posix_transport(port, baud)
                                  : make_serial_transport(port, baud);
}

// ---------------------------------------------------------------------------------------
// stim-emu: the device on a pseudo-terminal.

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) {
  g_stop = 1;
}

// Applies drop/corrupt injection to a byte buffer in place.
void inject(std::vector<std::uint8_t>& bytes, const FaultInjection& f, SplitMix64& rng) {
  if (f.drop <= 0 && f.corrupt <= 0) return;
  std::vector<std::uint8_t> out;
  out.reserve(bytes.size());
  for (std::uint8_t b : bytes) {
    if (rng.unit() < f.drop) continue;
    if (rng.unit() < f.corrupt)
      b = static_cast<std::uint8_t>(b ^ (1u << static_cast<int>(rng.unit() * 8)));
    out.push_back(b);
  }
  bytes.swap(out);
}

// Connects to the device's Unix socket, waiting up to 10 s for it to appear.
int connect_device(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof addr.sun_path) bad_input("--forward: socket path too long: " + path);
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) failure(std::string("socket: ") + std::strerror(errno));
    if (connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) {
      fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
      return fd;
    }
    const int err = errno;
    close(fd);
    if (err != ENOENT && err != ECONNREFUSED)
      failure("cannot connect to the device at " + path + ": " + std::strerror(err));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  failure("no device at " + path + " after 10 s");
}

// Waits until the device answers an identify (up to 10 s): a booting firmware drops what
// arrives before its UART is on, and a host's first frame must not be lost to that.
void await_device(int fd, const std::string& path) {
  std::vector<std::uint8_t> probe;
  device::encode_frame(device::Frame{0, static_cast<std::uint8_t>(device::Msg::identify), {}},
                       probe);
  device::FrameDecoder decoder;
  std::uint8_t buf[256];
  for (int attempt = 0; attempt < 200; ++attempt) {
    if (::write(fd, probe.data(), probe.size()) < 0 && errno != EAGAIN && errno != EINTR)
      failure("cannot write to the device at " + path + ": " + std::strerror(errno));
    const std::uint64_t until = monotonic_us() + 50000;
    for (std::uint64_t now = monotonic_us(); now < until; now = monotonic_us()) {
      pollfd pfd{fd, POLLIN, 0};
      if (poll(&pfd, 1, static_cast<int>((until - now) / 1000 + 1)) <= 0) continue;
      const ssize_t n = read(fd, buf, sizeof buf);
      if (n == 0) failure("the device at " + path + " closed its line");
      for (ssize_t i = 0; i < n; ++i)
        if (decoder.push(buf[i]) &&
            decoder.frame().type == static_cast<std::uint8_t>(device::Msg::ack))
          return;
    }
  }
  failure("the device at " + path + " did not answer within 10 s");
}

// stim-emu's device on a pseudo-terminal, in named steps: open the line, connect the
// forwarded device (if any), then turns of wait -> the device's replies -> the host's
// bytes (forwarded, or handled by the device core) until a signal, a fault or an error
// ends it; every end stops the output first (link_lost).
class PtyEmulator {
 public:
  explicit PtyEmulator(const PtyEmulatorOptions& opt)
      : opt_(opt),
        recorder_(opt.record_path, opt.skin),
        core_(emulator_capabilities(opt.caps, opt.skin)),
        rng_{opt.faults.seed} {
    if (!opt.apply_log_path.empty()) apply_log_.emplace(opt.apply_log_path, "--apply-log");
    if (!opt.event_log_path.empty()) event_log_.emplace(opt.event_log_path, "--event-log");
    reply_delay_us_ = static_cast<std::uint64_t>(std::llround(opt.faults.reply_delay_s * 1e6));
  }
  ~PtyEmulator() {
    if (device_fd_ >= 0) close(device_fd_);
    if (slave_ >= 0) close(slave_);
    if (master_ >= 0) close(master_);
  }
  PtyEmulator(const PtyEmulator&) = delete;
  PtyEmulator& operator=(const PtyEmulator&) = delete;

  int run() {
    open_line();
    install_signals();
    if (forward()) {
      device_fd_ = connect_device(opt_.forward_socket);
      await_device(device_fd_, opt_.forward_socket);
    }
    std::printf("%s\n", path_.c_str());
    std::fflush(stdout);
    t0_ = monotonic_us();
    try {
      while (!g_stop && turn()) {
      }
    } catch (const Error&) {
      // A record or log that cannot be written (a full disk): the output stops first, then
      // the emulator exits saying why.
      core_.link_lost();
      throw;
    }
    try {
      recorder_.advance(core_, monotonic_us());
    } catch (const Error&) {
      // The record's last pulses could not be written: said below.
    }
    core_.link_lost();  // output stops before the emulator goes
    if (recorder_.failed()) failure("--record: cannot write '" + opt_.record_path + "'");
    if (!forward() && recorder_.pulses() > 0)
      std::fprintf(stderr,
                   "stim-emu: %llu pulses delivered, each within %s ms of its time (%llu more "
                   "than 1 ms late)\n",
                   static_cast<unsigned long long>(recorder_.pulses()),
                   number_text(static_cast<double>(recorder_.latest_us()) * 1e-3).c_str(),
                   static_cast<unsigned long long>(recorder_.late()));
    return 0;
  }

 private:
  static constexpr std::size_t kMaxToDevice = 65536;

  bool forward() const { return !opt_.forward_socket.empty(); }

  // The pseudo-terminal; its slave kept open here in raw mode, so that the line behaves
  // like a serial port (no echo, no line editing) and reads on the master never fail while
  // no host is attached.
  void open_line() {
    master_ = posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0)
      failure(std::string("cannot open a pseudo-terminal: ") + std::strerror(errno));
    const char* name = ptsname(master_);
    if (!name) failure("ptsname failed");
    path_ = name;
    slave_ = open(path_.c_str(), O_RDWR | O_NOCTTY);
    if (slave_ < 0) failure("cannot open " + path_ + ": " + std::strerror(errno));
    termios tio{};
    tcgetattr(slave_, &tio);
    cfmakeraw(&tio);
    tcsetattr(slave_, TCSANOW, &tio);
    fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  }

  static void install_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
    std::signal(SIGPIPE, SIG_IGN);
  }

  // One turn: faults by the clock, the device's time, due replies, a wait, then what
  // arrived.  False: the emulator ends (a fault's disconnect, the device's line closed).
  bool turn() {
    const std::uint64_t now = monotonic_us();
    const double up_s = static_cast<double>(now - t0_) * 1e-6;
    if (opt_.faults.disconnect_after_s >= 0 && up_s >= opt_.faults.disconnect_after_s) {
      std::fprintf(stderr, "stim-emu: disconnecting (fault injection)\n");
      return false;
    }
    stalled_ = opt_.faults.stall_after_s >= 0 && up_s >= opt_.faults.stall_after_s &&
               up_s < opt_.faults.stall_after_s + opt_.faults.stall_s;
    recorder_.advance(core_, now);
    send_due(now);
    pollfd pfds[2];
    const int pr = wait(now, pfds);
    if (pr < 0) return errno == EINTR;
    if (forward()) {  // the host's waiting bytes are offered to the device at every turn
      if (pr > 0 && (pfds[1].revents & (POLLIN | POLLHUP | POLLERR)) && !take_device_replies())
        return false;
      if (pr > 0 && (pfds[0].revents & POLLIN)) take_host_bytes_forwarded();
      return write_to_device();
    }
    if (pr > 0 && (pfds[0].revents & POLLIN)) take_host_bytes();
    return true;
  }

  // Sleeps until the next pulse, watchdog deadline or reply, at most 5 ms.  Forwarding
  // never blocks: the host's bytes wait in to_device_ while the device's line is full, and
  // the host is not read while that holds 64 KiB (the device's replies are read all the
  // while: a device that cannot write its replies stops reading too).
  int wait(std::uint64_t now, pollfd (&pfds)[2]) {
    std::uint64_t next = forward() ? UINT64_MAX : core_.next_event_us();
    if (!replies_.empty()) next = std::min(next, replies_.front().first);
    // To the microsecond (ppoll), so that pulses are not late by poll's rounding up to a
    // millisecond; at most 5 ms.
    std::uint64_t wait_us = 5000;
    if (next != UINT64_MAX) wait_us = next <= now ? 0 : std::min<std::uint64_t>(next - now, 5000);
    const timespec timeout{0, static_cast<long>(wait_us * 1000)};
    const bool read_host = !stalled_ && (!forward() || to_device_.size() < kMaxToDevice);
    const short device_events =
        static_cast<short>(stalled_ ? 0 : (POLLIN | (to_device_.empty() ? 0 : POLLOUT)));
    pfds[0] = {master_, static_cast<short>(read_host ? POLLIN : 0), 0};
    pfds[1] = {device_fd_, device_events, 0};
    return ppoll(pfds, forward() ? 2 : 1, &timeout, nullptr);
  }

  // Replies whose time has come, oldest first.  A host that does not read fills the line:
  // the rest of a reply is lost (as on a UART), never waited for, so the device loop and
  // its watchdog keep running.
  void send_due(std::uint64_t now) {
    while (!replies_.empty() && replies_.front().first <= now) {
      const std::vector<std::uint8_t>& bytes = replies_.front().second;
      std::size_t off = 0;
      while (off < bytes.size()) {
        const ssize_t w = ::write(master_, bytes.data() + off, bytes.size() - off);
        if (w > 0)
          off += static_cast<std::size_t>(w);
        else if (w < 0 && errno == EINTR)
          continue;
        else
          break;
      }
      replies_.pop_front();
    }
  }

  // The forwarded device's replies, through the same faults and delay as the built-in
  // device's.  False: the device closed its line.
  bool take_device_replies() {
    const ssize_t n = read(device_fd_, in_.data(), in_.size());
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
      std::fprintf(stderr, "stim-emu: the device closed its line\n");
      return false;
    }
    if (n > 0) {
      std::vector<std::uint8_t> bytes(in_.begin(), in_.begin() + n);
      inject(bytes, opt_.faults, rng_);
      if (!bytes.empty()) replies_.emplace_back(monotonic_us() + reply_delay_us_, bytes);
      send_due(monotonic_us());
    }
    return true;
  }

  void take_host_bytes_forwarded() {
    const ssize_t n = read(master_, in_.data(), in_.size());
    if (n <= 0) return;
    std::vector<std::uint8_t> bytes(in_.begin(), in_.begin() + n);
    inject(bytes, opt_.faults, rng_);
    to_device_.insert(to_device_.end(), bytes.begin(), bytes.end());
  }

  // False: the device's line fails.
  bool write_to_device() {
    if (to_device_.empty() || stalled_) return true;
    const ssize_t w = ::write(device_fd_, to_device_.data(), to_device_.size());
    if (w > 0) {
      to_device_.erase(to_device_.begin(), to_device_.begin() + w);
    } else if (w < 0 && errno != EAGAIN && errno != EINTR) {
      std::fprintf(stderr, "stim-emu: cannot write to the device: %s\n", std::strerror(errno));
      return false;
    }
    return true;
  }

  // The built-in device: the host's bytes through the faults, into the device core, its
  // replies queued for their time; the logs told what changed.
  void take_host_bytes() {
    const ssize_t n = read(master_, in_.data(), in_.size());
    if (n <= 0) return;
    std::vector<std::uint8_t> bytes(in_.begin(), in_.begin() + n);
    inject(bytes, opt_.faults, rng_);
    out_.clear();
    const std::uint64_t t_rx = monotonic_us();
    recorder_.advance(core_, t_rx);
    core_.receive(bytes.data(), bytes.size(), t_rx, out_);
    log_events(t_rx);
    inject(out_, opt_.faults, rng_);
    if (!out_.empty()) replies_.emplace_back(t_rx + reply_delay_us_, out_);
    send_due(monotonic_us());
  }

  void log_events(std::uint64_t t_rx) {
    if (event_log_ && (core_.status().state == device::State::running) != running_) {
      running_ = !running_;
      timespec wall{};
      clock_gettime(CLOCK_REALTIME, &wall);
      event_log_->line(
          std::string(running_ ? "start " : "stop ") +
          std::to_string(static_cast<long long>(t_rx) * 1000) + " " +
          std::to_string(static_cast<long long>(wall.tv_sec) * 1000000000LL + wall.tv_nsec));
    }
    if (apply_log_) {
      const auto t = static_cast<long long>(monotonic_ns());
      for (; applied_ < core_.status().weight_updates; ++applied_)
        apply_log_->line(std::to_string(applied_ + 1) + " " + std::to_string(t));
    }
  }

  const PtyEmulatorOptions& opt_;
  PulseRecorder recorder_;
  std::optional<LineFile> apply_log_, event_log_;
  device::DeviceCore core_;
  SplitMix64 rng_;  // reproducible fault injection
  std::uint64_t reply_delay_us_ = 0;
  int master_ = -1, slave_ = -1, device_fd_ = -1;
  std::string path_;
  std::uint64_t t0_ = 0;
  bool stalled_ = false;
  bool running_ = false;  // as last logged
  std::uint32_t applied_ = 0;
  std::vector<std::uint8_t> in_ = std::vector<std::uint8_t>(4096), out_;
  std::vector<std::uint8_t> to_device_;  // forwarded bytes the device's line has not taken yet
  // Replies waiting for their time (fault injection: a slow device), oldest first.
  std::deque<std::pair<std::uint64_t, std::vector<std::uint8_t>>> replies_;
};

}  // namespace

int run_pty_emulator(const PtyEmulatorOptions& opt) { return PtyEmulator(opt).run(); }

}  // namespace tp::host
