#include "pulse/stimulus.hpp"

#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"

namespace tp {

std::vector<Phase> PulseShape::delivered() const {
  return shaped() ? phases : shorthand_phases(width_us, interphase_us, balance_width_us);
}

double PulseShape::length_us() const {
  if (!shaped()) return width_us + interphase_us + balance_width_us;
  double d = 0;
  for (const Phase& p : phases) d += p.duration_us;
  return d;
}

namespace {

void range(double v, double lo, double hi, const std::string& what, const std::string& unit) {
  if (!std::isfinite(v) || v < lo || v > hi)
    bad_input(what + " " + number_beside(v, lo, hi) + " " + unit + " outside [" +
              number_text(lo) + ", " + number_text(hi) + "] " + unit);
}

// The pulse's ranges: the shorthand's widths or the phases, the rate, and the period.
void check_shape(const PulseShape& p, const StimulusLimits& lim) {
  if (p.shaped()) {
    check_phases(p.phases, PhaseLimits{lim.min_width_us, lim.max_width_us,
                                       lim.max_balance_width_us});
  } else {
    range(p.width_us, lim.min_width_us, lim.max_width_us, "pulse width", "us");
    range(p.balance_width_us, p.width_us, lim.max_balance_width_us, "balance width", "us");
    range(p.interphase_us, 0.0, lim.max_width_us, "interphase gap", "us");
  }
  range(p.frequency_hz, lim.min_frequency_hz, lim.max_frequency_hz, "frequency", "Hz");
  if (p.length_us() >= p.period_us())
    bad_input("pulse of " + number_beside(p.length_us(), p.period_us()) +
              " us does not fit its period of " + number_text(p.period_us()) + " us");
}

// Each channel's current within the limit at every phase (the shorthand's main phase is its
// largest), and the currents summing to zero.
void check_currents(const Stimulus& s, const StimulusLimits& lim) {
  const double limit = std::min(lim.max_current_mA, s.max_current_mA);
  const double level = s.shape.shaped() ? shape_sums(s.shape.phases).peak_level : 1.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < s.currents_mA.size(); ++i) {
    const double c = s.currents_mA[i];
    if (!std::isfinite(c)) bad_input("channel " + std::to_string(i) + ": non-finite current");
    if (s.shape.shaped() && std::fabs(c) * level > limit + 1e-12)
      bad_input("channel " + std::to_string(i) + ": current " + number_text(c) +
                " mA at level " + number_text(level) + " is " +
                number_beside(std::fabs(c) * level, limit) + " mA, above the limit of " +
                number_text(limit) + " mA");
    if (std::fabs(c) > limit + 1e-12)
      bad_input("channel " + std::to_string(i) + ": current " +
                number_beside(c, c < 0 ? -limit : limit) + " mA exceeds the limit of " +
                number_text(limit) + " mA");
    sum += c;
  }
  // Every phase is the same shape times each channel's current, so the instantaneous sum
  // is a multiple of the sum of the main-phase currents.
  if (std::fabs(sum) > lim.sum_tolerance_mA)
    bad_input("channel currents sum to " + number_text(sum) +
              " mA, not 0: the current would not stay local (weights must sum to zero)");
}

}  // namespace

void check_stimulus(const Stimulus& s, const StimulusLimits& lim) {
  if (s.currents_mA.empty()) bad_input("stimulus: no channels");
  if (s.currents_mA.size() > static_cast<std::size_t>(ranges::max_channels))
    bad_input("stimulus: " + std::to_string(s.currents_mA.size()) +
              " channels, more than a stimulator drives (at most " +
              std::to_string(ranges::max_channels) + ")");
  check_shape(s.shape, lim);
  if (s.count < 1) bad_input("stimulus: pulse count must be >= 1");
  if (s.duration_s() > lim.max_duration_s)
    bad_input("duration " + number_beside(s.duration_s(), lim.max_duration_s) +
              " s above the limit of " + number_text(lim.max_duration_s) + " s");
  check_currents(s, lim);
  const SafetyFigures f = safety_figures(s);
  if (f.max_net_charge_nC > 1e-9) bad_input("pulse is not charge balanced");
  for (std::size_t i = 0; i < s.currents_mA.size(); ++i)
    if (f.rms_current_mA[i] > lim.max_rms_current_mA * (1 + 1e-12))
      bad_input("channel " + std::to_string(i) + ": RMS current " +
                number_beside(f.rms_current_mA[i], lim.max_rms_current_mA) +
                " mA above the limit of " + number_text(lim.max_rms_current_mA) +
                " mA (docs/safety.md)");
  if (f.max_mean_current_mA > lim.max_mean_current_mA * (1 + 1e-12))
    bad_input("mean current " + number_beside(f.max_mean_current_mA, lim.max_mean_current_mA) +
              " mA (charge per second, both phases) above the limit of " +
              number_text(lim.max_mean_current_mA) + " mA (docs/safety.md)");
  if (f.shannon_k > lim.shannon_k)
    bad_input("charge " + number_text(f.max_charge_per_phase_nC) + " nC per phase at " +
              number_text(f.max_charge_density_uC_per_cm2) + " uC/cm2: Shannon's k " +
              number_text(std::round(f.shannon_k * 1000) / 1000) + " above " +
              number_text(lim.shannon_k) + " (docs/safety.md)");
}

