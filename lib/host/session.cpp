#include "host/session.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <time.h>

#include "core/error.hpp"
#include "host/hold.hpp"
#include "host/line_reader.hpp"
#include "host/live.hpp"
#include "host/signals.hpp"
#include "core/files.hpp"
#include "core/json.hpp"
#include "core/number.hpp"

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

// What needs no device: patterns, the protocol's channels, the duration.
void check_request(const Mix& m, const SessionOptions& opt) {
  if (m.patterns.empty()) bad_input("stimulus: no patterns");
  const std::size_t channels = m.patterns[0].currents_mA.size();
  if (channels > device::kMaxChannels)
    bad_input("stimulus has " + std::to_string(channels) +
              " channels; the protocol carries at most " + std::to_string(device::kMaxChannels));
  const double max_s = opt.limits.max_duration_s;
  if (opt.duration_s >= 0 && !(opt.duration_s > 0 && opt.duration_s <= max_s))
    bad_input("--duration: " + number_beside(opt.duration_s, 0, max_s) + " s outside (0, " +
              number_text(max_s) + "] s");
  if (opt.live && !opt.frames)
    throw Error(ExitCode::failure, "live session without a frame source (SessionOptions::frames)");
  if (opt.live && opt.hold_sensation)
    bad_input("--hold-sensation: not with --live (a live frame's currents would leave the held "
              "energy behind)");
}

// A single stimulus's configuration (protocol 1 to 3), checked against the device's timing.
device::PulseConfig single_config(const Stimulus& s, const device::Capabilities& caps) {
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
  if (period < std::ceil(1e6 / caps.max_rate_hz))
    bad_input("period of " + number_text(period) + " us is faster than the device's " +
              std::to_string(caps.max_rate_hz) + " Hz");
  // The device's timing rule (device::phase_fits): a gap, and the off time between
  // pulses, each at least its shortest phase, in which it loads the next phase's codes.
  if (cfg.interphase_us != 0 && cfg.interphase_us < caps.min_width_us)
    bad_input("interphase gap of " + std::to_string(cfg.interphase_us) +
              " us is shorter than the device's shortest phase of " +
              std::to_string(caps.min_width_us) + " us (0 for no gap)");
  if (period - length_us < caps.min_width_us)
    bad_input("off time of " + number_text(period - length_us) + " us between pulses (period " +
              number_text(period) + " us, pulse " + number_text(length_us) +
              " us) is shorter than the device's shortest phase of " +
              std::to_string(caps.min_width_us) + " us");
  cfg.channels = static_cast<std::uint8_t>(s.currents_mA.size());
  return cfg;
}

// The device's throughput (Capabilities::max_pulse_rate_hz), checked as it will at start:
// the pulses a second over every pattern, in whole thousandths.
void check_pulse_rate(const SessionPlan& plan, const Mix& m) {
  device::PatternTiming single;
  single.period_us = plan.single.period_us;
  const std::uint64_t rate = plan.table
                                 ? device::pulse_rate_mHz(plan.timings.data(), plan.timings.size())
                                 : device::pulse_rate_mHz(&single, 1);
  if (!device::within_pulse_rate(rate, plan.caps))
    bad_input("the stimulus asks " +
              number_text(std::round(static_cast<double>(rate) / 100) / 10) + " pulses a second" +
              (m.single() ? std::string()
                          : " over its " + std::to_string(m.patterns.size()) + " patterns") +
              "; the device delivers at most " + std::to_string(plan.caps.max_pulse_rate_hz) +
              " a second on time (its measured throughput): lower the rates or use fewer "
              "patterns (docs/safety.md)");
  if (!plan.table) return;
  // Then the edges (protocol 6): a shaped pulse has one more than its phases.
  const std::uint64_t edges = device::edge_rate_mHz(plan.timings.data(), plan.timings.size());
  if (!device::within_edge_rate(edges, plan.caps))
    bad_input("the stimulus asks " + number_text(std::round(static_cast<double>(edges) / 100) / 10) +
              " phase edges a second; the device makes at most " +
              std::to_string(plan.caps.max_edge_rate_hz) +
              " a second on time: lower the rates or use fewer phases (docs/safety.md)");
}

