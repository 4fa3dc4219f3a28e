#pragma once
// The array options shared by the programs that describe an electrode array: either a
// document (--config FILE, - for stdin), a uniform array (--electrodes N --pitch MM), or a
// 2-D grid of pads (--grid CxR --pitch MM [--row-pitch MM] [--pad WxL]); and the conductor
// model's flags.  The flags are declared here (CLI11); their values, and what makes a
// document of them, are the library's (requests/document_options.hpp), which the Python
// module fills too.

#include <string>

#include <CLI/CLI.hpp>

#include "requests/document_options.hpp"

namespace tp::cli {

using tp::ArrayOptions;
using tp::load_document;
using tp::ModelOptions;
using tp::apply_model_options;
using tp::refuse_plane_z;

// Declares --config, --electrodes, --pitch, --grid, --row-pitch and --pad (--config
// excludes the others, --electrodes excludes --grid); returns the --config option so that
// a program can exclude more of its own flags from it.
CLI::Option* add_array_options(CLI::App& app, ArrayOptions& o, const std::string& config_help);

// The conductor model flags shared by the programs that compute fields: --model (o.flag),
// --z (the 3-D models' fibre plane) and --skin.
void add_model_options(CLI::App& app, ModelOptions& o);

}  // namespace tp::cli
