#include "host/emulator.hpp"

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <deque>
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
#include "io/number.hpp"

namespace tp::host {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}
std::uint64_t monotonic_us() {
  return static_cast<std::uint64_t>(monotonic_ns() / 1000);
}

PulseRecorder::PulseRecorder(const std::string& path) {
  if (!path.empty()) out_.emplace(path, "--record");
}

void PulseRecorder::record(const device::DeliveredPulse& p) {
  ++pulses_;
  const double step_mA = p.caps.dac_step_nA * 1e-6;
  for (std::int16_t c : p.codes) peak_mA_ = std::max(peak_mA_, std::fabs(c * step_mA));
  if (!out_ || failed_) return;
  // The device's own record (lib/device/pulse_record.hpp), as the firmware's monitor
  // writes it: the balancing phase in whole DAC codes.
  device::PulseRecord r;
  r.pattern = p.pattern;
  r.t_us = p.t_us - p.start_us;
  r.slip_us = p.slip_us;
  r.channels = static_cast<std::uint8_t>(p.codes.size());
  std::copy(p.codes.begin(), p.codes.end(), r.main);
  device::balance_codes(p.codes, p.timing.width_us, p.timing.balance_width_us, r.balance);
  r.step_nA = p.caps.dac_step_nA;
  r.width_us = p.timing.width_us;
  r.interphase_us = p.timing.interphase_us;
  r.balance_width_us = p.timing.balance_width_us;
  char line[device::kMaxRecordLine];
  const std::size_t n = device::format_record(r, line);
  try {
    out_->write(line, n);
  } catch (const Error&) {
    failed_ = true;
    throw;
  }
}

// ---------------------------------------------------------------------------------------
// In-process emulator: the device core behind an in-memory link.  Replies are produced
// synchronously on write; pulses are delivered (recorded) whenever the host touches the
// link, each with its scheduled time.

namespace {

class LoopbackTransport final : public Transport {
 public:
  explicit LoopbackTransport(const EmulatorOptions& o) : core_(o.caps), recorder_(o.record_path) {}
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
      core_.advance(monotonic_us(),
                    [this](const device::DeliveredPulse& p) { recorder_.record(p); });
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

}  // namespace

int run_pty_emulator(const PtyEmulatorOptions& opt) {
  PulseRecorder recorder(opt.record_path);
  std::optional<LineFile> apply_log, event_log;
  if (!opt.apply_log_path.empty()) apply_log.emplace(opt.apply_log_path, "--apply-log");
  if (!opt.event_log_path.empty()) event_log.emplace(opt.event_log_path, "--event-log");
  bool running = false;  // as last logged
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0)
    failure(std::string("cannot open a pseudo-terminal: ") + std::strerror(errno));
  const char* name = ptsname(master);
  if (!name) failure("ptsname failed");
  const std::string path = name;
  // Keep the slave open ourselves, in raw mode: the line then behaves like a serial port
  // (no echo, no line editing) and reads on the master never fail while no host is attached.
  const int slave = open(path.c_str(), O_RDWR | O_NOCTTY);
  if (slave < 0) failure("cannot open " + path + ": " + std::strerror(errno));
  termios tio{};
  tcgetattr(slave, &tio);
  cfmakeraw(&tio);
  tcsetattr(slave, TCSANOW, &tio);
  fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  const bool forward = !opt.forward_socket.empty();
  const int device_fd = forward ? connect_device(opt.forward_socket) : -1;
  std::vector<std::uint8_t> to_device;  // forwarded bytes the device's line has not taken yet
  constexpr std::size_t kMaxToDevice = 65536;
  if (forward) await_device(device_fd, opt.forward_socket);

  std::printf("%s\n", path.c_str());
  std::fflush(stdout);

