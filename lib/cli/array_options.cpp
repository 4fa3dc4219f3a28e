#include "cli/array_options.hpp"

namespace tp::cli {

CLI::Option* add_array_options(CLI::App& app, ArrayOptions& o, const std::string& config_help) {
  auto* config = app.add_option("--config", o.config, config_help)->type_name("FILE");
  auto* n = app.add_option("--electrodes", o.electrodes,
                           "Number of electrodes of a uniform array, 1 to 64 [8]")
                ->type_name("N");
  auto* pitch =
      app.add_option("--pitch", o.pitch, "Electrode pitch (a grid's along x), mm, 0.01 to 100 [1]")
          ->type_name("MM");
  auto* grid = app.add_option("--grid", o.grid,
                              "A 2-D grid of COLUMNSxROWS pads (columns along x, rows along z, "
                              "at most 256 pads), centred on (0, 0); the rect3d model unless "
                              "--model says otherwise")
                   ->type_name("CxR");
  auto* row_pitch =
      app.add_option("--row-pitch", o.row_pitch, "A grid's pitch along z, mm [--pitch]")
          ->type_name("MM");
  auto* pad =
      app.add_option("--pad", o.pad, "A grid's pads, WIDTHxLENGTH (x by z), mm [half the pitches]")
          ->type_name("WxL");
  config->excludes(n)->excludes(pitch)->excludes(grid)->excludes(row_pitch)->excludes(pad);
  n->excludes(grid)->excludes(row_pitch)->excludes(pad);
  return config;
}

void add_model_options(CLI::App& app, ModelOptions& o) {
  app.add_option(o.flag, o.model,
                 "Conductor model: line2d (the paper's), strip2d, point3d or rect3d (3-D, "
                 "half-space), layered (3-D, layered skin) [the document's, or line2d]")
      ->type_name("NAME");
  app.add_option("--z", o.plane_z,
                 "3-D models: the fibres' plane along the electrodes' length, mm, within +-500 "
                 "(0: their middle) [the document's, or 0]")
      ->type_name("MM");
  app.add_option("--skin", o.skin,
                 "layered model: the skin's layers, fingertip (hydrated, electrode gel), "
                 "fingertip-dry, or a skin file (JSON; - for stdin) [the document's, or fingertip]")
      ->type_name("NAME|FILE");
}

}  // namespace tp::cli