// A shaped pattern, as the device will check it (device::check_shape), then its limits
// again on the currents its codes deliver.
void check_shaped_pattern(const Stimulus& p, const device::PatternTiming& t,
                          const std::vector<std::int16_t>& codes, const device::Capabilities& caps,
                          const StimulusLimits& lim, const std::string& where) {
  switch (device::check_shape(t.shape, caps)) {
    case device::Result::ok:
      break;
    case device::Result::not_supported:
      bad_input(caps.protocol < 6
                    ? "the device speaks protocol " + std::to_string(caps.protocol) +
                          ": it cannot deliver shaped pulses (pulse.phases; protocol 6)"
                    : std::string("the device cannot deliver shaped pulses (pulse.phases): its "
                                  "capabilities claim none"));
    case device::Result::bad_length:
      bad_input(where + std::to_string(t.shape.n) + " phases, more than the device's " +
                std::to_string(caps.max_phases));
    default:
      bad_input(where + "a phase outside the device's timing (each " +
                std::to_string(caps.min_width_us) + " to " +
                std::to_string(caps.max_balance_width_us) + " us, the largest level's at most " +
                std::to_string(caps.max_width_us) + " us)");
  }
  try {
    check_stimulus(host::delivered_stimulus(p, codes, caps), lim);
  } catch (const Error& e) {
    bad_input(where + "as the device's codes deliver it: " + e.what());
  }
}

// A table: each pattern's timing (its own count) and codes, checked as the device will.
void plan_table(SessionPlan& plan, const Mix& m, const SessionOptions& opt) {
  const device::Capabilities& caps = plan.caps;
  const StimulusLimits& lim = plan.limits;
  if (m.patterns.size() > caps.max_patterns)
    bad_input("stimulus has " + std::to_string(m.patterns.size()) + " patterns; the device holds " +
              std::to_string(caps.max_patterns));
  const double least_gap = std::max(caps.min_gap_us, caps.min_width_us);
  if (m.gap_us < least_gap)
    bad_input("gap_us: " + number_beside(m.gap_us, least_gap) +
              " us, below the device's least gap of " + number_text(least_gap) + " us");
  device::ChannelLoad load;
  std::size_t entries = 0;
  plan.pulses = 0;
  plan.expected_s = 0;
  for (const Stimulus& p : m.patterns) {
    const double n_p = pulse_count(p, opt, lim, "--duration: shorter than one period of a pattern");
    plan.timings.push_back(pattern_timing(p, static_cast<long>(n_p)));
    const device::PatternTiming& t = plan.timings.back();
    if (t.period_us < std::ceil(1e6 / caps.max_rate_hz) || !device::phase_fits(t, caps))
      bad_input("pattern " + std::to_string(plan.timings.size() - 1) +
                ": its period, gap or off time is outside the device's timing (" +
                std::to_string(caps.max_rate_hz) + " Hz, shortest phase " +
                std::to_string(caps.min_width_us) + " us)");
    plan.table_codes.push_back(pattern_codes(p, caps, current_limit_mA(p, lim)));
    if (t.shaped())
      check_shaped_pattern(p, t, plan.table_codes.back(), caps, lim,
                           m.single() ? "" : "pattern " + std::to_string(plan.timings.size() - 1) + ": ");
    for (std::int16_t c : plan.table_codes.back()) entries += c != 0;
    device::add_dense(load, plan.table_codes.back(), t);
    plan.pulses += n_p;
    plan.expected_s =
        std::max(plan.expected_s, (t.phase_us + (t.max_pulses + 0.0) * t.period_us) * 1e-6);
  }
  if (entries > caps.code_pool)
    bad_input("the patterns have " + std::to_string(entries) +
              " non-zero codes; the device holds " + std::to_string(caps.code_pool));
  check_load(load, caps, "summed over the patterns: ");
}

}  // namespace

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

double current_limit_mA(const Stimulus& s, const StimulusLimits& lim) {
  return std::min(s.max_current_mA, lim.max_current_mA);
}

std::vector<std::int16_t> parse_live_frame(const std::string& line, std::size_t n_line,
                                           const Stimulus& s, const StimulusLimits& lim,
                                           const device::Capabilities& caps) {
  Mix m;
  m.patterns.push_back(s);
  LiveState state(m, lim, caps);
  const LiveFrame f = parse_live_line(line, "input line " + std::to_string(n_line));
  if (f.kind != LiveFrame::Kind::currents)
    bad_input("input line " + std::to_string(n_line) + ": expected {\"currents_mA\": [...]}");
  state.add(f);
  return *state.take().codes;
}