  device::DeviceCore core(opt.caps);
  SplitMix64 rng{opt.faults.seed};  // reproducible fault injection
  const std::uint64_t t0 = monotonic_us();
  std::uint32_t applied = 0;
  auto sink = [&](const device::DeliveredPulse& p) { recorder.record(p); };
  std::vector<std::uint8_t> in(4096), out;
  // Replies waiting for their time (fault injection: a slow device), oldest first.
  std::deque<std::pair<std::uint64_t, std::vector<std::uint8_t>>> replies;
  const auto reply_delay_us =
      static_cast<std::uint64_t>(std::llround(opt.faults.reply_delay_s * 1e6));
  auto send_due = [&](std::uint64_t now) {
    while (!replies.empty() && replies.front().first <= now) {
      const std::vector<std::uint8_t>& bytes = replies.front().second;
      std::size_t off = 0;
      // A host that does not read fills the line: the rest of the reply is lost (as on a
      // UART), never waited for, so the device loop and its watchdog keep running.
      while (off < bytes.size()) {
        const ssize_t w = ::write(master, bytes.data() + off, bytes.size() - off);
        if (w > 0)
          off += static_cast<std::size_t>(w);
        else if (w < 0 && errno == EINTR)
          continue;
        else
          break;
      }
      replies.pop_front();
    }
  };
  int status = 0;
  try {
    while (!g_stop) {
      const std::uint64_t now = monotonic_us();
      const double up_s = static_cast<double>(now - t0) * 1e-6;
      if (opt.faults.disconnect_after_s >= 0 && up_s >= opt.faults.disconnect_after_s) {
        std::fprintf(stderr, "stim-emu: disconnecting (fault injection)\n");
        break;
      }
      const bool stalled = opt.faults.stall_after_s >= 0 && up_s >= opt.faults.stall_after_s &&
                           up_s < opt.faults.stall_after_s + opt.faults.stall_s;
      core.advance(now, sink);
      send_due(now);
      // Sleep until the next pulse, watchdog deadline or reply, at most 5 ms.
      std::uint64_t next = forward ? UINT64_MAX : core.next_event_us();
      if (!replies.empty()) next = std::min(next, replies.front().first);
      int timeout_ms = 5;
      if (next != UINT64_MAX)
        timeout_ms = next <= now
                         ? 0
                         : static_cast<int>(std::min<std::uint64_t>((next - now + 999) / 1000, 5));
      // Forwarding never blocks: the host's bytes wait in to_device while the device's line
      // is full, and the host is not read while that holds 64 KiB (the device's replies are
      // read all the while: a device that cannot write its replies stops reading too).
      const bool read_host = !stalled && (!forward || to_device.size() < kMaxToDevice);
      const short device_events =
          static_cast<short>(stalled ? 0 : (POLLIN | (to_device.empty() ? 0 : POLLOUT)));
      pollfd pfds[2] = {{master, static_cast<short>(read_host ? POLLIN : 0), 0},
                        {device_fd, device_events, 0}};
      const int pr = poll(pfds, forward ? 2 : 1, timeout_ms);
      if (pr < 0 && errno != EINTR) break;
      pollfd& pfd = pfds[0];
      if (forward && pr > 0 && (pfds[1].revents & (POLLIN | POLLHUP | POLLERR))) {
        // The device's replies: through the same faults and delay as the built-in device's.
        const ssize_t n = read(device_fd, in.data(), in.size());
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
          std::fprintf(stderr, "stim-emu: the device closed its line\n");
          break;
        }
        if (n > 0) {
          std::vector<std::uint8_t> bytes(in.begin(), in.begin() + n);
          inject(bytes, opt.faults, rng);
          if (!bytes.empty()) replies.emplace_back(monotonic_us() + reply_delay_us, bytes);
          send_due(monotonic_us());
        }
      }
      if (forward && pr > 0 && (pfd.revents & POLLIN)) {
        const ssize_t n = read(master, in.data(), in.size());
        if (n > 0) {
          std::vector<std::uint8_t> bytes(in.begin(), in.begin() + n);
          inject(bytes, opt.faults, rng);
          to_device.insert(to_device.end(), bytes.begin(), bytes.end());
        }
      }
      if (forward && !to_device.empty() && !stalled) {
        const ssize_t w = ::write(device_fd, to_device.data(), to_device.size());
        if (w > 0) {
          to_device.erase(to_device.begin(), to_device.begin() + w);
        } else if (w < 0 && errno != EAGAIN && errno != EINTR) {
          std::fprintf(stderr, "stim-emu: cannot write to the device: %s\n", std::strerror(errno));
          break;
        }
      }
      if (!forward && pr > 0 && (pfd.revents & POLLIN)) {
        const ssize_t n = read(master, in.data(), in.size());
        if (n > 0) {
          std::vector<std::uint8_t> bytes(in.begin(), in.begin() + n);
          inject(bytes, opt.faults, rng);
          out.clear();
          const std::uint64_t t_rx = monotonic_us();
          core.advance(t_rx, sink);
          core.receive(bytes.data(), bytes.size(), t_rx, out);
          if (event_log && (core.status().state == device::State::running) != running) {
            running = !running;
            timespec wall{};
            clock_gettime(CLOCK_REALTIME, &wall);
            event_log->line(
                std::string(running ? "start " : "stop ") +
                std::to_string(static_cast<long long>(t_rx) * 1000) + " " +
                std::to_string(static_cast<long long>(wall.tv_sec) * 1000000000LL + wall.tv_nsec));
          }
          if (apply_log) {
            const auto t = static_cast<long long>(monotonic_ns());
            for (; applied < core.status().weight_updates; ++applied)
              apply_log->line(std::to_string(applied + 1) + " " + std::to_string(t));
          }
          inject(out, opt.faults, rng);
          if (!out.empty()) replies.emplace_back(t_rx + reply_delay_us, out);
          send_due(monotonic_us());
        }
      }
    }
  } catch (const Error&) {
    // A record or log that cannot be written (a full disk): the output stops first, then
    // the emulator exits saying why.
    core.link_lost();
    if (device_fd >= 0) close(device_fd);
    close(slave);
    close(master);
    throw;
  }
  try {
    core.advance(monotonic_us(), sink);
  } catch (const Error&) {
    // The record's last pulses could not be written: said below.
  }
  core.link_lost();  // output stops before the emulator goes
  if (recorder.failed()) failure("--record: cannot write '" + opt.record_path + "'");
  if (device_fd >= 0) close(device_fd);
  close(slave);
  close(master);
  return status;
}

}  // namespace tp::host
