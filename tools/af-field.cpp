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
#include "requests/field.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Activating function (AF) of an electrode array on the skin (Kajimoto et al., "
      "Eq. 14-25).\nx runs along the skin, y is depth (mm, y > 0), z across (a 2-D array's "
      "rows); a positive weight is cathodic; AF > 0 depolarises.\nCSV columns: "
      "x_mm,y_mm,af_h,af_v (V/ms, myelinated 10 um fibres, horizontal along x and vertical); "
      "with --plane-depth, x_mm,z_mm,af_h,af_v.",
      "af-field"};
  tp::AfFieldRequest r;
  auto* o_config = tp::cli::add_array_options(
      app, r.array, "Document with array, model, receptors and weights (JSON; - for stdin)");
  auto* o_w = app.add_option("--weights", r.weights,
                             "Comma-separated weights, one per electrode (positive = cathodic) "
                             "[one cathode on the centre electrode]")
                  ->type_name("W1,W2,...");
  o_config->excludes(o_w);
  app.add_option("--amplitude", r.amplitude,
                 "Current of an electrode with |weight| = 1, mA, 1e-6 to 100 [the document's "
                 "max_current_mA, 2]")
      ->type_name("MA");
  tp::cli::add_model_options(app, r.model);
  app.add_option("--x", r.x,
                 "Grid along the skin MIN:MAX:STEP, mm, within +-500 [array +-5 mm, step 0.1]; at "
                 "most 1e8 points in all")
      ->type_name("MIN:MAX:STEP");
  app.add_option("--y", r.y, "Grid in depth MIN:MAX:STEP, mm, within 0.01 to 20 [0.2:3:0.05]")
      ->type_name("MIN:MAX:STEP");
  app.add_option("--plane-depth", r.plane_depth,
                 "3-D models: the AF over the x-z plane at this depth, mm, 0.01 to 20 (CSV "
                 "x_mm,z_mm,af_h,af_v) instead of the x-y grid")
      ->type_name("MM");
  app.add_option("--z-grid", r.z,
                 "With --plane-depth: grid across MIN:MAX:STEP, mm, within +-500 [the pads' "
                 "centres +-5 mm, step 0.1]")
      ->type_name("MIN:MAX:STEP");
  app.add_flag("--summary", r.summary,
               "Print each receptor's largest AF and the mode ratios (JSON)");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    const tp::Document doc = tp::af_field_document(r);
    const tp::AfFieldPlan plan = tp::plan_af_field(doc, r);
    tp::run_af_field(doc, plan, tp::cli::write_stdout);
  });
}