namespace {

double peak_of(const std::vector<std::int16_t>& codes, const device::Capabilities& caps) {
  int m = 0;
  for (std::int16_t c : codes) m = std::max(m, std::abs(int{c}));
  return m * caps.dac_step_nA * 1e-6;
}

}  // namespace

device::Guards guards_of(const Mix& m, const SessionOptions& opt) {
  const StimulusLimits& limits = opt.limits;
  device::Guards g;
  if (opt.suspend_on_contact_loss) g.flags = device::kGuardSuspend;
  g.probe_uA = static_cast<std::uint16_t>(std::clamp(std::floor(opt.probe_mA * 1000 + 1e-9), 10.0, 500.0));
  double area_mm2 = 4000.0;  // the protocol's largest; a larger pad is guarded as this
  for (const Stimulus& s : m.patterns) area_mm2 = std::min(area_mm2, s.electrode_area_mm2);
  g.area_um2 = static_cast<std::uint32_t>(
      std::clamp(std::floor(area_mm2 * 1e6), double{device::kMinGuardAreaUm2},
                 double{device::kMaxGuardAreaUm2}));
  g.shannon_k_milli = static_cast<std::uint16_t>(std::clamp(
      std::floor(limits.shannon_k * 1000 + 1e-9), 500.0, 2500.0));
  return g;
}

std::string guard_trip_text(const device::MeasurementsHead& h, const device::Capabilities& caps) {
  const std::string channel = "channel " + std::to_string(h.trip_channel);
  const std::string when = " at t = " + number_text(h.trip_t_us * 1e-6) + " s (";
  const std::string z = h.trip_ohm == device::kOpenOhm
                            ? "no current flowed"
                            : "impedance " + number_text(h.trip_ohm * 1e-3) + " kOhm";
  switch (h.trip) {
    case device::Fault::contact:
      return channel + " lost contact" + when + z + ")";
    case device::Fault::compliance:
      return channel + " needed more than the " + std::to_string(caps.compliance_V) +
             " V compliance" + when + z + "): its current was not delivered as asked";
    case device::Fault::density:
      return channel + ": charge density above the limit on the contact area left" + when + z +
             ")";
    default:
      return "a guard stopped it, but the device does not say which";
  }
}

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

SessionReport run_session(Transport& transport, const Stimulus& s, const SessionOptions& opt) {
  Mix m;
  m.patterns.push_back(s);
  return run_session(transport, m, opt);
}

SessionPlan plan_session(const device::Capabilities& caps, const Mix& m,
                         const SessionOptions& opt) {
  check_request(m, opt);
  const Stimulus& s = m.patterns[0];
  SessionPlan plan;
  plan.caps = caps;
  // A shaped pulse goes as a table (set_shape gives a pattern its phases).
  plan.table = m.table() || std::any_of(m.patterns.begin(), m.patterns.end(),
                                        [](const Stimulus& p) { return p.shape.shaped(); });
  check_device(caps);
  if (s.currents_mA.size() > caps.channels)
    bad_input("stimulus has " + std::to_string(s.currents_mA.size()) +
              " channels; the device has " + std::to_string(caps.channels));
  plan.limits = device_limits(opt.limits, caps);
  const StimulusLimits& lim = plan.limits;
  check_mix(m, lim);
  plan.single = single_config(s, caps);
  const double count = pulse_count(s, opt, lim, "--duration: shorter than one pulse period");
  // The device always has a pulse budget: it stops by itself after the stimulus' pulses
  // (live mode: --duration, or the duration limit), whatever becomes of the host.
  plan.single.max_pulses = static_cast<std::uint32_t>(count);
  // No code above the limit in force (the stimulus's, the host's, the device's).
  plan.codes = pattern_codes(s, caps, current_limit_mA(s, lim));
  if (plan.table) {
    plan_table(plan, m, opt);
  } else {
    device::ChannelLoad load;
    device::add_dense(load, plan.codes, pattern_timing(s, 0));
    check_load(load, caps, "");
    plan.pulses = count;
  }
  check_pulse_rate(plan, m);
  // At the device's (rounded) periods; a table's pulses may come up to 1 ms late.
  plan.expected_s = plan.table ? plan.expected_s + 0.001 : count * plan.single.period_us * 1e-6;
  return plan;
}

