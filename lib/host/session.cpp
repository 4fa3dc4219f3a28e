#include "host/session.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include <time.h>

#include "core/error.hpp"
#include "host/line_reader.hpp"
#include "host/signals.hpp"
#include "io/json.hpp"
#include "io/number.hpp"

namespace tp::host {
namespace {

std::uint16_t whole_us(double v, const char* what) {
  if (!(v >= 0.0 && v <= 65535.0))  // range first: the conversion below cannot wrap
    bad_input(std::string(what) + ": the device takes whole microseconds up to 65535, got " +
              number_text(v));
  const double r = std::round(v);
  if (std::fabs(v - r) > 1e-6)
    bad_input(std::string(what) + ": the device takes whole microseconds, got " + number_text(v));
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
  l.max_rms_current_mA = std::min(l.max_rms_current_mA, c.max_rms_uA * 1e-3);
  l.max_mean_current_mA = std::min(l.max_mean_current_mA, c.max_mean_uA * 1e-3);
  l.min_gap_us = std::max(l.min_gap_us, static_cast<double>(c.min_gap_us));
  l.max_slip_us = std::min(l.max_slip_us, static_cast<double>(c.max_slip_us));
  return l;
}

// A pattern's pulse count: its own, cut by --duration; in live mode --duration's (or the
// duration limit's).  In double first (bounded by the duration limit and the rate limit),
// so that the conversion to the device's 32-bit count cannot wrap.
double pulse_count(const Stimulus& p, const SessionOptions& opt, const StimulusLimits& lim,
                   const char* too_short) {
  const double max_s = opt.limits.max_duration_s;
  const double f = p.shape.frequency_hz;
  double n = static_cast<double>(p.count);
  if (opt.live)
    n = std::floor((opt.duration_s > 0 ? opt.duration_s : max_s) * f + 0.5);
  else if (opt.duration_s > 0)
    n = std::min(n, std::floor(opt.duration_s * f + 0.5));
  if (n < 1) bad_input(too_short);
  if (!(n <= max_s * lim.max_frequency_hz + 1))
    bad_input("stimulus: " + number_text(n) + " pulses exceed the duration limit");
  return n;
}

// The device's own check of the codes it is sent (device::ChannelLoad, in integers): each
// electrode's RMS and mean current, summed over the patterns, as the DAC makes them.  The
// host's check in mA (check_stimulus, check_mix) can pass a current the codes' rounding
// puts just over a bound; this one refuses it before anything is sent.
void check_load(const device::ChannelLoad& load, const device::Capabilities& caps,
                const std::string& where) {
  const std::size_t i = load.first_over(caps);
  if (i == device::kMaxChannels) return;
  bad_input(where + "electrode " + std::to_string(i) + ": RMS " +
            number_text(load.rms_mA(i, caps.dac_step_nA)) + " mA, mean " +
            number_text(load.mean_mA(i, caps.dac_step_nA)) +
            " mA, as the DAC makes them: above the device's bounds of " +
            number_text(caps.max_rms_uA * 1e-3) + " mA RMS and " +
            number_text(caps.max_mean_uA * 1e-3) + " mA mean (docs/safety.md)");
}

}  // namespace

double current_limit_mA(const Stimulus& s, const StimulusLimits& lim) {
  return std::min(s.max_current_mA, lim.max_current_mA);
}

std::vector<std::int16_t> parse_live_frame(const std::string& line, std::size_t n_line,
                                           const Stimulus& s, const StimulusLimits& lim,
                                           const device::Capabilities& caps) {
  Stimulus shape_of = s;
  const std::string where = "input line " + std::to_string(n_line);
  Json j;
  try {
    j = parse_json_strict(line, where);
  } catch (const nlohmann::json::exception&) {
    bad_input(where + ": malformed JSON");
  }
  if (!j.is_object() || !j.contains("currents_mA") || !j["currents_mA"].is_array())
    bad_input(where + ": expected {\"currents_mA\": [...]}");
  const Json& list = j["currents_mA"];
  if (list.size() != shape_of.currents_mA.size())
    bad_input(where + ": " + std::to_string(list.size()) + " currents for " +
              std::to_string(shape_of.currents_mA.size()) + " channels");
  std::vector<double> c;
  for (std::size_t i = 0; i < list.size(); ++i)
    c.push_back(json_finite(list[i], where + " currents_mA[" + std::to_string(i) + "]"));
  shape_of.currents_mA = c;
  try {
    check_stimulus(shape_of, lim);
    auto codes = quantize_currents(c, caps, current_limit_mA(s, lim));
    device::ChannelLoad load;
    device::add_dense(load, codes, pattern_timing(s, 0));
    check_load(load, caps, "");
    return codes;
  } catch (const Error& e) {
    bad_input(where + ": " + e.what());
  }
}

namespace {

double peak_of(const std::vector<std::int16_t>& codes, const device::Capabilities& caps) {
  int m = 0;
  for (std::int16_t c : codes) m = std::max(m, std::abs(int{c}));
  return m * caps.dac_step_nA * 1e-6;
}

std::string end_by_signal(int sig) {
  if (sig == SIGINT) return "interrupted (SIGINT)";
  if (sig == SIGTERM) return "terminated (SIGTERM)";
  return "stopped by " + signal_name(sig);
}

}  // namespace

void check_device(const device::Capabilities& caps) {
  if (caps.watchdog_ms > kMaxDeviceWatchdogMs)
    bad_input("device watchdog of " + std::to_string(caps.watchdog_ms) +
              " ms is longer than the host's safety bound of " +
              std::to_string(kMaxDeviceWatchdogMs) + " ms: a dead host's output would run on");
  if (caps.watchdog_ms < kMinDeviceWatchdogMs)
    bad_input("device watchdog of " + std::to_string(caps.watchdog_ms) +
              " ms is shorter than two keep-alive periods (" +
              std::to_string(kMinDeviceWatchdogMs) + " ms at one per " +
              std::to_string(kKeepAliveMs) + " ms)");
  if (caps.channels > device::kMaxChannels)
    bad_input("device reports " + std::to_string(caps.channels) +
              " channels; the protocol carries at most " + std::to_string(device::kMaxChannels));
}

SessionReport run_session(Transport& transport, const Stimulus& s, const SessionOptions& opt,
                          const volatile std::sig_atomic_t* signal_flag) {
  Mix m;
  m.patterns.push_back(s);
  return run_session(transport, m, opt, signal_flag);
}

SessionReport run_session(Transport& transport, const Mix& m, const SessionOptions& opt,
                          const volatile std::sig_atomic_t* signal_flag) {
  if (m.patterns.empty()) bad_input("stimulus: no patterns");
  const Stimulus& s = m.patterns[0];
  const bool table = m.table();
  StimulatorClient dev(transport);
  SessionReport rep;
  rep.port = transport.name();
  auto interrupted = [&] { return signal_flag && *signal_flag != 0; };
  auto end_by_flag = [&] {
    rep.end = end_by_signal(*signal_flag);
    rep.exit_code = 128 + *signal_flag;
  };

  // 1. Every check before anything but identify is sent: the stimulus, its duration, the
  //    device's capabilities, and the stimulus against them.
  if (s.currents_mA.size() > device::kMaxChannels)
    bad_input("stimulus has " + std::to_string(s.currents_mA.size()) +
              " channels; the protocol carries at most " + std::to_string(device::kMaxChannels));
  const double max_s = opt.limits.max_duration_s;
  if (opt.duration_s >= 0 && !(opt.duration_s > 0 && opt.duration_s <= max_s))
    bad_input("--duration: " + number_beside(opt.duration_s, 0, max_s) + " s outside (0, " +
              number_text(max_s) + "] s");
  if (interrupted()) {
    end_by_flag();
    return rep;
  }
  rep.caps = dev.identify();
  check_device(rep.caps);
  if (s.currents_mA.size() > rep.caps.channels)
    bad_input("stimulus has " + std::to_string(s.currents_mA.size()) +
              " channels; the device has " + std::to_string(rep.caps.channels));
  const StimulusLimits lim = device_limits(opt.limits, rep.caps);
  check_mix(m, lim);
  const double count = pulse_count(s, opt, lim, "--duration: shorter than one pulse period");
  device::PulseConfig cfg;
  cfg.width_us = whole_us(s.shape.width_us, "pulse width");
  cfg.interphase_us = whole_us(s.shape.interphase_us, "interphase gap");
  cfg.balance_width_us = whole_us(s.shape.balance_width_us, "balance width");
  // The device counts whole microseconds: the period is rounded (150 Hz: 6667 us, 149.993 Hz).
  const double period = std::round(s.shape.period_us());
  if (!(period >= 1 && period <= device::hard::max_period_us))
    bad_input("pulse period of " + number_text(period) + " us outside the protocol's 1 us to " +
              std::to_string(device::hard::max_period_us / 1000000) + " s");
  cfg.period_us = static_cast<std::uint32_t>(period);
  // The rounded period must still hold the pulse and respect the device's rate.
  const double length_us =
      static_cast<double>(cfg.width_us + cfg.interphase_us + cfg.balance_width_us);
  if (!(period > length_us))
    bad_input("pulse of " + number_text(length_us) + " us does not fit the device's period of " +
              number_text(period) + " us (" + number_text(s.shape.frequency_hz) +
              " Hz rounded to whole microseconds)");
  if (period < std::ceil(1e6 / rep.caps.max_rate_hz))
    bad_input("period of " + number_text(period) + " us is faster than the device's " +
              std::to_string(rep.caps.max_rate_hz) + " Hz");
  // The device's timing rule (device::phase_fits): a gap, and the off time between
  // pulses, each at least its shortest phase, in which it loads the next phase's codes.
  if (cfg.interphase_us != 0 && cfg.interphase_us < rep.caps.min_width_us)
    bad_input("interphase gap of " + std::to_string(cfg.interphase_us) +
              " us is shorter than the device's shortest phase of " +
              std::to_string(rep.caps.min_width_us) + " us (0 for no gap)");
  if (period - length_us < rep.caps.min_width_us)
    bad_input("off time of " + number_text(period - length_us) + " us between pulses (period " +
              number_text(period) + " us, pulse " + number_text(length_us) +
              " us) is shorter than the device's shortest phase of " +
              std::to_string(rep.caps.min_width_us) + " us");
  cfg.channels = static_cast<std::uint8_t>(s.currents_mA.size());
  // The device always has a pulse budget: it stops by itself after the stimulus' pulses
  // (live mode: --duration, or the duration limit), whatever becomes of the host.
  cfg.max_pulses = static_cast<std::uint32_t>(count);
  // No code above the limit in force (the stimulus's, the host's, the device's).
  const std::vector<std::int16_t> codes =
      quantize_currents(s.currents_mA, rep.caps, current_limit_mA(s, lim));
  // A table: each pattern's timing (its own count) and codes, checked as the device will.
  std::vector<device::PatternTiming> timings;
  std::vector<std::vector<std::int16_t>> table_codes;
  double table_s = 0;
  if (table) {
    if (m.patterns.size() > rep.caps.max_patterns)
      bad_input("stimulus has " + std::to_string(m.patterns.size()) +
                " patterns; the device holds " + std::to_string(rep.caps.max_patterns));
    const double least_gap = std::max(rep.caps.min_gap_us, rep.caps.min_width_us);
    if (m.gap_us < least_gap)
      bad_input("gap_us: " + number_beside(m.gap_us, least_gap) +
                " us, below the device's least gap of " + number_text(least_gap) + " us");
    device::ChannelLoad load;
    std::size_t entries = 0;
    for (const Stimulus& p : m.patterns) {
      const double n_p =
          pulse_count(p, opt, lim, "--duration: shorter than one period of a pattern");
      timings.push_back(pattern_timing(p, static_cast<long>(n_p)));
      const device::PatternTiming& t = timings.back();
      if (t.period_us < std::ceil(1e6 / rep.caps.max_rate_hz) || !device::phase_fits(t, rep.caps))
        bad_input("pattern " + std::to_string(timings.size() - 1) +
                  ": its period, gap or off time is outside the device's timing (" +
                  std::to_string(rep.caps.max_rate_hz) + " Hz, shortest phase " +
                  std::to_string(rep.caps.min_width_us) + " us)");
      table_codes.push_back(quantize_currents(p.currents_mA, rep.caps, current_limit_mA(p, lim)));
      for (std::int16_t c : table_codes.back()) entries += c != 0;
      device::add_dense(load, table_codes.back(), t);
      table_s = std::max(table_s, (t.phase_us + (t.max_pulses + 0.0) * t.period_us) * 1e-6);
    }
    if (entries > rep.caps.code_pool)
      bad_input("the patterns have " + std::to_string(entries) +
                " non-zero codes; the device holds " + std::to_string(rep.caps.code_pool));
    check_load(load, rep.caps, "summed over the patterns: ");
  } else {
    device::ChannelLoad load;
    device::add_dense(load, codes, pattern_timing(s, 0));
    check_load(load, rep.caps, "");
  }
  // At the device's (rounded) periods; a table's pulses may come up to 1 ms late.
  const double expected_s = table ? table_s + 0.001 : count * period * 1e-6;

  std::FILE* latency = nullptr;
  if (opt.live && !opt.latency_log.empty()) {
    latency = std::fopen(opt.latency_log.c_str(), "w");
    if (!latency) bad_input("--latency-log: cannot open '" + opt.latency_log + "'");
  }
  struct CloseLog {
    std::FILE*& f;
    ~CloseLog() {
      if (f) std::fclose(f);
    }
  } close_log{latency};

  // 2. A device still running is another host's output (the port is ours alone): stop it.
  //    Then configure a session of our own, set the weights, start.  The stop flag is
  //    checked before every step that leads to output.
  std::int64_t t0 = monotonic_ns();  // from the start, once started (a table's upload aside)
  bool configured = false;
  try {
    if (interrupted()) {
      end_by_flag();
      return rep;
    }
    if (dev.status().state == device::State::running) {
      dev.stop();
      rep.preempted = true;
    }
    // A table: configure, each pattern's timing and codes, its starting amplitudes (when
    // the document gives them: after the codes, which reset them), start.
    const int uploads = 2 * static_cast<int>(m.patterns.size());
    const bool start_scales = table && !m.start_amplitudes_mA.empty();
    const int steps = table ? 2 + uploads + (start_scales ? 1 : 0) : 3;
    for (int step = 0; step < steps; ++step) {
      if (interrupted()) break;
      if (step == 0 && table) {
        dev.configure_table(static_cast<std::uint16_t>(m.patterns.size()),
                            static_cast<std::uint8_t>(s.currents_mA.size()),
                            static_cast<std::uint16_t>(std::lround(m.gap_us)));
        configured = true;
      } else if (step == 0) {
        dev.configure(cfg);
        configured = true;
      } else if (table && step <= uploads) {
        const auto i = static_cast<std::uint16_t>((step - 1) / 2);
        if ((step - 1) % 2 == 0) {
          dev.set_pattern(i, timings[i]);
        } else {
          dev.set_codes(i, table_codes[i]);
          rep.peak_mA = std::max(rep.peak_mA, peak_of(table_codes[i], rep.caps));
        }
      } else if (start_scales && step == uploads + 1) {
        dev.set_amplitudes(
            parse_amplitudes({{"amplitudes", m.start_amplitudes_mA}}, m, "start_amplitudes_mA"));
      } else if (step == 1) {
        dev.set_weights(codes);
        rep.peak_mA = peak_of(codes, rep.caps);
      } else {
        dev.start();
        rep.started = true;
        t0 = monotonic_ns();
      }
    }
    if (!rep.started) {
      end_by_flag();
      dev.stop();  // disarm the session we opened
      return rep;
    }

    // 3. Keep the session alive until the run ends.
    LineReader input(opt.input_fd);
    std::int64_t last_keepalive = monotonic_ns();
    const std::int64_t period_ns = std::int64_t{kKeepAliveMs} * 1000000;
    std::string line;
    while (true) {
      if (interrupted()) {
        end_by_flag();
        break;
      }
      const std::int64_t now = monotonic_ns();
      const double elapsed = static_cast<double>(now - t0) * 1e-9;
      if (elapsed > expected_s + 1.0) failure("device did not complete the stimulus in time");
      const std::int64_t wait_ns = std::max<std::int64_t>(0, last_keepalive + period_ns - now);
      if (opt.live) {
        // One line per turn, so a flood of input never delays the keep-alive below.
        if (input.next(line)) {
          if (line.find_first_not_of(" \t\r") != std::string::npos) {
            const std::string where = "input line " + std::to_string(input.lines());
            if (line.find("\"amplitudes\"") != std::string::npos || table) {
              Json j;
              try {
                j = parse_json_strict(line, where);
              } catch (const nlohmann::json::exception&) {
                bad_input(where + ": malformed JSON");
              }
              if (table && !(j.is_object() && j.contains("amplitudes")))
                bad_input(where + ": a mix takes {\"amplitudes\": [...]}, one per pattern");
              dev.set_amplitudes(parse_amplitudes(j, m, where));
            } else {
              const auto frame = parse_live_frame(line, input.lines(), s, lim, rep.caps);
              dev.set_weights(frame);
              rep.peak_mA = std::max(rep.peak_mA, peak_of(frame, rep.caps));
            }
            ++rep.weight_frames;
            if (latency)
              std::fprintf(latency, "%u %lld\n", rep.weight_frames,
                           static_cast<long long>(dev.last_write_ns()));
          }
        } else if (input.at_end()) {
          rep.end = "end of input";
          break;
        } else {
          input.fill(static_cast<int>((wait_ns + 999999) / 1000000));
        }
      } else {
        timespec ts{0, static_cast<long>(wait_ns)};
        nanosleep(&ts, nullptr);
      }
      const std::int64_t after = monotonic_ns();
      const bool keepalive_due = after - last_keepalive >= period_ns;
      const bool should_be_done = static_cast<double>(after - t0) * 1e-9 >= expected_s;
      if (keepalive_due || should_be_done) {
        const device::Status st = dev.keepalive();
        last_keepalive = monotonic_ns();
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
    if (configured) {
      try {
        dev.stop();
      } catch (...) {
        // The device is unreachable; its watchdog stops the output.
      }
    }
    throw;
  }
  const device::Status st = dev.status();
  rep.pulses = st.pulses;
  rep.seconds = static_cast<double>(monotonic_ns() - t0) * 1e-9;
  rep.retransmissions = dev.retransmissions();
  rep.rx_errors = st.rx_errors;
  rep.line_errors = st.line_errors;
  rep.overruns = st.overruns;
  return rep;
}

}  // namespace tp::host
