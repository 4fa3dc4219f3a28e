#pragma once
// The array options shared by the programs that describe an electrode array: either a
// document (--config FILE, - for stdin) or a uniform array (--electrodes N --pitch MM).

#include <string>

#include <CLI/CLI.hpp>

#include "io/document.hpp"

namespace tp::cli {

struct ArrayOptions {
  std::string config, electrodes, pitch;
};

// Declares --config, --electrodes and --pitch (the first excludes the others); returns the
// --config option so that a program can exclude more of its own flags from it.
CLI::Option* add_array_options(CLI::App& app, ArrayOptions& o, const std::string& config_help);

// The document from --config, or a uniform array (default 8 electrodes at 1 mm).
Document load_document(const ArrayOptions& o, int min_electrodes);

}  // namespace tp::cli
