#pragma once
// The array options shared by the programs that describe an electrode array: either a
// document (--config FILE, - for stdin), a uniform array (--electrodes N --pitch MM), or a
// 2-D grid of pads (--grid CxR --pitch MM [--row-pitch MM] [--pad WxL]).

#include <string>

#include <CLI/CLI.hpp>

#include "io/document.hpp"

namespace tp::cli {

struct ArrayOptions {
  std::string config, electrodes, pitch, grid, row_pitch, pad;
};

// Declares --config, --electrodes, --pitch, --grid, --row-pitch and --pad (--config
// excludes the others, --electrodes excludes --grid); returns the --config option so that
// a program can exclude more of its own flags from it.
CLI::Option* add_array_options(CLI::App& app, ArrayOptions& o, const std::string& config_help);

// The document from --config, a uniform array (default 8 electrodes at 1 mm), or a grid
// (the rect3d model).
Document load_document(const ArrayOptions& o, int min_electrodes);

// The conductor model flags shared by the programs that compute fields: --model and --z
// (the 3-D models' fibre plane).  Given, they override the document's.
struct ModelOptions {
  std::string model, plane_z, skin;
  std::string flag = "--model";  // the conductor flag's name (fiber-threshold: --conductor)
};
void add_model_options(CLI::App& app, ModelOptions& o);
// Applies the flags to doc and checks the model against the receptors (bad input, exit 2).
void apply_model_options(Document& doc, const ModelOptions& o);
// Refuses (bad input) a fibre plane (--z, or the document's model.plane_z_mm) where it
// would be ignored, saying `why`.
void refuse_plane_z(const Document& doc, const ModelOptions& o, const std::string& why);

}  // namespace tp::cli
