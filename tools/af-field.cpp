// af-field: the activating function of a weighted electrode array, on a grid (CSV), over a
// plane at one depth under a 2-D array (CSV), or summarised per receptor with the three
// mode ratios (JSON).
//
//   af-field --electrodes 8 --pitch 1 --weights 0,0,-1,2,-1,0,0,0 > field.csv
//   optimize-weights --mode SAI | af-field --config - --summary
//   af-field --grid 8x8 --pitch 2 --plane-depth 0.9 > plane.csv

#include <cstdio>
#include <string>

#include "cli/array_options.hpp"
#include "cli/entry.hpp"
#include "core/error.hpp"
#include "io/document.hpp"
#include "io/reports.hpp"
#include "core/ranges.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Activating function (AF) of an electrode array on the skin (Kajimoto et al., "
      "Eq. 14-25).\nx runs along the skin, y is depth (mm, y > 0), z across (a 2-D array's "
      "rows); a positive weight is cathodic; AF > 0 depolarises.\nCSV columns: "
      "x_mm,y_mm,af_h,af_v (V/ms, myelinated 10 um fibres, horizontal along x and vertical); "
      "with --plane-depth, x_mm,z_mm,af_h,af_v.",
      "af-field"};
  tp::cli::ArrayOptions array;
  std::string weights, x_spec, y_spec, z_spec, plane_depth, amplitude;
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
  app.add_option("--plane-depth", plane_depth,
                 "3-D models: the AF over the x-z plane at this depth, mm, 0.01 to 20 (CSV "
                 "x_mm,z_mm,af_h,af_v) instead of the x-y grid")
      ->type_name("MM");
  app.add_option("--z-grid", z_spec,
                 "With --plane-depth: grid across MIN:MAX:STEP, mm, within +-500 [the pads' "
                 "centres +-5 mm, step 0.1]")
      ->type_name("MIN:MAX:STEP");
  app.add_flag("--summary", summary, "Print each receptor's largest AF and the mode ratios (JSON)");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    tp::Document doc = tp::cli::load_document(array, 1);
    if (!weights.empty()) doc.weights = tp::parse_list(weights, "--weights");
    tp::cli::apply_model_options(doc, model);
    if (!doc.weights) {
      // Default pattern: one cathode at the electrode nearest the centre.
      doc.weights = std::vector<double>(doc.setup.array.size(), 0.0);
      (*doc.weights)[doc.setup.array.centre_index()] = 1.0;
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

    if (summary && (!x_spec.empty() || !y_spec.empty() || !plane_depth.empty()))
      tp::bad_input("--summary: --x, --y and --plane-depth do not apply");
    if (!z_spec.empty() && plane_depth.empty())
      tp::bad_input("--z-grid: applies with --plane-depth only");
    if (summary && doc.setup.array.two_d())
      tp::cli::refuse_plane_z(doc, model,
                              "to --summary under a 2-D array (its fibres fill every z; the "
                              "plane places af-field's x-y section only)");
    if (!plane_depth.empty()) {
      if (!y_spec.empty()) tp::bad_input("--y: does not apply with --plane-depth (one depth)");
      tp::cli::refuse_plane_z(doc, model,
                              "with --plane-depth (a plane at one depth, over every z)");
      const double depth = tp::parse_finite(plane_depth, "--plane-depth");
      tp::ranges::check(depth, tp::ranges::depth_mm, "--plane-depth");
      const tp::Axis x =
          x_spec.empty() ? tp::default_x_axis(doc.setup.array) : tp::parse_axis(x_spec, "--x");
      const tp::Axis z =
          z_spec.empty() ? tp::default_z_axis(doc.setup.array) : tp::parse_axis(z_spec, "--z-grid");
      tp::validate_plane(x, z, depth);
      tp::check_grid_work(static_cast<double>(x.count()) * static_cast<double>(z.count()),
                          doc.setup.array.size());
      tp::check_model_depth(doc.setup, depth, "--plane-depth");
      const tp::Field field(doc.setup, currents_mA);
      if (!field.conductor().three_d())
        tp::bad_input(
            "--plane-depth: " + doc.setup.conductor.model +
            " does not evaluate points off the fibres' plane; use point3d, rect3d or layered");
      tp::check_plane(doc.setup, field.conductor(), x, z, depth);  // before the first row
      tp::write_af_plane(tp::cli::write_stdout, field, x, z, depth);
      return;
    }
    const tp::Axis x =
        x_spec.empty() ? tp::default_x_axis(doc.setup.array) : tp::parse_axis(x_spec, "--x");
    const tp::Axis y = y_spec.empty() ? tp::default_y_axis() : tp::parse_axis(y_spec, "--y");
    if (!summary) {  // every check before the first row is written
      tp::validate_grid(x, y);
      tp::check_grid_work(static_cast<double>(x.count()) * static_cast<double>(y.count()),
                          doc.setup.array.size());
      tp::check_model_depth(doc.setup, y.at(y.count() - 1), "--y: the deepest row,");
    }
    const tp::Field field(doc.setup, currents_mA);
    if (!summary) tp::check_grid(doc.setup, field.conductor(), x, y);  // before the first row
    if (summary) {
      const tp::Summary s = tp::summarize(doc.setup, currents_mA);
      tp::cli::write_stdout(tp::dump_json(tp::summary_to_json(doc.setup, currents_mA, s)));
      return;
    }
    tp::write_af_grid(tp::cli::write_stdout, field, x, y);
  });
}
