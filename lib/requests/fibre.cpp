#include "requests/fibre.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "io/number.hpp"
#include "requests/checks.hpp"

namespace tp {

namespace {

// The pulse of the widths and gap (the stimulus excludes them, and a monophasic pulse has
// neither gap nor balancing phase: the programs' parser refuses those pairs in its words).
fibre::PulseSpec pulse_of_widths(const FibreRequest& r) {
  if (r.monophasic && r.interphase_us) bad_input("--interphase excludes --monophasic");
  if (r.monophasic && r.balance_width_us) bad_input("--balance-width excludes --monophasic");
  fibre::PulseSpec p;
  if (r.width_us) p.width_us = *r.width_us;
  p.balance_width_us = r.balance_width_us ? *r.balance_width_us : p.width_us;
  if (r.interphase_us) p.interphase_us = *r.interphase_us;
  p.monophasic = r.monophasic;
  if (r.monophasic) p.balance_width_us = p.width_us;
  return p;
}

}  // namespace

FibreSetup fibre_setup(const FibreRequest& r) {
  check_finite("--width", r.width_us);
  check_finite("--interphase", r.interphase_us);
  check_finite("--balance-width", r.balance_width_us);
  check_finite("--tolerance", r.tolerance);
  if (r.stimulus && r.width_us) bad_input("--stimulus excludes --width");
  if (r.stimulus && r.interphase_us) bad_input("--stimulus excludes --interphase");
  if (r.stimulus && r.balance_width_us) bad_input("--stimulus excludes --balance-width");
  if (r.stimulus && r.monophasic) bad_input("--stimulus excludes --monophasic");
  FibreSetup f;
  const std::string model = r.model.value_or("mrg");
  const auto& known = fibre::fibre_models();
  if (std::find(known.begin(), known.end(), model) == known.end())
    bad_input(r.model_flag + ": unknown fibre model " + quoted_text(model) + " (mrg or senn)");
  f.model = fibre::make_fibre_model(model);
  f.settings.geometry = fibre::geometry_from_string(r.geometry);
  if (r.stimulus) {
    check_stimulus(*r.stimulus, StimulusLimits{});
    f.pulse = fibre::pulse_of(r.stimulus->shape);
    f.stimulus = r.stimulus;
  } else {
    f.pulse = pulse_of_widths(r);
  }
  fibre::check_pulse(f.pulse);
  const int offsets = r.offsets.value_or(8);
  check_whole("--offsets", offsets, 1, 64);
  f.settings.offsets = static_cast<std::size_t>(offsets);
  if (r.tolerance) {
    f.settings.tolerance = *r.tolerance;
    if (!(f.settings.tolerance >= 1e-4 && f.settings.tolerance <= 0.1))
      bad_input("--tolerance: " + number_beside(*r.tolerance, 1e-4, 0.1) +
                " outside [0.0001, 0.1]");
  }
  if (r.threads) check_whole("--threads", *r.threads, 1, 256);
  f.settings.threads = static_cast<unsigned>(r.threads.value_or(0));
  return f;
}

void check_stimulus_weights(const FibreSetup& f, const std::vector<double>& weights) {
  if (!f.stimulus) return;
  const Stimulus& s = *f.stimulus;
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
}

}  // namespace tp
