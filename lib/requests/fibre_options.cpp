#include "requests/fibre_options.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/json.hpp"
#include "core/number.hpp"

namespace tp {

namespace {

// A value refused as the program refuses its flag's text when it is not finite.
void check_finite(const std::optional<double>& v, const std::string& flag) {
  if (v && !std::isfinite(*v)) parse_finite(std::isnan(*v) ? "nan" : *v > 0 ? "inf" : "-inf", flag);
}

// The checks the programs' command-line parser makes (CLI11's words, without its "(see
// --help)"): options that exclude each other, the integers' ranges, finite numbers.
void check_flags(const FibreOptions& o) {
  const bool st = !o.stimulus.empty();
  if (st && o.width_us) bad_input("--stimulus excludes --width");
  if (st && o.interphase_us) bad_input("--stimulus excludes --interphase");
  if (st && o.balance_width_us) bad_input("--stimulus excludes --balance-width");
  if (st && o.monophasic) bad_input("--stimulus excludes --monophasic");
  const bool ph = !o.phases.empty();
  if (st && ph) bad_input("--stimulus excludes --phases");
  if (ph && o.width_us) bad_input("--phases excludes --width");
  if (ph && o.interphase_us) bad_input("--phases excludes --interphase");
  if (ph && o.balance_width_us) bad_input("--phases excludes --balance-width");
  if (ph && o.monophasic) bad_input("--phases excludes --monophasic");
  if (o.monophasic && o.interphase_us) bad_input("--interphase excludes --monophasic");
  if (o.monophasic && o.balance_width_us) bad_input("--balance-width excludes --monophasic");
  if (!(o.offsets >= 1 && o.offsets <= 64))
    bad_input("--offsets: " + std::to_string(o.offsets) + " outside [1, 64]");
  if (o.threads != 0 && !(o.threads >= 1 && o.threads <= 256))
    bad_input("--threads: " + std::to_string(o.threads) + " outside [1, 256]");
  check_finite(o.width_us, "--width");
  check_finite(o.interphase_us, "--interphase");
  check_finite(o.balance_width_us, "--balance-width");
  check_finite(o.tolerance, "--tolerance");
}

// The stimulus document's pulse, when it is the weights times one amplitude and within
// every limit.
Stimulus checked_stimulus(const std::string& path, const std::vector<double>& weights) {
  Stimulus s = stimulus_from_json(read_json(path, "--stimulus"));
  check_stimulus(s, StimulusLimits{});
  if (s.currents_mA.size() != weights.size())
    bad_input("--stimulus: " + std::to_string(s.currents_mA.size()) +
              " channels, the weights have " + std::to_string(weights.size()));
  double amp = 0.0, wmax = 0.0;
  for (double c : s.currents_mA) amp = std::max(amp, std::fabs(c));
  for (double x : weights) wmax = std::max(wmax, std::fabs(x));
  if (!(amp > 0.0)) bad_input("--stimulus: every current is zero");
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (std::fabs(s.currents_mA[i] / amp - weights[i] / wmax) > 1e-6)
      bad_input("--stimulus: its currents are not the weights times one amplitude (channel " +
                std::to_string(i + 1) + ")");
  return s;
}

}  // namespace

FibreSetup apply_fibre_options(const FibreOptions& o, const std::vector<double>& weights) {
  check_flags(o);
  FibreSetup f;
  const auto& known = fibre::fibre_models();
  if (std::find(known.begin(), known.end(), o.model) == known.end())
    bad_input(o.model_flag + ": unknown fibre model " + quoted_text(o.model) + " (mrg or senn)");
  f.model = fibre::make_fibre_model(o.model);
  f.settings.geometry = fibre::geometry_from_string(o.geometry);
  if (!o.stimulus.empty()) {
    f.stimulus = checked_stimulus(o.stimulus, weights);
    f.pulse = tp::pulse_of(f.stimulus->shape);
  } else if (!o.phases.empty()) {
    f.pulse.phases = o.phases;
  } else if (o.carried_pulse && !o.width_us && !o.interphase_us && !o.balance_width_us &&
             !o.monophasic) {
    f.pulse = *o.carried_pulse;
  } else {
    if (o.width_us) f.pulse.width_us = *o.width_us;
    f.pulse.balance_width_us = o.balance_width_us ? *o.balance_width_us : f.pulse.width_us;
    if (o.interphase_us) f.pulse.interphase_us = *o.interphase_us;
    f.pulse.monophasic = o.monophasic;
    if (o.monophasic) f.pulse.balance_width_us = f.pulse.width_us;
  }
  tp::check_pulse(f.pulse);
  f.settings.offsets = static_cast<std::size_t>(o.offsets);
  if (o.tolerance) {
    f.settings.tolerance = *o.tolerance;
    if (!(f.settings.tolerance >= 1e-4 && f.settings.tolerance <= 0.1))
      bad_input("--tolerance: " +
                (o.tolerance_text.empty() ? number_beside(*o.tolerance, 1e-4, 0.1)
                                          : o.tolerance_text) +
                " outside [0.0001, 0.1]");
  }
  f.settings.threads = static_cast<unsigned>(o.threads);
  return f;
}

FibreOptions fibre_values(const FibreText& t) {
  FibreOptions v;
  v.model = t.model;
  v.geometry = t.geometry;
  v.stimulus = t.stimulus;
  if (!t.width.empty()) v.width_us = parse_finite(t.width, "--width");
  if (!t.balance_width.empty()) v.balance_width_us = parse_finite(t.balance_width, "--balance-width");
  if (!t.interphase.empty()) v.interphase_us = parse_finite(t.interphase, "--interphase");
  v.monophasic = t.monophasic;
  if (!t.phases.empty()) v.phases = phases_from_text(t.phases, "--phases");
  v.offsets = t.offsets;
  if (!t.tolerance.empty()) v.tolerance = parse_finite(t.tolerance, "--tolerance");
  v.tolerance_text = t.tolerance;
  v.threads = t.threads;
  v.model_flag = t.model_flag;
  return v;
}

}  // namespace tp
