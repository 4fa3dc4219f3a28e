// af-field: the activating function of a weighted line-electrode array, on a grid (CSV)
// or summarised per receptor with the three mode ratios (JSON).
//
//   af-field --electrodes 8 --pitch 1 --weights 0,0,-1,2,-1,0,0,0 > field.csv
//   optimize-weights --mode SAI | af-field --config - --summary

#include <cstdio>
#include <string>

#include "cli/array_options.hpp"
#include "cli/entry.hpp"
#include "core/error.hpp"
#include "io/document.hpp"
#include "io/reports.hpp"
#include "model/ranges.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Activating function (AF) of a line-electrode array on the skin (Kajimoto et al., "
      "Eq. 14-25).\nx runs along the skin, y is depth (mm, y > 0); a positive weight is "
      "cathodic; AF > 0 depolarises.\nCSV columns: x_mm,y_mm,af_h,af_v (V/ms, myelinated "
      "10 um fibres, horizontal and vertical).",
      "af-field"};
  tp::cli::ArrayOptions array;
  std::string weights, x_spec, y_spec, amplitude;
  tp::cli::ModelOptions model;
  bool summary = false;
  auto* o_config = tp::cli::add_array_options(
      app, array, "Document with array, model, receptors and weights (JSON; - for stdin)");
  auto* o_w = app.add_option("--weights", weights,
                             "Comma-separated weights, one per electrode (positive = cathodic) "
                             "[one cathode on the centre electrode]")
                  ->type_name("W1,W2,...");
  o_config->excludes(o_w);
  app.add_option("--amplitude", amplitude,
                 "Current of an electrode with |weight| = 1, mA, 1e-6 to 100 [the document's "
                 "max_current_mA, 2]")
      ->type_name("MA");
  tp::cli::add_model_options(app, model);
  app.add_option("--x", x_spec,
                 "Grid along the skin MIN:MAX:STEP, mm, within +-500 [array +-5 mm, step 0.1]; at "
                 "most 1e8 points in all")
      ->type_name("MIN:MAX:STEP");
  app.add_option("--y", y_spec, "Grid in depth MIN:MAX:STEP, mm, within 0.01 to 20 [0.2:3:0.05]")
      ->type_name("MIN:MAX:STEP");
  app.add_flag("--summary", summary, "Print each receptor's largest AF and the mode ratios (JSON)");

  return tp::cli::run(app, argc, argv, [&] {
    tp::Document doc = tp::cli::load_document(array, 1);
    if (!weights.empty()) doc.weights = tp::parse_list(weights, "--weights");
    tp::cli::apply_model_options(doc, model);
    if (!doc.weights) {
      // Default pattern: one cathode at the electrode nearest the centre.
      doc.weights = std::vector<double>(doc.setup.array.size(), 0.0);
      (*doc.weights)[(doc.setup.array.size() - 1) / 2] = 1.0;
    }
    if (doc.weights->size() != doc.setup.array.size())
      tp::bad_input("--weights: expected " + std::to_string(doc.setup.array.size()) +
                    " values (one per electrode), got " + std::to_string(doc.weights->size()));
    const double amp =
        amplitude.empty() ? doc.max_current_mA : tp::parse_finite(amplitude, "--amplitude");
    tp::ranges::check(amp, tp::ranges::amplitude_mA, "--amplitude");
    for (std::size_t i = 0; i < doc.weights->size(); ++i)
      tp::ranges::check((*doc.weights)[i], tp::ranges::weight,
                        "--weights item " + std::to_string(i + 1));
    std::vector<double> currents_mA;
    for (double w : *doc.weights) currents_mA.push_back(w * amp);

    if (summary && (!x_spec.empty() || !y_spec.empty()))
      tp::bad_input("--summary: --x and --y do not apply");
    const tp::Axis x =
        x_spec.empty() ? tp::default_x_axis(doc.setup.array) : tp::parse_axis(x_spec, "--x");
    const tp::Axis y = y_spec.empty() ? tp::default_y_axis() : tp::parse_axis(y_spec, "--y");
    if (!summary) {  // every check before the first row is written
      tp::validate_grid(x, y);
      tp::check_model_depth(doc.setup, y.at(y.count() - 1), "--y: the deepest row,");
    }
    const tp::Field field(doc.setup, currents_mA);
    if (!summary) tp::check_grid(doc.setup, field.conductor(), x, y);  // before the first row
    if (summary) {
      const tp::Summary s = tp::summarize(doc.setup, currents_mA);
      tp::cli::write_stdout(tp::dump_json(tp::summary_to_json(doc.setup, currents_mA, s)));
      return;
    }
    tp::write_af_grid(stdout, field, x, y);
  });
}
