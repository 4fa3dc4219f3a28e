// fiber-threshold: the current at which each receptor's fibre fires, from a nonlinear
// myelinated-fibre model (MRG or SENN) in the conductor's field, and the threshold
// selectivity of the weight pattern.
//
//   optimize-weights --mode SAI | fiber-threshold > sai-thresholds.json
//   optimize-weights --mode SAI | fiber-threshold --strength-duration > sd.csv

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "cli/array_options.hpp"
#include "cli/entry.hpp"
#include "cli/fibre_options.hpp"
#include "cli/progress.hpp"
#include "fibre/population.hpp"
#include "io/document.hpp"
#include "core/files.hpp"
#include "core/json.hpp"
#include "requests/threshold.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Thresholds in mA: the current on an electrode of |weight| = 1 at which each receptor's "
      "fibre fires, from a compartmental myelinated-fibre model (MRG or SENN) driven by the "
      "conductor's potential, for the whole pulse waveform.\nPrints the weights document with "
      "\"thresholds\" (per receptor: threshold_mA, where the action potential started) and "
      "\"threshold_ratio\" (threshold over the lowest other receptor's: below 1, that receptor "
      "fires first); or, with --strength-duration, a CSV table.",
      "fiber-threshold"};
  tp::cli::ArrayOptions array;
  tp::cli::ModelOptions conductor;
  conductor.flag = "--conductor";
  tp::ThresholdText typed;
  std::string recruitment;
  long population = 0;
  std::uint64_t seed = 1;
  bool sd = false;
  auto* o_config = tp::cli::add_array_options(
      app, array, "Weights document (optimize-weights' JSON; - for stdin) [stdin]");
  auto* o_w = app.add_option("--weights", typed.weights,
                             "Comma-separated weights, one per electrode (positive = cathodic), "
                             "instead of a document")
                  ->type_name("W1,W2,...");
  o_config->excludes(o_w);
  tp::cli::add_model_options(app, conductor);
  tp::cli::add_fibre_options(app, typed.fibre, "--model");
  app.add_option("--at", typed.at,
                 "2-D arrays: the point X,Z (mm) the fibres pass through [the document's "
                 "focus, optimize-weights --at]")
      ->type_name("X,Z");
  tp::cli::add_integer(
      app, "--population", population,
      "N afferents of each class sampled over the array and its margin (diameters, depths and "
      "densities: docs/fibres.md), each its own threshold: CSV class,x_mm,offset_mm,depth_mm,"
      "diameter_um,threshold_mA; 1 to 10000, and no more fibre simulation than the work bound "
      "allows (refused before any work: about 7500 on the paper's 8-electrode array with a "
      "200 us pulse, fewer with longer pulses, more electrodes or a finer --tolerance)",
      1L, tp::fibre::kMaxPopulation);
  tp::cli::add_seed(app, "--seed", seed,
                    "--population: the sampling's seed, 0 to 18446744073709551615 (2^64 - 1) [1]");
  app.add_option("--recruitment", recruitment,
                 "--population: write the recruitment curves (each class's fraction recruited "
                 "against current, and each mode's selectivity index) as CSV to FILE")
      ->type_name("FILE");
  app.add_flag("--strength-duration", sd,
               "Print a strength-duration table (CSV: receptor,width_us,threshold_mA,charge_nC,"
               "rheobase_mA,chronaxie_us; rheobase and chronaxie from Weiss's law)");
  app.add_option("--widths", typed.widths,
                 "--strength-duration: main phase widths, us, 1 to 10000 "
                 "[20,50,100,200,500,1000,2000]")
      ->type_name("US1,US2,...");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    typed.config = array.config;
    typed.skin = conductor.skin;
    tp::cli::ArrayOptions source = array;
    source.config = tp::threshold_document_source(typed);
    tp::Document doc = tp::cli::load_document(source, 1);
    tp::ThresholdRequest r;
    r.conductor = conductor;
    r.strength_duration = sd;
    tp::parse_threshold_text(typed, doc, r);
    if (app.count("--population")) r.population = population;
    if (app.count("--seed")) r.seed = seed;
    r.recruitment = recruitment;
    const tp::ThresholdPlan plan = tp::plan_thresholds(std::move(doc), r);

    // The curves: a temporary beside the file from now (an unwritable place refused before
    // any work), renamed over it once the table too is written; else the file left as it was.
    std::optional<tp::AtomicFile> curves;
    if (!recruitment.empty()) curves.emplace(recruitment, "--recruitment");
    tp::cli::ProgressLine progress("fiber-threshold");  // on a terminal only
    tp::ThresholdProgress shown;
    if (progress.active())
      shown = [&](const std::string& text, bool new_stage) { progress.show(text, new_stage); };
    const tp::ThresholdOutput out = tp::run_thresholds(plan, shown);
    progress.clear();
    for (const std::string& line : out.notes) std::fprintf(stderr, "fiber-threshold: %s\n", line.c_str());
    if (out.document) {
      tp::cli::write_stdout(tp::dump_json(*out.document));
      return;
    }
    if (curves) curves->write(out.recruitment);
    tp::cli::write_stdout(out.table);
    if (curves) curves->commit();
  });
}
