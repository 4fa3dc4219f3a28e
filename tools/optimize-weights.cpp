// optimize-weights: minimax electrode weights for the RA, SAI or PC mode (Eq. 32-34).
//
//   optimize-weights --mode SAI > sai-weights.json
//   optimize-weights --mode PC --electrodes 12 --pitch 0.75 | af-field --config - --summary

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "cli/array_options.hpp"
#include "cli/entry.hpp"
#include "cli/fibre_options.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "opt/threshold_objective.hpp"
#include "io/document.hpp"
#include "io/reports.hpp"
#include "model/ranges.hpp"
#include "opt/bank.hpp"
#include "opt/focus.hpp"
#include "opt/minimax.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Electrode weights that make one receptor fire first: minimise the largest off-target "
      "activating function over the target's (Kajimoto et al., Eq. 32-34), with Sum w = 0.\n"
      "Prints the project's JSON document (weights positive = cathodic, max |w| = 1 at the "
      "current limit), or one CSV row.",
      "optimize-weights"};
  tp::cli::ArrayOptions array;
  tp::cli::ModelOptions model;
  std::string mode, max_current, min_af, format = "json";
  int random_starts = 0, pattern_starts = 2;
  bool timing = false, certify = false, no_header = false, header_only = false;
  std::string objective = "af";
  tp::cli::FibreOptions fibre;
  int max_evaluations = 12;
  std::vector<std::string> at;
  std::string radius, spill;
  bool bank = false;
  int neighbourhood = 0;
  app.add_option("--mode", mode,
                 "Target receptor: RA, SAI or PC (any name in the receptor table); several, "
                 "comma-separated, with --format csv: one row each; with --bank, the modes of "
                 "the bank [every receptor's]")
      ->type_name("MODE");
  tp::cli::add_array_options(app, array,
                             "Document with array, model and receptors (JSON; - for stdin)");
  tp::cli::add_model_options(app, model);
  app.add_option("--max-current", max_current,
                 "Current limit per electrode, mA, at most 2 [the document's, or 2]")
      ->type_name("MA");
  app.add_option("--min-target-af", min_af,
                 "Trade selectivity for efficiency: the target's largest AF at the current limit "
                 "must reach this, V/ms [0: the paper's problem]")
      ->type_name("V/MS");
  tp::cli::add_integer(app, "--pattern-starts", pattern_starts,
                       "How many of the paper's patterns start the surrogate: anode, cathode, "
                       "cathode with anodic neighbours, widened cathode, 0 to 4 [2]",
                       0, 4)
      ->type_name("K");
  tp::cli::add_integer(app, "--random-starts", random_starts,
                       "Random starts besides the paper's patterns and the LP seeds, 0 to 1000 [0]",
                       0, 1000)
      ->type_name("K");
  app.add_option("--format", format, "Output: json or csv [json]")
      ->check(CLI::IsMember({"json", "csv"}));
  app.add_flag("--no-header", no_header, "CSV without its header row (for sweeps)");
  app.add_flag("--header-only", header_only,
               "Check the options and print the CSV header row only, computing nothing (for "
               "sweeps)")
      ->excludes("--no-header");
  app.add_flag("--timing", timing,
               "Add solver.time_s to the JSON (output is then not reproducible)");
  app.add_option("--objective", objective,
                 "af: the paper's problem, the activating function (default); threshold: then "
                 "minimise the threshold ratio from a fibre model (see --fibre-model), starting "
                 "from the AF optimum, never worse than it (JSON, one mode)")
      ->check(CLI::IsMember({"af", "threshold"}));
  auto* fibre_group = app.add_option_group("threshold objective");
  tp::cli::add_fibre_options(*fibre_group, fibre, "--fibre-model");
  tp::cli::add_integer(*fibre_group, "--max-evaluations", max_evaluations,
                       "Whole threshold searches, 10 to 10000 [12: about 3 s on 2 cores for the "
                       "paper's array; more polish by Nelder-Mead on whole searches, about 0.2 s "
                       "each]",
                       10, 10000);
  app.add_option("--at", at,
                 "A pixel: the target's largest AF at this place on the skin, X (a 1-D array) or "
                 "X,Z (a 2-D array), mm, within the array's extent plus one pitch; the target's AF "
                 "beyond --radius stays at most --spill of its peak")
      ->type_name("X[,Z]");
  app.add_option("--radius", radius,
                 "A pixel's radius, mm, beyond a quarter pitch, at most 1000 [one pitch]")
      ->type_name("MM");
  app.add_option("--spill", spill,
                 "A pixel's target's largest AF beyond the radius over its peak, in (0, 1] [0.3]")
      ->type_name("S");
  app.add_flag("--bank", bank,
               "A bank of pixels: every pad centre's (or every --at's, repeated) pattern of "
               "each mode, as one JSON document; symmetric and translated pixels derived, "
               "every pattern judged on the whole array");
  tp::cli::add_integer(app, "--neighbourhood", neighbourhood,
                       "With --bank on a grid: each pattern uses only the K x K pads centred on "
                       "its focus's pad (shifted to stay inside the grid), K odd, 3 to 255 [every "
                       "pad]",
                       3, 255)
      ->type_name("K");
  app.add_flag("--certify", certify,
               "Also solve the LP at every sampled target point and report the certified global "
               "optimum (slow: seconds)");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    tp::Document doc = tp::cli::load_document(array, 2);
    tp::cli::apply_model_options(doc, model);
    if (doc.setup.array.size() < 2)
      tp::bad_input("array: optimisation needs at least 2 electrodes");
    if (doc.setup.array.two_d())
      tp::cli::refuse_plane_z(doc, model,
                              "under a 2-D array (its fibres fill every z; the plane places "
                              "af-field's x-y section only)");
    if (doc.setup.array.two_d() && at.empty() && !bank)
      tp::bad_input("array: " + doc.setup.array.describe() +
                    " is 2-D: give a pixel's place, --at X,Z (or --bank)");
    if (mode.empty() && !bank) tp::bad_input("--mode: required (RA, SAI, PC, ...)");
    if ((!radius.empty() || !spill.empty()) && at.empty() && !bank)
      tp::bad_input("--radius, --spill: apply to a pixel (--at) or a bank (--bank)");
    if (app.count("--neighbourhood") && !bank) tp::bad_input("--neighbourhood: with --bank only");
    if (at.size() > 1 && !bank) tp::bad_input("--at: one place (several: with --bank)");
    tp::OptimizeOptions opt;
    if (!max_current.empty()) doc.max_current_mA = tp::parse_finite(max_current, "--max-current");
    tp::ranges::check(doc.max_current_mA, tp::ranges::max_current_mA, "--max-current");
    opt.max_current_mA = doc.max_current_mA;
    if (!min_af.empty()) opt.min_target_af = tp::parse_finite(min_af, "--min-target-af");
    if (!(opt.min_target_af <= 1e4))  // the paper's optima reach 0.8 to 6 V/ms
      tp::bad_input("--min-target-af: " + min_af + " V/ms outside [0, 10000] V/ms");
    if (opt.min_target_af < 0.0) tp::bad_input("--min-target-af: must be >= 0");
    opt.random_starts = random_starts;
    opt.pattern_starts = pattern_starts;

    // Several modes (CSV only) share one process: one row each, in the order given.
    std::vector<std::string> modes;
    for (std::size_t a = 0; !mode.empty();) {
      const std::size_t b = mode.find(',', a);
      modes.push_back(mode.substr(a, b == std::string::npos ? std::string::npos : b - a));
      if (modes.back().empty()) tp::bad_input("--mode: empty name in " + tp::quoted_text(mode));
      for (std::size_t k = 0; k + 1 < modes.size(); ++k)
        if (modes[k] == modes.back())
          tp::bad_input("--mode: " + tp::quoted_text(modes.back()) + " given twice");
      if (b == std::string::npos) break;
      a = b + 1;
    }
    for (const std::string& m : modes) tp::receptor_index(doc.setup, m);  // all before any work
    const bool by_threshold = objective == "threshold";
    if (modes.size() > 1 && format != "csv" && !bank && !by_threshold)  // threshold: below
      tp::bad_input("--mode: several modes need --format csv (one row each)");
    for (const char* flag :
         {"--fibre-model", "--stimulus", "--width", "--interphase", "--balance-width",
          "--monophasic", "--offsets", "--tolerance", "--threads", "--max-evaluations"})
      if (!by_threshold && app.count(flag) > 0 &&
          !((bank || !at.empty()) && std::string(flag) == "--threads"))
        tp::bad_input(std::string(flag) + ": applies to --objective threshold only" +
                      (std::string(flag) == "--threads" ? ", --at and --bank" : ""));
    // The pixel's places (--at, repeated with --bank), radius and spill.
    std::vector<std::pair<double, double>> places;
    for (const std::string& p : at) {
      const std::vector<double> xz = tp::parse_list(p, "--at");
      const bool two_d = doc.setup.array.two_d();
      if (xz.size() != (two_d ? 2u : 1u))
        tp::bad_input("--at: expected " +
                      std::string(two_d ? "X,Z (a 2-D array)" : "X (a 1-D array)") + ", got " +
                      tp::quoted_text(p));
      places.emplace_back(xz[0], two_d ? xz[1] : 0.0);
    }
    tp::FocusOptions focus;
    if (!radius.empty()) {
      focus.radius_mm = tp::parse_finite(radius, "--radius");
      if (!(focus.radius_mm > 0.0))
        tp::bad_input("--radius: must be > 0 mm (omit it for one pitch), got " + radius);
    }
    if (!spill.empty()) focus.spill = tp::parse_finite(spill, "--spill");
    focus.max_current_mA = opt.max_current_mA;
    if (bank) {
      if (by_threshold) tp::bad_input("--bank: designs by the AF objective only");
      if (certify) tp::bad_input("--certify: with --bank is not available yet");
      if (opt.min_target_af > 0) tp::bad_input("--min-target-af: does not apply with --bank");
      if (format != "json" || header_only || no_header)
        tp::bad_input("--bank: JSON output only (no --format csv, --header-only, --no-header)");
      if (app.count("--pattern-starts") || app.count("--random-starts"))
        tp::bad_input("--pattern-starts, --random-starts: do not apply with --bank");
      tp::BankOptions b;
      b.modes = modes;
      b.at = places;
      b.radius_mm = focus.radius_mm;
      b.spill = focus.spill;
      b.max_current_mA = focus.max_current_mA;
      b.neighbourhood = neighbourhood;
      b.threads = static_cast<unsigned>(app.count("--threads") ? fibre.threads : 0);
      tp::cli::ProgressLine progress("optimize-weights");  // on a terminal only
      if (progress.active())
        b.progress = [&](const tp::BankProgress& p) {
          progress.show(p.judged == 0 ? "bank " + std::to_string(p.solved) + " of " +
                                            std::to_string(p.problems) + " problems"
                                      : "bank " + std::to_string(p.judged) + " of " +
                                            std::to_string(p.patterns) + " patterns judged",
                        p.judged == 1);  // the second stage: shown as it starts
        };
      const tp::Bank result = tp::optimize_bank(doc.setup, b);
      progress.clear();
      const std::string text = tp::dump_json(tp::bank_to_json(doc, result, b));
      std::size_t infeasible = 0, broken = 0;
      for (const tp::BankPattern& p : result.patterns) {
        if (!p.feasible)
          ++infeasible;
        else if (!p.result.bounds_hold)
          ++broken;
      }
      std::fprintf(stderr,
                   "optimize-weights: bank of %zu pixels x %zu modes: %d solved, %zu derived, "
                   "%zu with no pattern, %zu breaking a bound on the whole array\n",
                   result.pixels.size(),
                   result.patterns.size() / std::max<std::size_t>(1, result.pixels.size()),
                   result.solves, result.patterns.size() - static_cast<std::size_t>(result.solves),
                   infeasible, broken);
      tp::cli::write_stdout(text);
      return;
    }
    if (by_threshold && (format != "json" || modes.size() > 1))
      tp::bad_input("--objective threshold: one mode, JSON output");
    if (by_threshold && certify)
      tp::bad_input("--certify: certifies the AF problem, not --objective threshold");
    if (by_threshold && opt.min_target_af > 0)
      tp::bad_input("--min-target-af: applies to the AF objective only");
    if (certify && format != "json")
      tp::bad_input("--certify: the certified optimum is reported in JSON only (--format json)");
    if (!places.empty()) {
      focus.x_mm = places[0].first;
      focus.z_mm = places[0].second;
      focus.threads = app.count("--threads") ? static_cast<unsigned>(fibre.threads)
                                             : std::max(1u, std::thread::hardware_concurrency());
      tp::check_focus(doc.setup, focus);
      if (by_threshold)
        tp::bad_input("--at: designs by the AF objective only, not --objective threshold");
      focus.certify = certify;
      if (opt.min_target_af > 0) tp::bad_input("--min-target-af: does not apply with --at");
      if (format != "csv" && modes.size() > 1)
        tp::bad_input("--at: several modes need --format csv (one row each)");
      if (format == "csv" && certify)
        tp::bad_input("--certify: the certified optimum is reported in JSON only");
      if (app.count("--pattern-starts") || app.count("--random-starts"))
        tp::bad_input(
            "--pattern-starts, --random-starts: do not apply with --at (the focus is "
            "solved by linear programming)");
      if (header_only) {  // the checks above, and no work
        if (format != "csv") tp::bad_input("--header-only: needs --format csv");
        tp::cli::write_stdout(tp::optimize_csv_header(doc.setup));
        return;
      }
      // The whole output first (a later mode may still fail), then the talk, then it.
      std::string text = format == "csv" && !no_header ? tp::optimize_csv_header(doc.setup) : "";
      std::string talk;
      for (const std::string& m : modes) {
        const tp::FocusResult r = tp::optimize_focus(doc.setup, m, focus);
        text += format == "csv" ? tp::focus_csv_row(doc.setup, r)
                                : tp::dump_json(tp::focus_result_to_json(doc, r, focus, timing));
        if (!r.least_norm)
          talk += "optimize-weights: warning: " + m +
                  ": the least-Sum-w^2 step did not converge; these are the LP's weights, optimal "
                  "but not the unique least-power ones\n";
        char line[320];
        std::snprintf(line, sizeof line,
                      "optimize-weights: %s pixel at %s, ratio %.6g, spill %.3g (at most %.3g "
                      "beyond %.3g mm), target AF %.4g V/ms at %.3g mA, %d rounds, %.3f s\n",
                      m.c_str(), at[0].c_str(), r.ratio, r.spill, focus.spill, r.radius_mm,
                      r.target_max_af, opt.max_current_mA, r.rounds, r.time_s);
        talk += line;
      }
      std::fputs(talk.c_str(), stderr);
      tp::cli::write_stdout(text);
      return;
    }
    if (header_only) {
      if (format != "csv") tp::bad_input("--header-only: needs --format csv");
      tp::cli::write_stdout(tp::optimize_csv_header(doc.setup));
      return;
    }

    if (by_threshold) {
      const tp::OptimizeResult r = tp::optimize_mode(doc.setup, modes[0], opt);
      const tp::cli::FibreSetup f = tp::cli::apply_fibre_options(fibre, r.weights);
      tp::fibre::ThresholdSearchOptions so;
      so.max_evaluations = static_cast<std::size_t>(max_evaluations);
      tp::cli::ProgressLine progress("optimize-weights");  // on a terminal only
      if (progress.active())
        so.progress = [&](std::size_t k) {
          progress.show("threshold search " + std::to_string(k) + " of at most " +
                        std::to_string(so.max_evaluations) + " whole searches");
        };
      const std::size_t target = tp::receptor_index(doc.setup, modes[0]);
      const tp::fibre::ThresholdOptimum t = tp::fibre::optimize_threshold(
          doc.setup, target, r.weights, *f.model, f.pulse, f.settings, so);
      progress.clear();
      tp::Document out = doc;
      out.weights = t.weights;
      std::vector<double> currents;
      for (double w : t.weights) currents.push_back(w * opt.max_current_mA);
      const tp::Summary s = tp::summarize(doc.setup, currents);
      out.extra.erase("thresholds");
      out.extra.erase("threshold_ratio");
      out.extra["mode"] = modes[0];
      out.extra["objective"] = "threshold";
      const auto af_ratio = tp::mode_ratio(s.peaks, modes[0]);
      out.extra["ratio"] = af_ratio ? tp::Json(*af_ratio) : tp::Json(nullptr);
      out.extra["currents_mA"] = currents;
      out.extra["thresholds"] = tp::fibre::thresholds_to_json(doc.setup, t.report);
      out.extra["threshold_ratio"] = tp::fibre::ratios_to_json(doc.setup, t.report);
      tp::Json start = tp::Json::object();
      start["weights"] = r.weights;
      start["ratio"] = r.ratio;
      start["threshold_ratio"] =
          t.start.ratios[target] ? tp::Json(*t.start.ratios[target]) : tp::Json(nullptr);
      start["threshold_mA"] = t.start.receptors[target].threshold_mA
                                  ? tp::Json(*t.start.receptors[target].threshold_mA)
                                  : tp::Json(nullptr);
      out.extra["af_optimum"] = start;
      tp::Json search = tp::Json::object();
      search["method"] =
          "Nelder-Mead over the zero-sum weights from the AF optimum, on linear stand-ins "
          "checked by whole searches, then on whole searches";
      search["evaluations"] = t.evaluations;
      search["rounds"] = t.rounds;
      search["improved"] = t.improved;
      out.extra["threshold_search"] = search;
      const std::string text = tp::dump_json(tp::document_to_json(out));
      std::fprintf(stderr, "optimize-weights: %s, AF ratio %.4g, %zu evaluations, %s, %s\n",
                   tp::fibre::threshold_search_summary(t, target, f.settings.max_mA).c_str(),
                   af_ratio ? *af_ratio : 0.0, t.evaluations, f.model->name(),
                   f.pulse.describe().c_str());
      tp::cli::write_stdout(text);
      return;
    }
    std::string out = format == "csv" && !no_header ? tp::optimize_csv_header(doc.setup) : "";
    std::string talk;
    for (const std::string& m : modes) {
      const tp::OptimizeResult r = tp::optimize_mode(doc.setup, m, opt);
      std::optional<double> certified;
      if (certify) {
        const double bound = opt.min_target_af > 0 ? opt.max_current_mA / opt.min_target_af : 0.0;
        certified = tp::certify_mode(doc.setup, m, opt.polish_step_mm, bound).optimum;
      }
      // The whole output first (it may still refuse), then the summary lines, then the output.
      out += format == "csv"
                 ? tp::optimize_csv_row(doc.setup, r)
                 : tp::dump_json(tp::optimize_result_to_json(doc, r, timing, certified));
      char line[256];
      std::snprintf(
          line, sizeof line,
          "optimize-weights: %s ratio %.6g, target AF %.4g V/ms at %.3g mA, %d starts, %.3f s\n",
          m.c_str(), r.ratio, r.target_max_af, opt.max_current_mA, r.starts, r.time_s);
      talk += line;
    }
    std::fputs(talk.c_str(), stderr);
    tp::cli::write_stdout(out);
  });
}