namespace {

// One run of a session, in named steps: prepare (every check; identify only), open the
// output (stop another host's, configure, upload, start), keep it alive (live updates,
// keep-alives, the device's end), finish (stop, the device's counts, delivered against
// scheduled).  Every step that leads to output first asks whether to stop.
class SessionRun {
 public:
  SessionRun(Transport& t, const Mix& m, const SessionOptions& opt)
      : m_(m), opt_(opt), dev_(t) {
    rep_.port = t.name();
  }

  SessionReport run() {
    if (!prepare()) return rep_;
    try {
      if (!open_output()) return rep_;
      keep_alive();
      dev_.stop();
    } catch (const Error& e) {
      // A failure once the output runs (a bad live frame, a lost link) ends it first, and
      // says so: what was asked is not what was delivered.
      const bool stopped = stop_quietly();
      if (!rep_.started) throw;
      throw Error(e.code(), std::string(e.what()) +
                                (stopped ? "; output stopped"
                                         : "; the device did not answer the stop: its watchdog "
                                           "ends the output"));
    } catch (...) {
      stop_quietly();
      throw;
    }
    finish();
    return rep_;
  }

 private:
  bool stop_asked() const { return opt_.stop.requested(); }
  void end_by_stop() {
    StopToken::Why why = opt_.stop.why();
    rep_.end = std::move(why.reason);
    rep_.exit_code = why.exit_code;
  }
  // True when the device acknowledged the stop (or nothing was configured to stop).
  bool stop_quietly() noexcept {
    if (!configured_) return true;
    try {
      dev_.stop();
      return true;
    } catch (...) {
      return false;  // the device is unreachable; its watchdog stops the output
    }
  }
  double elapsed_s() const { return static_cast<double>(monotonic_ns() - t0_) * 1e-9; }

  bool prepare();
  bool open_output();
  void upload(int step);
  void keep_alive();
  bool take_frames(int wait_ms);
  bool send_update(const LiveState::Update& u);
  bool device_ended(const device::Status& st);
  // Protocol 7: each channel's last reading into rep_.measured (and opt_.measurements), the
  // head (what tripped); nothing from a device that does not measure.
  device::MeasurementsHead read_measurements();
  void finish();