namespace {

// The density and Shannon's k of the largest charge per phase.
void add_density(SafetyFigures& f, double electrode_area_mm2) {
  // nC / mm^2 -> uC / cm^2: 1 nC/mm^2 = 1e-3 uC / 1e-2 cm^2 = 0.1 uC/cm^2.
  f.max_charge_density_uC_per_cm2 = f.max_charge_per_phase_nC / electrode_area_mm2 * 0.1;
  // Q in uC, D in uC/cm2; 0 for no charge (no log of 0).
  if (f.max_charge_per_phase_nC > 0)
    f.shannon_k =
        std::log10(f.max_charge_density_uC_per_cm2) + std::log10(f.max_charge_per_phase_nC * 1e-3);
}

// A shaped pulse's figures: each channel's current times the shape's sums; the charge per
// phase is that of the largest run of one sign.
SafetyFigures shaped_figures(const Stimulus& s) {
  SafetyFigures f;
  const ShapeSums sums = shape_sums(s.shape.phases);
  const double T = s.shape.period_us();
  double sum = 0.0;
  for (double c : s.currents_mA) {
    const double a = std::fabs(c);
    f.peak_current_mA = std::max(f.peak_current_mA, a * sums.peak_level);
    f.charge_per_phase_nC.push_back(a * sums.max_run_charge_us());
    f.max_charge_per_phase_nC = std::max(f.max_charge_per_phase_nC, f.charge_per_phase_nC.back());
    f.max_net_charge_nC = std::max(f.max_net_charge_nC, a * std::fabs(sums.net_us));
    f.rms_current_mA.push_back(a * std::sqrt(sums.square_us / T));
    f.max_rms_current_mA = std::max(f.max_rms_current_mA, f.rms_current_mA.back());
    f.mean_current_mA.push_back(a * sums.abs_us / T);
    f.max_mean_current_mA = std::max(f.max_mean_current_mA, f.mean_current_mA.back());
    sum += c;
  }
  f.max_instant_sum_mA = std::fabs(sum) * sums.peak_level;
  f.shortest_phase_us = sums.shortest_us;
  f.level_unit = level_unit(s.shape.phases);
  add_density(f, s.electrode_area_mm2);
  return f;
}

}  // namespace

SafetyFigures safety_figures(const Stimulus& s) {
  if (s.shape.shaped()) return shaped_figures(s);
  SafetyFigures f;
  const PulseShape& p = s.shape;
  double sum_main = 0.0;
  for (double c : s.currents_mA) {
    const double main_nC = std::fabs(c) * p.width_us;  // mA * us = nC
    const double balance_mA = std::fabs(c) * p.balance_scale();
    const double balance_nC = balance_mA * p.balance_width_us;
    f.peak_current_mA = std::max(f.peak_current_mA, std::max(std::fabs(c), balance_mA));
    f.charge_per_phase_nC.push_back(main_nC);
    f.max_charge_per_phase_nC = std::max(f.max_charge_per_phase_nC, main_nC);
    f.max_net_charge_nC = std::max(f.max_net_charge_nC, std::fabs(main_nC - balance_nC));
    // RMS over a period: main^2 * w + balance^2 * wb, over the period.
    const double ms =
        (c * c * p.width_us + balance_mA * balance_mA * p.balance_width_us) / p.period_us();
    f.rms_current_mA.push_back(std::sqrt(ms));
    f.max_rms_current_mA = std::max(f.max_rms_current_mA, std::sqrt(ms));
    f.mean_current_mA.push_back((main_nC + balance_nC) / p.period_us());
    f.max_mean_current_mA = std::max(f.max_mean_current_mA, f.mean_current_mA.back());
    sum_main += c;
  }
  f.max_instant_sum_mA = std::fabs(sum_main) * std::max(1.0, p.balance_scale());
  add_density(f, s.electrode_area_mm2);
  return f;
}

