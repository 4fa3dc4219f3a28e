#include "cli/fibre_options.hpp"

#include <algorithm>
#include <cmath>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "io/number.hpp"

namespace tp::cli {

void add_fibre_options(CLI::App& app, FibreOptions& o, const std::string& model_flag) {
  o.model_flag = model_flag;
  app.add_option(model_flag, o.model,
                 "Fibre model: mrg (McIntyre-Richardson-Grill 2002, 37 C, 2 to 16 um) or senn "
                 "(McNeal 1976 / Reilly, Frankenhaeuser-Huxley nodes, 20 C, 1 to 30 um) [mrg]")
      ->type_name("NAME");
  app.add_option("--geometry", o.geometry,
                 "Vertical (RA) fibres: straight (the paper's: a sealed node at the receptor's "
                 "top, straight down) or afferent (an ending, a heminode, short internodes, "
                 "a bend into a horizontal stem at the bottom of the receptor's range: "
                 "docs/fibres.md) [straight]")
      ->type_name("NAME");
  auto* st = app.add_option("--stimulus", o.stimulus,
                            "Stimulus document (make-pulse's output; - for stdin): its pulse "
                            "shape, and its amplitude in units of each threshold")
                 ->type_name("FILE");
  auto* w =
      app.add_option("--width", o.width, "Main phase width, us, 1 to 10000 [200]")->type_name("US");
  auto* g = app.add_option("--interphase", o.interphase, "Gap between the phases, us [0]")
                ->type_name("US");
  auto* b = app.add_option("--balance-width", o.balance_width,
                           "Balancing phase width, us; its current is main x width / this "
                           "[= --width: symmetric]")
                ->type_name("US");
  auto* m = app.add_flag("--monophasic", o.monophasic,
                         "Main phase only (for analysis: not charge-balanced, so never delivered)");
  st->excludes(w)->excludes(g)->excludes(b)->excludes(m);
  m->excludes(g)->excludes(b);
  add_integer(app, "--offsets", o.offsets,
              "Horizontal fibres: node alignments tried, spread over one internode, 1 to 64 [8]", 1,
              64)
      ->type_name("K");
  app.add_option("--tolerance", o.tolerance,
                 "Relative resolution of the thresholds, 1e-4 to 0.1 [0.001]")
      ->type_name("REL");
  add_integer(app, "--threads", o.threads, "Threads, 1 to 256 [every core]", 1, 256);
}

FibreSetup apply_fibre_options(const FibreOptions& o, const std::vector<double>& weights) {
  FibreSetup f;
  const auto& known = fibre::fibre_models();
  if (std::find(known.begin(), known.end(), o.model) == known.end())
    bad_input(o.model_flag + ": unknown fibre model " + quoted_text(o.model) + " (mrg or senn)");
  f.model = fibre::make_fibre_model(o.model);
  f.settings.geometry = fibre::geometry_from_string(o.geometry);
  if (!o.stimulus.empty()) {
    Stimulus s = stimulus_from_json(read_json(o.stimulus, "--stimulus"));
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
    f.pulse = fibre::pulse_of(s.shape);
    f.stimulus = std::move(s);
  } else {
    if (!o.width.empty()) f.pulse.width_us = parse_finite(o.width, "--width");
    f.pulse.balance_width_us = o.balance_width.empty()
                                   ? f.pulse.width_us
                                   : parse_finite(o.balance_width, "--balance-width");
    if (!o.interphase.empty()) f.pulse.interphase_us = parse_finite(o.interphase, "--interphase");
    f.pulse.monophasic = o.monophasic;
    if (o.monophasic) f.pulse.balance_width_us = f.pulse.width_us;
  }
  fibre::check_pulse(f.pulse);
  f.settings.offsets = static_cast<std::size_t>(o.offsets);
  if (!o.tolerance.empty()) {
    f.settings.tolerance = parse_finite(o.tolerance, "--tolerance");
    if (!(f.settings.tolerance >= 1e-4 && f.settings.tolerance <= 0.1))
      bad_input("--tolerance: " + o.tolerance + " outside [0.0001, 0.1]");
  }
  f.settings.threads = static_cast<unsigned>(o.threads);
  return f;
}

}  // namespace tp::cli
