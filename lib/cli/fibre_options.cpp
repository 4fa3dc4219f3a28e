#include "cli/fibre_options.hpp"

#include "cli/entry.hpp"

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
  auto* ph = app.add_option("--phases", o.phases,
                            "A shaped pulse: up to 16 phases DURATION_US:LEVEL, level x the "
                            "amplitude (+1: cathodic), e.g. 500:0.1,200:1,700:-0.5 (simulated as "
                            "given: balanced or not)")
                 ->type_name("D:L,...");
  st->excludes(w)->excludes(g)->excludes(b)->excludes(m)->excludes(ph);
  m->excludes(g)->excludes(b)->excludes(ph);
  ph->excludes(w)->excludes(g)->excludes(b);
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
  return tp::apply_fibre_options(fibre_values(o), weights);
}

}  // namespace tp::cli
