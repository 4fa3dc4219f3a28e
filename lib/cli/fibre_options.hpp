#pragma once
// The flags of the programs that compute fibre thresholds (fiber-threshold,
// optimize-weights --objective threshold): the fibre model, the pulse (flags or a stimulus
// document), the node offsets, the lattice tolerance and the threads, as CLI11 declares
// them.  Their values, and what they make, are the library's (requests/fibre_options.hpp).

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "requests/fibre_options.hpp"

namespace tp::cli {

// The flags' texts (numbers parsed by fibre_values, naming the flag).
using FibreOptions = tp::FibreText;

// model_flag: "--model" (fiber-threshold) or "--fibre-model" (optimize-weights).
void add_fibre_options(CLI::App& app, FibreOptions& o, const std::string& model_flag);

using tp::fibre_values;

using tp::FibreSetup;
// tp::apply_fibre_options over the flags' values.
FibreSetup apply_fibre_options(const FibreOptions& o, const std::vector<double>& weights);

}  // namespace tp::cli