Json stimulus_to_json(const Stimulus& s) {
  Json j;
  j["format"] = "tactile-primaries/stimulus/1";
  j["channels"] = s.currents_mA.size();
  j["currents_mA"] = s.currents_mA;
  j["max_current_mA"] = s.max_current_mA;
  if (s.amplitude_mA > 0) j["amplitude_mA"] = s.amplitude_mA;
  if (s.shape.shaped())
    j["pulse"] = Json{{"phases", phases_to_json(s.shape.phases)},
                      {"frequency_hz", s.shape.frequency_hz}};
  else
    j["pulse"] = Json{{"width_us", s.shape.width_us},
                      {"interphase_us", s.shape.interphase_us},
                      {"balance_width_us", s.shape.balance_width_us},
                      {"frequency_hz", s.shape.frequency_hz}};
  j["count"] = s.count;
  j["duration_s"] = s.duration_s();
  j["electrode_area_mm2"] = s.electrode_area_mm2;
  if (!s.reference_impedance_kohm.empty()) {
    Json z = Json::array();
    for (double v : s.reference_impedance_kohm) z.push_back(v > 0 ? Json(v) : Json(nullptr));
    j["reference_impedance_kohm"] = z;
  }
  const SafetyFigures f = safety_figures(s);
  j["safety"] = Json{{"peak_current_mA", f.peak_current_mA},
                     {"charge_per_phase_nC", f.charge_per_phase_nC},
                     {"max_charge_density_uC_per_cm2", f.max_charge_density_uC_per_cm2},
                     {"rms_current_mA", f.rms_current_mA},
                     {"net_charge_per_pulse_nC", f.max_net_charge_nC},
                     {"max_instant_sum_mA", f.max_instant_sum_mA},
                     {"mean_current_mA", f.max_mean_current_mA},
                     {"shannon_k", f.shannon_k}};
  if (s.shape.shaped()) {
    j["safety"]["shortest_phase_us"] = f.shortest_phase_us;
    j["safety"]["level_unit"] = f.level_unit;
  }
  for (auto it = s.carried.begin(); it != s.carried.end(); ++it) j[it.key()] = it.value();
  return j;
}

namespace {
// reference_impedance_kohm: one per channel, each 0.01 to 100000 kOhm or null (0).
std::vector<double> reference_impedances(const Json& j, std::size_t channels) {
  if (!j.is_array() || j.size() != channels)
    bad_input("reference_impedance_kohm: expected a list of " + std::to_string(channels) +
              " impedances (kOhm, or null), one per channel");
  std::vector<double> z;
  for (std::size_t c = 0; c < j.size(); ++c) {
    if (j[c].is_null()) {
      z.push_back(0);
      continue;
    }
    const std::string what = "reference_impedance_kohm[" + std::to_string(c) + "]";
    z.push_back(json_finite(j[c], what));
    ranges::check(z.back(), ranges::impedance_kohm, what);
  }
  return z;
}
}  // namespace

