#include "host/session.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include <poll.h>
#include <time.h>
#include <unistd.h>

#include "core/error.hpp"
#include "io/json.hpp"
#include "io/number.hpp"

namespace tp::host {
namespace {

std::uint16_t whole_us(double v, const char* what) {
  const double r = std::round(v);
  if (std::fabs(v - r) > 1e-6 || r < 0 || r > 65535)
    bad_input(std::string(what) + ": the device takes whole microseconds up to 65535, got " +
              number_text(v));
  return static_cast<std::uint16_t>(r);
}

// The host's limits narrowed to what the device says it can do.
StimulusLimits device_limits(StimulusLimits l, const device::Capabilities& c) {
  l.max_current_mA = std::min(l.max_current_mA, c.max_current_uA * 1e-3);
  l.min_width_us = std::max(l.min_width_us, static_cast<double>(c.min_width_us));
  l.max_width_us = std::min(l.max_width_us, static_cast<double>(c.max_width_us));
  l.max_balance_width_us =
      std::min(l.max_balance_width_us, static_cast<double>(c.max_balance_width_us));
  l.max_frequency_hz = std::min(l.max_frequency_hz, static_cast<double>(c.max_rate_hz));
  return l;
}

// Reads complete lines from a non-blocking descriptor; false at end of input.
class LineReader {
 public:
  explicit LineReader(int fd) : fd_(fd) {}
  bool poll_lines(int timeout_ms, std::vector<std::string>& lines) {
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, timeout_ms);
    if (r <= 0) return true;  // timeout or EINTR: nothing yet
    char buf[65536];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n < 0) return errno == EINTR || errno == EAGAIN;
    if (n == 0) {
      if (!pending_.empty()) lines.push_back(pending_);
      pending_.clear();
      return false;
    }
    pending_.append(buf, static_cast<std::size_t>(n));
    for (std::size_t pos; (pos = pending_.find('\n')) != std::string::npos;) {
      lines.push_back(pending_.substr(0, pos));
      pending_.erase(0, pos + 1);
    }
    return true;
  }

 private:
  int fd_;
  std::string pending_;
};

// One live frame: {"currents_mA": [...]}, checked like the stimulus itself.
std::vector<std::int16_t> live_frame(const std::string& line, std::size_t n_line, Stimulus shape_of,
                                     const StimulusLimits& lim, const device::Capabilities& caps) {
  const std::string where = "input line " + std::to_string(n_line);
  Json j;
  try {
    j = Json::parse(line);
  } catch (const std::exception&) {
    bad_input(where + ": malformed JSON");
  }
  if (!j.is_object() || !j.contains("currents_mA") || !j["currents_mA"].is_array())
    bad_input(where + ": expected {\"currents_mA\": [...]}");
  std::vector<double> c;
  for (std::size_t i = 0; i < j["currents_mA"].size(); ++i)
    c.push_back(
        json_finite(j["currents_mA"][i], where + " currents_mA[" + std::to_string(i) + "]"));
  if (c.size() != shape_of.currents_mA.size())
    bad_input(where + ": " + std::to_string(c.size()) + " currents for " +
              std::to_string(shape_of.currents_mA.size()) + " channels");
  shape_of.currents_mA = c;
  try {
    check_stimulus(shape_of, lim);
  } catch (const Error& e) {
    bad_input(where + ": " + e.what());
  }
  return quantize_currents(c, caps);
}

std::int64_t now_ns() {
  return monotonic_ns();
}

}  // namespace

