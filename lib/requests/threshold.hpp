#pragma once
// fiber-threshold's work, for the program and the Python module alike (docs/programs.md,
// fiber-threshold): a weights document and the options become each receptor's threshold
// (the document with "thresholds"), a strength-duration table, or a population's
// thresholds and recruitment curves.
//
//   ThresholdRequest r;  r.fibre.model = "senn";  r.strength_duration = true;
//   const ThresholdPlan plan = plan_thresholds(doc, r);   // every check, no work
//   const ThresholdOutput out = run_thresholds(plan);     // stdout's text, stderr's lines

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fibre/population.hpp"
#include "fibre/strength_duration.hpp"
#include "io/document.hpp"
#include "core/json.hpp"
#include "requests/document_options.hpp"
#include "requests/fibre_options.hpp"

namespace tp {

// The values of fiber-threshold's options (the weights document is the plan's argument).
struct ThresholdRequest {
  ModelOptions conductor{"", "", "", "--conductor"};  // --conductor, --z, --skin
  FibreOptions fibre;                                  // --model, --geometry, the pulse, ...
  // 2-D arrays: the point X,Z (mm) the fibres pass through [the document's focus];
  // at_text: the flag as given, for messages.
  std::optional<std::vector<double>> at_mm;
  std::string at_text;
  // --strength-duration [--widths]: the widths given (with strength_duration only) [the
  // default widths, kStrengthDurationWidths_us].
  bool strength_duration = false;
  std::optional<std::vector<double>> widths_us;
  // --population N [--seed S] [--recruitment FILE]: N afferents of each class, 1 to
  // kMaxPopulation; the seed [1]; where the program writes the curves (with population only).
  std::optional<long> population;
  std::optional<std::uint64_t> seed;
  std::string recruitment;
};

// fiber-threshold's flags as typed, and the ones that say where its inputs come from.
struct ThresholdText {
  std::string config;   // --config as given (empty: not given)
  std::string skin;     // --skin as given (-: stdin)
  std::string weights;  // --weights W1,W2,... instead of a document
  std::string at;       // --at X,Z
  std::string widths;   // --widths US1,US2,... (with --strength-duration only)
  FibreText fibre;      // --model, the pulse, ... (--stimulus -: stdin)
};

// Where the weights document comes from: --config, else stdin unless --weights gives the
// weights ("": the array from the default document).  Bad input when stdin would be read
// by more than one of the document, --stimulus and --skin (naming the first two).
std::string threshold_document_source(const ThresholdText& t);

// The texts into the request and the document: --weights' values as doc's weights, the
// fibre options' values, --at (quoted as given by messages), and --widths where they apply
// (r.strength_duration set first; without it, given and empty, which the plan refuses).
// Bad input names the flag whose text is not a number, in that order.
void parse_threshold_text(const ThresholdText& t, Document& doc, ThresholdRequest& r);

enum class ThresholdMode { thresholds, strength_duration, population };

// A checked request: what run_thresholds() does and everything it needs.
struct ThresholdPlan {
  ThresholdMode mode = ThresholdMode::thresholds;
  Document doc;  // the conductor options applied; its weights checked
  double peak_weight = 1.0;  // max |w|
  FibreSetup fibre;          // the model, the pulse and the search's settings
  std::vector<double> widths_us;  // strength-duration: ascending, distinct
  fibre::PopulationOptions population;  // per_class and seed
};

// Every check that needs no fibre simulation, in the program's order; bad input names the
// option as fiber-threshold's flag (--at, --widths, --population, ...), or the document's key.
// A strength-duration table's pulses and its whole work are checked here; a population's
// and the thresholds' own checks come with their work (before any of it).
ThresholdPlan plan_thresholds(Document doc, const ThresholdRequest& r);

// What fiber-threshold writes.
struct ThresholdOutput {
  // stdout: the weights document with "thresholds" and "threshold_ratio" (and with a
  // stimulus "threshold_multiples"), or a CSV table (the strength-duration table, or the
  // population's afferents).
  std::optional<Json> document;
  std::string table;
  std::string recruitment;  // population: the recruitment curves (CSV)
  // The summary on stderr, one line each, without the program's name.
  std::vector<std::string> notes;
};

// The progress of long work (a population, a strength-duration table): a line of text,
// and whether it begins a new stage of the work (cli::ProgressLine::show's arguments).
// Called from the working threads, one call at a time.
using ThresholdProgress = std::function<void(const std::string& text, bool new_stage)>;

ThresholdOutput run_thresholds(const ThresholdPlan& plan, const ThresholdProgress& progress = {});

// plan_thresholds, then run_thresholds.
ThresholdOutput run_thresholds(Document doc, const ThresholdRequest& r,
                               const ThresholdProgress& progress = {});

// The strength-duration table's widths, checked against the pulse (bad input naming
// --widths): each 1 to 10000 us and its balancing phase too, at most 64; sorted, each once.
std::vector<double> strength_duration_widths(std::vector<double> widths_us,
                                             const tp::PulseSpec& pulse);

}  // namespace tp