  Mix m_;  // a copy: --hold-sensation raises it to its ceiling (host/hold.hpp)
  const SessionOptions& opt_;
  StimulatorClient dev_;
  SessionReport rep_;
  SessionPlan plan_;
  std::optional<LiveState> live_;
  std::optional<LineFile> latency_;
  std::int64_t t0_ = 0;
  bool configured_ = false;
  bool input_open_ = true;
  std::uint32_t updates_ = 0;  // live updates sent (each the fold of the frames before it)
};

// 1. Every check before anything but identify is sent: the stimulus, its duration, the
//    device's capabilities, and the stimulus against them (plan_session).
bool SessionRun::prepare() {
  check_request(m_, opt_);  // before identify: bad input sends nothing at all
  if (stop_asked()) {
    end_by_stop();
    return false;
  }
  rep_.caps = dev_.identify();
  if (opt_.suspend_on_contact_loss && !rep_.caps.measures())
    bad_input("--contact-loss suspend: " + rep_.port +
              " does not measure its pulses, so it cannot tell a lost contact (protocol 7)");
  if (opt_.hold_sensation) {
    if (!rep_.caps.measures())
      bad_input("--hold-sensation: " + rep_.port +
                " does not measure its pulses, so it cannot hold the sensation (protocol 7)");
    m_ = hold_ceiling(m_, device_limits(opt_.limits, rep_.caps), &rep_.hold_headroom);
  }
  plan_ = plan_session(rep_.caps, m_, opt_);
  rep_.scheduled = plan_.pulses;
  if (opt_.live) {
    live_.emplace(m_, plan_.limits, rep_.caps);
    if (!opt_.latency_log.empty()) latency_.emplace(opt_.latency_log, "--latency-log");
  }
  return true;
}

// 2. A device still running is another host's output (the port is ours alone): stop it.
//    Then configure a session of our own, upload, start.  False: stopped before the start
//    (the session we opened is disarmed).
bool SessionRun::open_output() {
  t0_ = monotonic_ns();
  if (stop_asked()) {
    end_by_stop();
    return false;
  }
  if (dev_.status().state == device::State::running) {
    dev_.stop();
    rep_.preempted = true;
  }
  // A table: configure, each pattern's timing and codes, its starting amplitudes (when the
  // document gives them: after the codes, which reset them), start.  A single stimulus:
  // configure, its weights, start.
  const int uploads = plan_.table ? 2 * static_cast<int>(m_.patterns.size()) : 1;
  const bool start_scales = plan_.table && !m_.start_amplitudes_mA.empty();
  const int steps = 1 + uploads + (start_scales ? 1 : 0);
  for (int step = 0; step < steps; ++step) {
    if (stop_asked()) {
      end_by_stop();
      dev_.stop();  // disarm the session we opened
      return false;
    }
    upload(step);
  }
  if (stop_asked()) {
    end_by_stop();
    dev_.stop();
    return false;
  }
  dev_.start();
  rep_.started = true;
  t0_ = monotonic_ns();
  return true;
}

void SessionRun::upload(int step) {
  const Stimulus& s = m_.patterns[0];
  const int uploads = plan_.table ? 2 * static_cast<int>(m_.patterns.size()) : 1;
  if (step == 0) {
    if (plan_.table)
      dev_.configure_table(static_cast<std::uint16_t>(m_.patterns.size()),
                           static_cast<std::uint8_t>(s.currents_mA.size()),
                           static_cast<std::uint16_t>(std::lround(m_.gap_us)));
    else
      dev_.configure(plan_.single);
    configured_ = true;
    if (rep_.caps.measures()) dev_.set_guards(guards_of(m_, opt_));
  } else if (!plan_.table) {
    dev_.set_weights(plan_.codes);
    rep_.peak_mA = peak_of(plan_.codes, rep_.caps);
  } else if (step <= uploads) {
    const auto i = static_cast<std::uint16_t>((step - 1) / 2);
    if ((step - 1) % 2 == 0 && plan_.timings[i].shaped()) {
      dev_.set_shape(i, plan_.timings[i]);
    } else if ((step - 1) % 2 == 0) {
      dev_.set_pattern(i, plan_.timings[i]);
    } else {
      dev_.set_codes(i, plan_.table_codes[i]);
      if (opt_.hold_sensation)
        dev_.set_hold(i, hold_energy(plan_.table_codes[i], m_.patterns[i].reference_impedance_kohm));
      rep_.peak_mA = std::max(rep_.peak_mA, peak_of(plan_.table_codes[i], rep_.caps) *
                                                plan_.timings[i].max_units());
    }
  } else {
    dev_.set_amplitudes(
        parse_amplitudes({{"amplitudes", m_.start_amplitudes_mA}}, m_, "start_amplitudes_mA"));
  }
}

// 3. Keeps the session alive until the run ends: the stimulus completes, --duration passes,
//    the live input ends, a stop is asked, or the device stops the output.
void SessionRun::keep_alive() {
  std::int64_t last_keepalive = monotonic_ns(), last_progress = last_keepalive;
  const std::int64_t period_ns = std::int64_t{kKeepAliveMs} * 1000000;
  while (true) {
    if (stop_asked()) {
      end_by_stop();
      return;
    }
    const std::int64_t now = monotonic_ns();
    if (elapsed_s() > plan_.expected_s + 1.0) {
      const device::Status st = dev_.status();
      failure("device did not complete the stimulus in time: " + std::to_string(st.pulses) +
              " of " + number_text(plan_.pulses) + " pulses delivered " +
              number_text(std::round(elapsed_s() * 100) / 100) + " s after the start");
    }
    const std::int64_t wait_ns = std::max<std::int64_t>(0, last_keepalive + period_ns - now);
    const int wait_ms = static_cast<int>((wait_ns + 999999) / 1000000);
    if (live_ && input_open_) {
      if (!take_frames(wait_ms)) return;  // the device ended the session: rep_.end says how
      if (!input_open_) {
        rep_.end = "end of input";
        return;
      }
    } else {
      timespec ts{0, static_cast<long>(wait_ns)};
      nanosleep(&ts, nullptr);
    }
    const std::int64_t after = monotonic_ns();
    const bool keepalive_due = after - last_keepalive >= period_ns;
    const bool should_be_done = elapsed_s() >= plan_.expected_s;
    if (keepalive_due || should_be_done) {
      const device::Status st = dev_.keepalive();
      last_keepalive = monotonic_ns();
      rep_.pulses = st.pulses;
      if (device_ended(st)) return;
    }
    if ((opt_.progress || opt_.measurements) && after - last_progress >= 250000000) {
      last_progress = after;
      read_measurements();
      if (opt_.progress)
        opt_.progress(SessionProgress{elapsed_s(), plan_.expected_s, rep_.pulses, plan_.pulses,
                                      rep_.weight_frames, rep_.measured});
    }
  }
}

// The live input's frames, waiting up to wait_ms; their net effect sent at once.  False:
// the device had ended the session meanwhile (completed: rep_.end says so).
bool SessionRun::take_frames(int wait_ms) {
  FrameSource& source = *opt_.frames;
  input_open_ = source.pump(*live_, wait_ms);
  const LiveState::Update u = live_->take();
  if (u.empty()) return true;
  rep_.weight_frames += u.frames;
  if (!send_update(u)) return false;
  ++updates_;
  if (latency_)
    latency_->line(std::to_string(updates_) + " " + std::to_string(dev_.last_write_ns()));
  return true;
}

bool SessionRun::send_update(const LiveState::Update& u) {
  // Refused as not of the session: the device ended it meanwhile (or another host took it).
  auto ended = [&] {
    const device::Status st = dev_.status();
    if (st.state == device::State::running)
      failure("the device is running another session's output: ours was taken over");
    rep_.pulses = st.pulses;
    return !device_ended(st);
  };
  if (u.codes) {
    if (!dev_.set_weights_live(*u.codes)) return ended();
    rep_.peak_mA = std::max(rep_.peak_mA, peak_of(*u.codes, rep_.caps));
  }
  if (u.scales && !dev_.set_amplitudes_live(*u.scales)) return ended();
  return true;
}

// The device's state after a keep-alive or a refused update: true when it has ended the
// session; a completed stimulus ends the run, any other end is a failure naming it.
bool SessionRun::device_ended(const device::Status& st) {
  if (st.state != device::State::idle) return false;
  if (st.fault == device::Fault::completed) {
    rep_.end = "stimulus complete";
    return true;
  }
  const std::string counts =
      std::to_string(st.pulses) + " of " + number_text(plan_.pulses) + " pulses delivered";
  if (st.fault == device::Fault::stop_input) {
    const device::MeasurementsHead h = read_measurements();
    const std::string when = h.trip == device::Fault::stop_input
                                 ? " at t = " + number_text(h.trip_t_us * 1e-6) + " s"
                                 : "";
    failure("device stopped the output: its stop input was pressed" + when +
            " (the output is latched off until a new session); " + counts);
  }
  if (st.fault == device::Fault::contact || st.fault == device::Fault::compliance ||
      st.fault == device::Fault::density) {
    const std::string trip = guard_trip_text(read_measurements(), rep_.caps);
    if (opt_.probe) {
      rep_.end = "a guard stopped the probe: " + trip;
      return true;
    }
    failure("device stopped the output: " + trip + "; " + counts);
  }
  failure(std::string("device stopped the output: ") + device::to_string(st.fault) + " (" +
          counts + ")");
}

device::MeasurementsHead SessionRun::read_measurements() {
  if (!rep_.caps.measures()) return {};
  const device::Measurements m = dev_.measurements(m_.patterns[0].currents_mA.size());
  rep_.measured = m.channels;
  if (opt_.measurements) opt_.measurements(rep_.measured);
  return m.head;
}

// 4. The device's counts; a completed stimulus must have delivered what was scheduled.
void SessionRun::finish() {
  const device::Status st = dev_.status();
  rep_.pulses = st.pulses;
  rep_.seconds = elapsed_s();
  rep_.retransmissions = dev_.retransmissions();
  rep_.rx_errors = st.rx_errors;
  rep_.line_errors = st.line_errors;
  rep_.overruns = st.overruns;
  rep_.suspended_pulses = read_measurements().suspended;
  if (latency_) latency_->close();
  if (rep_.end == "stimulus complete" && static_cast<double>(st.pulses) != plan_.pulses)
    failure("the device delivered " + std::to_string(st.pulses) + " of the " +
            number_text(plan_.pulses) +
            " pulses scheduled and reported the stimulus complete: the stimulus was not "
            "delivered as asked (a device that cannot keep up with its rate: docs/safety.md)");
}

}  // namespace

SessionReport run_session(Transport& transport, const Mix& m, const SessionOptions& opt) {
  return SessionRun(transport, m, opt).run();
}

}  // namespace tp::host
