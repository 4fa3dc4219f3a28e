// optimize-weights: minimax electrode weights for the RA, SAI or PC mode (Eq. 32-34).
//
//   optimize-weights --mode SAI > sai-weights.json
//   optimize-weights --mode PC --electrodes 12 --pitch 0.75 | af-field --config - --summary
//
// The flags fill an OptimizeRequest (lib/requests/optimize.hpp), which checks them and does
// the work; the program prints what it returns.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/array_options.hpp"
#include "cli/entry.hpp"
#include "cli/fibre_options.hpp"
#include "cli/progress.hpp"
#include "requests/optimize.hpp"

namespace {

struct Flags {
  tp::cli::ArrayOptions array;
  tp::cli::ModelOptions model;
  tp::OptimizeText text;  // --mode, the numbers, --at and the fibre's flags
  std::string format = "json";
  int random_starts = 0, pattern_starts = 2;
  bool timing = false, certify = false, no_header = false, header_only = false;
  std::string objective = "af";
  int max_evaluations = 12;
  int population = 30;
  std::uint64_t seed = 1;
  bool bank = false;
  int neighbourhood = 0;
};

// Declares the flags, bound to f.
void declare(CLI::App& app, Flags& f) {
  app.add_option("--mode", f.text.modes,
                 "Target receptor: RA, SAI or PC (any name in the receptor table); several, "
                 "comma-separated, with --format csv: one row each; with --bank, the modes of "
                 "the bank [every receptor's]")
      ->type_name("MODE");
  tp::cli::add_array_options(app, f.array,
                             "Document with array, model and receptors (JSON; - for stdin)");
  tp::cli::add_model_options(app, f.model);
  app.add_option("--max-current", f.text.max_current_mA,
                 "Current limit per electrode, mA, at most 2 [the document's, or 2]")
      ->type_name("MA");
  app.add_option("--min-target-af", f.text.min_target_af,
                 "Trade selectivity for efficiency: the target's largest AF at the current limit "
                 "must reach this, V/ms [0: the paper's problem]")
      ->type_name("V/MS");
  tp::cli::add_integer(app, "--pattern-starts", f.pattern_starts,
                       "How many of the paper's patterns start the surrogate: anode, cathode, "
                       "cathode with anodic neighbours, widened cathode, 0 to 4 [2]",
                       0, 4)
      ->type_name("K");
  tp::cli::add_integer(app, "--random-starts", f.random_starts,
                       "Random starts besides the paper's patterns and the LP seeds, 0 to 1000 [0]",
                       0, 1000)
      ->type_name("K");
  app.add_option("--format", f.format, "Output: json or csv [json]")
      ->check(CLI::IsMember({"json", "csv"}));
  app.add_flag("--no-header", f.no_header, "CSV without its header row (for sweeps)");
  app.add_flag("--header-only", f.header_only,
               "Check the options and print the CSV header row only, computing nothing (for "
               "sweeps)")
      ->excludes("--no-header");
  app.add_flag("--timing", f.timing,
               "Add solver.time_s to the JSON (output is then not reproducible)");
  app.add_option("--objective", f.objective,
                 "af: the paper's problem, the activating function (default); threshold: then "
                 "minimise the threshold ratio from a fibre model (see --fibre-model), starting "
                 "from the AF optimum, never worse than it (JSON, one mode); selectivity: the "
                 "weights and the pulse's shape that recruit the mode's afferents first in a "
                 "sampled population (docs/fibres.md), from the AF and threshold optima, never "
                 "worse than them (JSON, one mode; with --at, a pixel)")
      ->check(CLI::IsMember({"af", "threshold", "selectivity"}));
  auto* fibre_group = app.add_option_group("threshold and selectivity objectives");
  tp::cli::add_fibre_options(*fibre_group, f.text.fibre, "--fibre-model");
  tp::cli::add_integer(*fibre_group, "--max-evaluations", f.max_evaluations,
                       "Whole threshold searches, 10 to 10000 [12: about 3 s on 2 cores for the "
                       "paper's array; more polish by Nelder-Mead on whole searches, about 0.2 s "
                       "each]; --objective selectivity: populations scored, 10 to 1000 [40: "
                       "1 to 2 minutes on 2 cores for the paper's array]",
                       10, 10000);
  tp::cli::add_integer(*fibre_group, "--population", f.population,
                       "--objective selectivity: afferents of each class in the population the "
                       "design is scored on, 1 to 1000 [30]; --bank: afferents of each class "
                       "sampled about each mode's centre pixel, the modes' recruitment (their "
                       "colours for render-tactile's gamut) [none]",
                       1, 1000);
  tp::cli::add_seed(*fibre_group, "--seed", f.seed,
                    "--objective selectivity or --bank --population: the population's seed, "
                    "0 to 18446744073709551615 [1]; a design's held-out check is drawn with the "
                    "next");
  fibre_group
      ->add_option("--max-charge", f.text.max_charge_nC,
                   "--objective selectivity: the comfort bound on the charge per phase at the "
                   "current recruiting half the target, nC, up to 100000 [twice the AF "
                   "optimum's]")
      ->type_name("NC");
  app.add_option("--at", f.text.at,
                 "A pixel: the target's largest AF at this place on the skin, X (a 1-D array) or "
                 "X,Z (a 2-D array), mm, within the array's extent plus one pitch; the target's AF "
                 "beyond --radius stays at most --spill of its peak")
      ->type_name("X[,Z]");
  app.add_option("--radius", f.text.radius_mm,
                 "A pixel's radius, mm, beyond a quarter pitch, at most 1000 [one pitch]")
      ->type_name("MM");
  app.add_option("--spill", f.text.spill,
                 "A pixel's target's largest AF beyond the radius over its peak, in (0, 1] [0.3]")
      ->type_name("S");
  app.add_flag("--bank", f.bank,
               "A bank of pixels: every pad centre's (or every --at's, repeated) pattern of "
               "each mode, as one JSON document; symmetric and translated pixels derived, "
               "every pattern judged on the whole array");
  tp::cli::add_integer(app, "--neighbourhood", f.neighbourhood,
                       "With --bank on a grid: each pattern uses only the K x K pads centred on "
                       "its focus's pad (shifted to stay inside the grid), K odd, 3 to 255 [every "
                       "pad]",
                       3, 255)
      ->type_name("K");
  app.add_flag("--certify", f.certify,
               "Also solve the LP at every sampled target point and report the certified global "
               "optimum (slow: seconds)");
  tp::cli::add_output_option(app);
}

// The request of the flags given: the texts parsed by the library (bad input names the
// flag), the others as given.
tp::OptimizeRequest request_of(const CLI::App& app, const Flags& f) {
  tp::OptimizeRequest r;
  tp::parse_optimize_text(f.text, r);
  if (app.count("--pattern-starts")) r.pattern_starts = f.pattern_starts;
  if (app.count("--random-starts")) r.random_starts = f.random_starts;
  r.csv = f.format == "csv";
  r.header = !f.no_header;
  r.header_only = f.header_only;
  r.timing = f.timing;
  r.certify = f.certify;
  if (f.objective == "threshold") r.objective = tp::OptimizeObjective::threshold;
  if (f.objective == "selectivity") r.objective = tp::OptimizeObjective::selectivity;
  if (app.count("--population")) r.population = f.population;
  if (app.count("--seed")) r.seed = f.seed;
  r.fibre_model_given = app.count("--fibre-model") > 0;
  r.offsets_given = app.count("--offsets") > 0;
  if (app.count("--max-evaluations")) r.max_evaluations = f.max_evaluations;
  r.bank = f.bank;
  if (app.count("--neighbourhood")) r.neighbourhood = f.neighbourhood;
  if (app.count("--threads")) r.threads = f.text.fibre.threads;
  r.plane_z_given = !f.model.plane_z.empty();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Electrode weights that make one receptor fire first: minimise the largest off-target "
      "activating function over the target's (Kajimoto et al., Eq. 32-34), with Sum w = 0.\n"
      "Prints the project's JSON document (weights positive = cathodic, max |w| = 1 at the "
      "current limit), or one CSV row.",
      "optimize-weights"};
  Flags f;
  declare(app, f);
  return tp::cli::run(app, argc, argv, [&] {
    tp::Document doc = tp::cli::load_document(f.array, 2);
    tp::cli::apply_model_options(doc, f.model);
    tp::OptimizeRequest r = request_of(app, f);
    tp::cli::ProgressLine progress("optimize-weights");  // on a terminal only
    if (progress.active())
      r.progress = [&](const std::string& text, bool new_stage) { progress.show(text, new_stage); };
    const tp::OptimizeOutput out = tp::run_optimize(doc, r);
    progress.clear();
    std::string talk;  // the whole output first (it may still refuse), then the talk, then it
    for (const std::string& line : out.notes) talk += "optimize-weights: " + line + "\n";
    std::fputs(talk.c_str(), stderr);
    tp::cli::write_stdout(out.text);
  });
}
