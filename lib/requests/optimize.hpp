#pragma once
// optimize-weights' work, for the program and the Python module alike (docs/programs.md,
// optimize-weights): a document and the options become the document the program prints.
// Five designs: each mode's minimax weights (Eq. 32-34; JSON, or one CSV row a mode), a
// pixel (at_mm: a focus), a bank of pixels, the selectivity objective (weights and pulse
// shape by a population's recruitment, on an array or at a pixel), or the threshold
// objective (weights by a fibre model's thresholds, from the AF optimum).  Bad input names
// the program's flags.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/document.hpp"
#include "core/json.hpp"
#include "requests/fibre_options.hpp"

namespace tp {

enum class OptimizeObjective { af, threshold, selectivity };

struct OptimizeRequest {
  // --mode: the target receptors (names in the document's table): one; several with CSV
  // output (one row each) or a bank; none: a bank of every receptor's.
  std::vector<std::string> modes;
  std::optional<double> max_current_mA;  // the limit per electrode [the document's]
  double min_target_af = 0.0;            // V/ms, [0, 10000]: the AF objective's trade-off
  std::optional<int> pattern_starts;     // 0 to 4 [2]
  std::optional<int> random_starts;      // 0 to 1000 [0]
  bool csv = false;                      // --format csv (else JSON)
  bool header = true;                    // false: --no-header
  bool header_only = false;              // the options checked, the CSV header, no work
  bool timing = false;                   // solver.time_s in the JSON (not reproducible)
  bool certify = false;                  // the certified optimum too (JSON)
  OptimizeObjective objective = OptimizeObjective::af;
  // The threshold objective's fibre model and pulse (--fibre-model, --width, ...: checked
  // with the AF optimum's weights, which a stimulus must be of; fibre.model_flag is
  // --fibre-model and fibre.threads is `threads`, whatever they say), whether its model and
  // offsets were given (the others: when set), and its budget of whole searches, 10 to
  // 10000 [12].  The AF objective refuses them.
  FibreOptions fibre;
  bool fibre_model_given = false, offsets_given = false;
  std::optional<int> max_evaluations;
  // The selectivity objective (docs/fibres.md, "Designed for selectivity"): afferents of
  // each class in its population, 1 to 1000 [30]; its seed [1] (the held-out check's: the
  // next); its budget of populations (max_evaluations, 10 to 1000 [40]); the comfort bound on
  // the charge per phase at I50, nC, 0 to 100000 [0: twice the AF optimum's].
  std::optional<int> population;
  std::optional<std::uint64_t> seed;
  std::optional<double> max_charge_nC;
  // A pixel: at_mm holds its place, X (a 1-D array) or X, Z (a 2-D array), mm; with a
  // bank, the pixels (empty: every pad's centre).
  std::vector<std::vector<double>> at_mm;
  std::optional<double> radius_mm;  // beyond a quarter pitch [one pitch]
  std::optional<double> spill;      // (0, 1] [0.3]
  bool bank = false;
  std::optional<int> neighbourhood;  // a bank on a grid: K x K pads, K odd, 3 to 255
  std::optional<int> threads;        // 1 to 256 (--objective threshold, a pixel, a bank)
  bool plane_z_given = false;        // the program's --z (applied to the document)
  // The texts the user typed, quoted by the messages that refuse them and by the pixel's
  // summary (the program's flags); empty: the values' numbers are written instead.
  struct Given {
    std::string min_target_af, radius;
    std::vector<std::string> at;
  } given;
  // Long work (a bank, the threshold search): called with a progress line's text (and
  // true as a new stage starts), one call at a time.  Empty: none.
  std::function<void(const std::string& text, bool new_stage)> progress;
};

struct OptimizeOutput {
  std::string text;  // what the program prints: the JSON document, or the CSV
  Json document;     // the JSON document (null with CSV output)
  // The lines the program writes on stderr after its name, in order: warnings, then the
  // summary (a line a mode, or one).
  std::vector<std::string> notes;
};

// optimize-weights' flags as typed: --mode's comma-separated names, the numbers and the
// threshold objective's fibre flags.
struct OptimizeText {
  std::string modes;  // "SAI,PC"
  std::string max_current_mA, min_target_af, radius_mm, spill, max_charge_nC;
  std::vector<std::string> at;  // each X or X,Z
  FibreText fibre;
};

// The modes, the numbers (bad input naming the flag whose text is not a number, in the
// order --max-current, --min-target-af, the fibre's, --at, --radius, --spill), the texts
// the messages quote, and the fibre options' values, into r; the rest of r as it was.
void parse_optimize_text(const OptimizeText& t, OptimizeRequest& r);

// Every check of the options against the document, in the program's order, without work:
// bad input names the flag (the message optimize-weights prints after its name).  The
// threshold objective's fibre options are checked by run_optimize() with the AF optimum's
// weights (a stimulus must be of them), before the threshold search.
void check_optimize(const Document& doc, const OptimizeRequest& r);

// The checks, then the work: the whole output, or bad input (as check_optimize, or from the
// solvers: a target AF no weights reach), or a runtime failure (a pixel no pattern can
// satisfy).
OptimizeOutput run_optimize(const Document& doc, const OptimizeRequest& r);

}  // namespace tp