SessionReport run_session(Transport& transport, const Stimulus& s, const SessionOptions& opt,
                          const volatile std::sig_atomic_t* signal_flag) {
  StimulatorClient dev(transport);
  SessionReport rep;
  rep.port = transport.name();

  // 1. What is on the line, and does the stimulus fit it?  Nothing but identify is sent
  //    before every check has passed.
  rep.caps = dev.identify();
  if (s.currents_mA.size() > rep.caps.channels)
    bad_input("stimulus has " + std::to_string(s.currents_mA.size()) +
              " channels; the device has " + std::to_string(rep.caps.channels));
  const StimulusLimits lim = device_limits(opt.limits, rep.caps);
  check_stimulus(s, lim);
  Stimulus run = s;
  if (opt.duration_s >= 0) {
    if (!(opt.duration_s > 0) || !std::isfinite(opt.duration_s))
      bad_input("--duration: must be > 0 s");
    run.count = std::min<long>(s.count, std::lround(opt.duration_s * s.shape.frequency_hz));
    if (opt.live) run.count = std::lround(opt.duration_s * s.shape.frequency_hz);
    if (run.count < 1) bad_input("--duration: shorter than one pulse period");
  }
  device::PulseConfig cfg;
  cfg.width_us = whole_us(s.shape.width_us, "pulse width");
  cfg.interphase_us = whole_us(s.shape.interphase_us, "interphase gap");
  cfg.balance_width_us = whole_us(s.shape.balance_width_us, "balance width");
  // The device counts whole microseconds: the period is rounded (150 Hz: 6667 us, 149.993 Hz).
  cfg.period_us = static_cast<std::uint32_t>(std::lround(s.shape.period_us()));
  cfg.channels = static_cast<std::uint8_t>(s.currents_mA.size());
  // The device stops itself after the stimulus' pulses (live mode without --duration: open-ended).
  cfg.max_pulses = opt.live && opt.duration_s < 0 ? 0u : static_cast<std::uint32_t>(run.count);
  const std::vector<std::int16_t> codes = quantize_currents(s.currents_mA, rep.caps);

  // 2. Configure, set the weights, start; from here on every exit stops the output.
  dev.configure(cfg);
  dev.set_weights(codes);
  std::FILE* latency = nullptr;
  if (opt.live && !opt.latency_log.empty()) {
    latency = std::fopen(opt.latency_log.c_str(), "w");
    if (!latency) bad_input("--latency-log: cannot open '" + opt.latency_log + "'");
  }
  const std::int64_t t0 = now_ns();
  bool started = false;
  try {
    dev.start();
    started = true;
    const double expected_s = run.duration_s();
    LineReader input(opt.input_fd);
    std::size_t n_line = 0;
    std::int64_t last_keepalive = now_ns();
    while (true) {
      if (signal_flag && *signal_flag) {
        rep.end = *signal_flag == SIGINT    ? "interrupted (SIGINT)"
                  : *signal_flag == SIGTERM ? "terminated (SIGTERM)"
                                            : "signal";
        rep.exit_code = 128 + *signal_flag;
        break;
      }
      const double elapsed = static_cast<double>(now_ns() - t0) * 1e-9;
      if (cfg.max_pulses != 0 && elapsed > expected_s + 1.0)
        failure("device did not complete the stimulus in time");
      if (opt.live) {
        std::vector<std::string> lines;
        const bool more = input.poll_lines(kKeepAliveMs, lines);
        for (const std::string& line : lines) {
          ++n_line;
          if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
          const auto frame = live_frame(line, n_line, s, lim, rep.caps);
          dev.set_weights(frame);
          ++rep.weight_frames;
          if (latency)
            std::fprintf(latency, "%u %lld\n", rep.weight_frames,
                         static_cast<long long>(dev.last_write_ns()));
          last_keepalive = now_ns();  // every acknowledged frame feeds the watchdog
        }
        if (!more) {
          rep.end = "end of input";
          break;
        }
      } else {
        timespec ts{0, kKeepAliveMs * 1000000L};
        nanosleep(&ts, nullptr);
      }
      const bool keepalive_due = now_ns() - last_keepalive >= std::int64_t{kKeepAliveMs} * 1000000;
      const bool should_be_done = cfg.max_pulses != 0 && elapsed >= expected_s;
      if (keepalive_due || should_be_done) {
        const device::Status st = dev.status();  // doubles as the keep-alive
        last_keepalive = now_ns();
        if (st.state == device::State::idle) {
          if (st.fault == device::Fault::completed) {
            rep.end = "stimulus complete";
            break;
          }
          failure(std::string("device stopped the output: ") + device::to_string(st.fault));
        }
      }
    }
    dev.stop();
  } catch (...) {
    if (latency) std::fclose(latency);
    if (started) {
      try {
        dev.stop();
      } catch (...) {
        // The device is unreachable; its watchdog stops the output.
      }
    }
    throw;
  }
  if (latency) std::fclose(latency);
  const device::Status st = dev.status();
  rep.pulses = st.pulses;
  rep.seconds = static_cast<double>(now_ns() - t0) * 1e-9;
  rep.retransmissions = dev.retransmissions();
  return rep;
}

}  // namespace tp::host
