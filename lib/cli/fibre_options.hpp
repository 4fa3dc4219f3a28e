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
struct FibreOptions {
  std::string model = "mrg";
  std::string geometry = "straight";
  std::string stimulus;
  std::string width, interphase, balance_width;
  bool monophasic = false;
  int offsets = 8;
  std::string tolerance;
  int threads = 0;
  std::string model_flag = "--model";  // set by add_fibre_options, for messages
};

// model_flag: "--model" (fiber-threshold) or "--fibre-model" (optimize-weights).
void add_fibre_options(CLI::App& app, FibreOptions& o, const std::string& model_flag);

// The values of the flags (bad input names a flag whose text is not a finite number).
tp::FibreOptions fibre_values(const FibreOptions& o);

using tp::FibreSetup;
// tp::apply_fibre_options over the flags' values.
FibreSetup apply_fibre_options(const FibreOptions& o, const std::vector<double>& weights);

}  // namespace tp::cli
