#pragma once
// The fibre model and the pulse of a threshold computation, as values, for the programs
// that compute thresholds (fiber-threshold, optimize-weights --objective threshold) and
// the Python module alike; bad input names the programs' flags.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fibre/models.hpp"
#include "fibre/report.hpp"
#include "pulse/stimulus.hpp"

namespace tp {

struct FibreRequest {
  // The fibre model, mrg or senn [mrg]; model_flag names it in messages ("--model" in
  // fiber-threshold, "--fibre-model" in optimize-weights).
  std::optional<std::string> model;
  std::string model_flag = "--model";
  std::string geometry = "straight";  // straight or afferent (RA's fibre)
  // The pulse: a stimulus's shape (a stimulus document, read by the front end), or the
  // widths (us) and gap, or a monophasic pulse; a stimulus excludes the others.
  std::optional<Stimulus> stimulus;
  std::optional<double> width_us, interphase_us, balance_width_us;
  bool monophasic = false;
  std::optional<int> offsets;       // horizontal fibres' node alignments, 1 to 64 [8]
  std::optional<double> tolerance;  // the thresholds' relative resolution, 1e-4 to 0.1 [1e-3]
  std::optional<int> threads;       // 1 to 256 [every core]
};

struct FibreSetup {
  std::unique_ptr<fibre::FibreModel> model;
  fibre::PulseSpec pulse;
  fibre::ThresholdSettings settings;
  std::optional<Stimulus> stimulus;  // the request's, checked against its limits
};

// Checks every value (bad input names the flag, in the order the programs check them) and
// makes the model, the pulse and the settings.
FibreSetup fibre_setup(const FibreRequest& r);

// Bad input when the setup's stimulus is not `weights` times one amplitude (a stimulus
// must be of the weights it is for); nothing without a stimulus.
void check_stimulus_weights(const FibreSetup& f, const std::vector<double>& weights);

}  // namespace tp