Stimulus stimulus_from_json(const Json& j) {
  if (!j.is_object()) bad_input("stimulus: expected a JSON object");
  if (!j.contains("format") || j["format"] != "tactile-primaries/stimulus/1")
    bad_input("stimulus: 'format' must be \"tactile-primaries/stimulus/1\" (make-pulse's output)");
  Stimulus s;
  if (!j.contains("currents_mA") || !j["currents_mA"].is_array())
    bad_input("stimulus: missing 'currents_mA'");
  for (std::size_t i = 0; i < j["currents_mA"].size(); ++i)
    s.currents_mA.push_back(
        json_finite(j["currents_mA"][i], "currents_mA[" + std::to_string(i) + "]"));
  if (j.contains("channels") &&
      json_int(j["channels"], "channels") != static_cast<int>(s.currents_mA.size()))
    bad_input("stimulus: 'channels' disagrees with 'currents_mA'");
  if (!j.contains("pulse") || !j["pulse"].is_object()) bad_input("stimulus: missing 'pulse'");
  const Json& p = j["pulse"];
  auto field = [&](const char* k) {
    if (!p.contains(k)) bad_input(std::string("stimulus: missing pulse.") + k);
    return json_finite(p[k], std::string("pulse.") + k);
  };
  if (p.contains("phases")) {
    for (const char* k : {"width_us", "interphase_us", "balance_width_us"})
      if (p.contains(k))
        bad_input(std::string("stimulus: pulse: give phases or ") + k + ", not both");
    s.shape.phases = phases_from_json(p["phases"], "pulse.phases");
  } else {
    s.shape.width_us = field("width_us");
    s.shape.interphase_us = field("interphase_us");
    s.shape.balance_width_us = field("balance_width_us");
  }
  s.shape.frequency_hz = field("frequency_hz");
  if (!j.contains("count")) bad_input("stimulus: missing 'count'");
  s.count = json_int(j["count"], "count");
  if (j.contains("max_current_mA")) {  // the weights document's limit, in its range
    s.max_current_mA = json_finite(j["max_current_mA"], "max_current_mA");
    ranges::check(s.max_current_mA, ranges::max_current_mA, "max_current_mA");
  }
  if (j.contains("amplitude_mA")) {
    s.amplitude_mA = json_finite(j["amplitude_mA"], "amplitude_mA");
    if (!(s.amplitude_mA > 0 && s.amplitude_mA <= StimulusLimits{}.max_current_mA))
      bad_input(
          "amplitude_mA: " + number_beside(s.amplitude_mA, 0, StimulusLimits{}.max_current_mA) +
          " mA outside (0, 2] mA");
  }
  if (j.contains("electrode_area_mm2"))
    s.electrode_area_mm2 = json_finite(j["electrode_area_mm2"], "electrode_area_mm2");
  if (!(s.electrode_area_mm2 >= 1e-4 && s.electrode_area_mm2 <= 1e4))
    bad_input("electrode_area_mm2: " + number_beside(s.electrode_area_mm2, 1e-4, 1e4) +
              " mm2 outside [0.0001, 10000] mm2");
  if (j.contains("reference_impedance_kohm"))
    s.reference_impedance_kohm = reference_impedances(j["reference_impedance_kohm"], s.currents_mA.size());
  static const std::set<std::string> own = {
      "format", "channels",   "currents_mA",        "max_current_mA", "pulse",
      "count",  "duration_s", "electrode_area_mm2", "safety",         "amplitude_mA",
      "reference_impedance_kohm"};
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!own.count(it.key())) s.carried[it.key()] = it.value();
  return s;
}

std::vector<std::vector<double>> waveform_points(const Stimulus& s, long max_pulses) {
  std::vector<std::vector<double>> rows;
  const PulseShape& p = s.shape;
  const long n = std::min(s.count, max_pulses);
  auto row = [&](double t, double scale) {
    std::vector<double> r{t};
    for (double c : s.currents_mA) r.push_back(c * scale);
    rows.push_back(std::move(r));
  };
  for (long k = 0; k < n && p.shaped(); ++k) {
    double t = static_cast<double>(k) * p.period_us();
    row(t, 0.0);
    for (const Phase& ph : p.phases) {
      row(t, ph.level);
      row(t + ph.duration_us, ph.level);
      t += ph.duration_us;
    }
    row(t, 0.0);
  }
  for (long k = 0; k < n && !p.shaped(); ++k) {
    const double t0 = static_cast<double>(k) * p.period_us();
    const double t1 = t0 + p.width_us, t2 = t1 + p.interphase_us, t3 = t2 + p.balance_width_us;
    row(t0, 0.0);
    row(t0, 1.0);
    row(t1, 1.0);
    row(t1, 0.0);
    if (p.interphase_us > 0) row(t2, 0.0);
    row(t2, -p.balance_scale());
    row(t3, -p.balance_scale());
    row(t3, 0.0);
  }
  row(static_cast<double>(n) * p.period_us(), 0.0);
  return rows;
}

}  // namespace tp
