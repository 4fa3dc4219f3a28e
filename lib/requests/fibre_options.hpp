#pragma once
// The options of the work that computes fibre thresholds (fiber-threshold, optimize-weights
// --objective threshold, Python's fiber_threshold): the fibre model, the pulse (its values,
// or a stimulus document), the node offsets, the lattice tolerance and the threads, as
// values.  The programs declare the flags in cli/fibre_options.hpp.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fibre/models.hpp"
#include "fibre/report.hpp"
#include "pulse/stimulus.hpp"

namespace tp {

struct FibreOptions {
  std::string model = "mrg";          // mrg or senn
  std::string geometry = "straight";  // vertical fibres: straight or afferent
  // A stimulus document (make-pulse's; - for stdin): its pulse, and its amplitude in units
  // of each threshold.  Excludes the pulse's values below.
  std::string stimulus;
  std::optional<double> width_us;          // [200]
  std::optional<double> interphase_us;     // [0]
  std::optional<double> balance_width_us;  // [width_us]
  bool monophasic = false;
  // A shaped pulse (--phases D:L,...: levels x the amplitude; simulated as given, balanced
  // or not).  Excludes the widths, --monophasic and --stimulus.
  std::vector<Phase> phases;
  // The weights document's pulse: the pulse when none of the above is given.
  std::optional<PulseSpec> carried_pulse;
  int offsets = 8;                    // 1 to 64
  std::optional<double> tolerance;    // 1e-4 to 0.1 [0.001]
  std::string tolerance_text;         // the flag as given, for messages [the value]
  int threads = 0;                    // 1 to 256; 0: every core
  std::string model_flag = "--model";  // the fibre model's flag, for messages
};

// The fibre flags as typed (cli/fibre_options.hpp declares them): numbers parsed by
// fibre_values, naming the flag.
struct FibreText {
  std::string model = "mrg";
  std::string geometry = "straight";
  std::string stimulus;
  std::string width, interphase, balance_width;
  bool monophasic = false;
  std::string phases;
  int offsets = 8;
  std::string tolerance;
  int threads = 0;
  std::string model_flag = "--model";  // set by cli::add_fibre_options, for messages
};

// The values of the flags (bad input names a flag whose text is not a finite number, in
// the order --width, --balance-width, --interphase, --tolerance).
FibreOptions fibre_values(const FibreText& t);

struct FibreSetup {
  std::unique_ptr<fibre::FibreModel> model;
  tp::PulseSpec pulse;
  fibre::ThresholdSettings settings;
  std::optional<Stimulus> stimulus;  // checked against its limits
};

// Checks every option (bad input names the program's flag, in the words of its
// command-line parser where that parser checks it: ranges, options that exclude each
// other); a stimulus must be the weights times one amplitude and within every limit.
FibreSetup apply_fibre_options(const FibreOptions& o, const std::vector<double>& weights);

}  // namespace tp
