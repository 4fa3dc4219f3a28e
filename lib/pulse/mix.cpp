#include "pulse/mix.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.hpp"
#include "device/device_core.hpp"
#include "core/number.hpp"

namespace tp {
namespace {

std::uint32_t whole_us(double v, double max, const std::string& what) {
  if (!(v >= 0.0 && v <= max))
    bad_input(what + " " + number_beside(v, 0, max) + " us outside [0, " + number_text(max) +
              "] us");
  const double r = std::round(v);
  if (std::fabs(v - r) > 1e-6)
    bad_input(what + ": the device takes whole microseconds, got " + number_text(v));
  return static_cast<std::uint32_t>(r);
}

const char* kMixFormat = "tactile-primaries/stimulus/2";

}  // namespace

double Mix::duration_s() const {
  double d = 0;
  for (const Stimulus& s : patterns) d = std::max(d, s.duration_s());
  return d;
}

device::Shape device_shape(const std::vector<Phase>& phases) {
  if (phases.empty() || phases.size() > device::kMaxPhases)
    bad_input("pulse.phases: " + std::to_string(phases.size()) + " phases, not 1 to " +
              std::to_string(device::kMaxPhases));
  const ShapeUnits u = shape_units(phases);
  device::Shape d;
  d.n = static_cast<std::uint8_t>(phases.size());
  for (std::size_t k = 0; k < phases.size(); ++k) {
    d.duration_us[k] = static_cast<std::uint16_t>(
        whole_us(phases[k].duration_us, 65535, "phase " + std::to_string(k + 1) + ": duration"));
    if (std::abs(u.units[k]) > device::hard::max_units)
      bad_input("phase " + std::to_string(k + 1) + ": " + std::to_string(u.units[k]) +
                " units, more than the protocol's " + std::to_string(device::hard::max_units));
    d.units[k] = static_cast<std::int16_t>(u.units[k]);
  }
  return d;
}

device::PatternTiming pattern_timing(const Stimulus& s, long count) {
  device::PatternTiming t;
  if (s.shape.shaped()) {  // no widths: the phases are the pulse (set_shape)
    t.width_us = t.interphase_us = t.balance_width_us = 0;
    t.shape = device_shape(s.shape.phases);
  } else {
    t.width_us = static_cast<std::uint16_t>(whole_us(s.shape.width_us, 65535, "pulse width"));
    t.interphase_us =
        static_cast<std::uint16_t>(whole_us(s.shape.interphase_us, 65535, "interphase gap"));
    t.balance_width_us =
        static_cast<std::uint16_t>(whole_us(s.shape.balance_width_us, 65535, "balance width"));
  }
  // The device counts whole microseconds: the period is rounded (150 Hz: 6667 us).
  const double period = std::round(s.shape.period_us());
  if (!(period >= 1 && period <= device::hard::max_period_us))
    bad_input("pulse period of " + number_text(period) + " us outside the protocol's 1 us to " +
              std::to_string(device::hard::max_period_us / 1000000) + " s");
  t.period_us = static_cast<std::uint32_t>(period);
  t.phase_us = whole_us(s.phase_us, period - 1, "phase");
  t.max_pulses = count < 0 ? 0 : static_cast<std::uint32_t>(std::min<long>(count, UINT32_MAX));
  return t;
}

MixFigures mix_figures(const Mix& m, double max_slip_us) {
  MixFigures f;
  const std::size_t n = m.patterns.empty() ? 0 : m.patterns[0].currents_mA.size();
  f.rms_current_mA.assign(n, 0.0);
  f.mean_current_mA.assign(n, 0.0);
  device::Scheduler sched;  // large: 10 KB of tables
  sched.set_table(static_cast<std::uint16_t>(m.patterns.size()),
                  static_cast<std::uint16_t>(std::lround(m.gap_us)));
  for (std::size_t p = 0; p < m.patterns.size(); ++p) {
    const Stimulus& s = m.patterns[p];
    const SafetyFigures sf = safety_figures(s);
    for (std::size_t i = 0; i < n && i < s.currents_mA.size(); ++i) {
      f.rms_current_mA[i] += sf.rms_current_mA[i] * sf.rms_current_mA[i];
      f.mean_current_mA[i] += sf.mean_current_mA[i];
    }
    const device::PatternTiming t = pattern_timing(s, 0);
    sched.set_timing(static_cast<std::uint16_t>(p), t.period_us, t.phase_us, t.length_us(), 0);
  }
  for (double& v : f.rms_current_mA) v = std::sqrt(v);
  f.utilisation = static_cast<double>(sched.utilisation_q20()) / device::Scheduler::kOneQ20;
  if (f.utilisation <= 1.0) {
    const std::uint32_t w =
        sched.worst_slip(static_cast<std::uint32_t>(std::clamp(max_slip_us, 0.0, 4e9)),
                         device::kMaxCheckedPulsesHost);
    f.worst_slip_us = w == UINT32_MAX ? HUGE_VAL : static_cast<double>(w);
  } else {
    f.worst_slip_us = HUGE_VAL;
  }
  return f;
}

void check_mix(const Mix& m, const StimulusLimits& lim) {
  if (m.patterns.empty()) bad_input("stimulus: no patterns");
  if (m.patterns.size() > device::kMaxPatterns)
    bad_input("stimulus: " + std::to_string(m.patterns.size()) +
              " patterns, more than a device holds (" + std::to_string(device::kMaxPatterns) + ")");
  if (!m.start_amplitudes_mA.empty())
    parse_amplitudes({{"amplitudes", m.start_amplitudes_mA}}, m, "start_amplitudes_mA");
  const std::size_t channels = m.patterns[0].currents_mA.size();
  for (std::size_t p = 0; p < m.patterns.size(); ++p) {
    const Stimulus& s = m.patterns[p];
    const std::string where = m.single() ? "" : "pattern " + std::to_string(p) + ": ";
    if (s.currents_mA.size() != channels)
      bad_input(where + std::to_string(s.currents_mA.size()) + " channels, pattern 0 has " +
                std::to_string(channels) + ": a mix drives one set of electrodes");
    try {
      check_stimulus(s, lim);
      (void)pattern_timing(s, s.count);
    } catch (const Error& e) {
      bad_input(where + e.what());
    }
  }
  if (!m.table()) return;
  if (!(m.gap_us >= lim.min_gap_us && m.gap_us <= lim.max_slip_us) ||
      std::fabs(m.gap_us - std::round(m.gap_us)) > 1e-6)
    bad_input("gap_us: " + number_beside(m.gap_us, lim.min_gap_us, lim.max_slip_us) +
              " us; whole microseconds in [" + number_text(lim.min_gap_us) + ", " +
              number_text(lim.max_slip_us) + "] us");
  const MixFigures f = mix_figures(m, lim.max_slip_us);
  for (std::size_t i = 0; i < channels; ++i) {
    if (f.rms_current_mA[i] > lim.max_rms_current_mA * (1 + 1e-12))
      bad_input("electrode " + std::to_string(i) + ": RMS current " +
                number_beside(f.rms_current_mA[i], lim.max_rms_current_mA) +
                " mA summed over the patterns, above the " + "limit of " +
                number_text(lim.max_rms_current_mA) + " mA (docs/safety.md)");
    if (f.mean_current_mA[i] > lim.max_mean_current_mA * (1 + 1e-12))
      bad_input("electrode " + std::to_string(i) + ": mean current " +
                number_beside(f.mean_current_mA[i], lim.max_mean_current_mA) +
                " mA summed over the patterns, above the " + "limit of " +
                number_text(lim.max_mean_current_mA) + " mA (docs/safety.md)");
  }
  if (f.utilisation > 1.0)
    bad_input("the patterns' pulses and gaps need " +
              number_text(std::round(f.utilisation * 1000) / 10) +
              " % of the time: they cannot fit their periods (lower a rate, shorten a pulse)");
  if (!(f.worst_slip_us <= lim.max_slip_us))
    bad_input("a pulse could be deferred by more than " + number_text(lim.max_slip_us) +
              " us behind the others' (docs/protocol.md, Scheduling): stagger the phases, or "
              "use fewer patterns or shorter pulses");
}

Mix mix_from_json(const Json& j) {
  if (!j.is_object()) bad_input("stimulus: expected a JSON object");
  Mix m;
  if (!j.contains("format") || j["format"] != kMixFormat) {
    if (!j.contains("format") || j["format"] != "tactile-primaries/stimulus/1")
      bad_input(std::string("stimulus: 'format' must be \"tactile-primaries/stimulus/1\" "
                            "(make-pulse's output) or \"") +
                kMixFormat + "\" (mix-stimuli's)");
    m.patterns.push_back(stimulus_from_json(j));
    return m;
  }
  if (!j.contains("patterns") || !j["patterns"].is_array() || j["patterns"].empty())
    bad_input("stimulus: missing 'patterns' (a list of stimuli)");
  if (j["patterns"].size() > device::kMaxPatterns)
    bad_input("stimulus: " + std::to_string(j["patterns"].size()) +
              " patterns, more than a device holds (" + std::to_string(device::kMaxPatterns) + ")");
  if (j.contains("gap_us")) m.gap_us = json_finite(j["gap_us"], "gap_us");
  for (std::size_t p = 0; p < j["patterns"].size(); ++p) {
    Json one = j["patterns"][p];
    const std::string where = "pattern " + std::to_string(p) + ": ";
    if (!one.is_object()) bad_input(where + "expected a JSON object");
    double phase = 0;
    if (one.contains("phase_us")) phase = json_finite(one["phase_us"], where + "phase_us");
    one.erase("phase_us");
    // A pattern is a stimulus document without its format (mix_to_json leaves it out); one
    // that names a format must name that one, never have another silently replaced.
    if (one.contains("format") && one["format"] != "tactile-primaries/stimulus/1")
      bad_input(where + "'format' " + one["format"].dump() +
                ": a pattern is a stimulus (\"tactile-primaries/stimulus/1\", or no format)");
    one["format"] = "tactile-primaries/stimulus/1";
    try {
      m.patterns.push_back(stimulus_from_json(one));
    } catch (const Error& e) {
      bad_input(where + e.what());
    }
    m.patterns.back().phase_us = phase;
  }
  if (j.contains("channels") &&
      json_int(j["channels"], "channels") != static_cast<int>(m.patterns[0].currents_mA.size()))
    bad_input("stimulus: 'channels' disagrees with the patterns'");
  if (j.contains("start_amplitudes_mA")) {
    // Checked as a live frame is: one per pattern, each 0 to its amplitude.
    parse_amplitudes({{"amplitudes", j["start_amplitudes_mA"]}}, m, "start_amplitudes_mA");
    for (const Json& a : j["start_amplitudes_mA"]) m.start_amplitudes_mA.push_back(a.get<double>());
  }
  return m;
}

Json mix_to_json(const Mix& m) {
  if (!m.table()) return stimulus_to_json(m.patterns[0]);
  Json j;
  j["format"] = kMixFormat;
  j["channels"] = m.patterns[0].currents_mA.size();
  j["gap_us"] = m.gap_us;
  j["duration_s"] = m.duration_s();
  if (!m.start_amplitudes_mA.empty()) j["start_amplitudes_mA"] = m.start_amplitudes_mA;
  Json list = Json::array();
  for (const Stimulus& s : m.patterns) {
    Json one = stimulus_to_json(s);
    one.erase("format");
    one.erase("channels");
    one["phase_us"] = s.phase_us;
    list.push_back(one);
  }
  j["patterns"] = list;
  const MixFigures f = mix_figures(m);
  j["safety"] = Json{{"rms_current_mA", f.rms_current_mA},
                     {"mean_current_mA", f.mean_current_mA},
                     {"utilisation", f.utilisation},
                     {"worst_slip_us", f.worst_slip_us}};
  return j;
}

double pattern_amplitude_mA(const Stimulus& s) {
  if (s.amplitude_mA > 0) return s.amplitude_mA;
  double top = 0;
  for (double c : s.currents_mA) top = std::max(top, std::fabs(c));
  return top;
}

std::vector<std::uint16_t> amplitude_scales(const std::vector<double>& a, const Mix& m,
                                            const std::string& where) {
  if (a.size() != m.patterns.size())
    bad_input(where + ": " + std::to_string(a.size()) + " amplitudes for " +
              std::to_string(m.patterns.size()) +
              (m.patterns.size() == 1 ? " pattern" : " patterns"));
  std::vector<std::uint16_t> scales;
  for (std::size_t p = 0; p < a.size(); ++p) {
    const double v = a[p];
    const double top = pattern_amplitude_mA(m.patterns[p]);
    if (!(v >= 0 && v <= top * (1 + 1e-12)))
      bad_input(where + ": amplitude " + number_beside(v, 0, top) + " mA for pattern " +
                std::to_string(p) + " outside [0, " + number_text(top) +
                "] mA (the current of its weight-1 electrode)");
    const double scale = top > 0 ? std::floor(std::min(1.0, v / top) * device::kFullScale) : 0.0;
    scales.push_back(static_cast<std::uint16_t>(scale));
  }
  return scales;
}

std::vector<std::uint16_t> parse_amplitudes(const Json& j, const Mix& m, const std::string& where) {
  if (!j.is_object() || j.size() != 1 || !j.contains("amplitudes") || !j["amplitudes"].is_array())
    bad_input(where + ": expected {\"amplitudes\": [...]} and no other key");
  const Json& list = j["amplitudes"];
  std::vector<double> a;
  for (std::size_t p = 0; p < list.size(); ++p)
    a.push_back(json_finite(list[p], where + " amplitudes[" + std::to_string(p) + "]"));
  return amplitude_scales(a, m, where);
}

}  // namespace tp
