#pragma once
// The options of the programs that compute fibre thresholds (fiber-threshold,
// optimize-weights --objective threshold): the fibre model, the pulse (flags or a stimulus
// document), the node offsets, the lattice tolerance and the threads.

#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "io/document.hpp"
#include "requests/fibre.hpp"

namespace tp::cli {

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

// The flags' values: the numbers parsed (bad input names the flag), --stimulus read.
FibreRequest fibre_request(const FibreOptions& o);

using FibreSetup = tp::FibreSetup;
// Checks every option (bad input names the flag); a stimulus must be the weights times one
// amplitude and within every limit.
FibreSetup apply_fibre_options(const FibreOptions& o, const std::vector<double>& weights);

}  // namespace tp::cli
