#pragma once
// Weights chosen by threshold: minimise threshold_ratio of a mode (its receptor's threshold
// over the lowest other receptor's) from the AF optimum, over the weights with Sum w = 0
// (docs/fibres.md, "Weights by threshold").  The thresholds are points of an amplitude
// lattice and minima over placements, so the objective is piecewise constant: no gradient
// to follow, hence Nelder-Mead, derivative-free.  A whole search (every receptor's
// threshold) costs about a hundred simulations, so the search works mostly on stand-ins
// (LinearStandIn, threshold_standin.hpp: a fibre's linear response, calibrated by the whole
// searches) and makes a whole search only to check the stand-ins' best; the whole searches
// left, if any, polish by Nelder-Mead on whole searches.  It is bounded by a number of whole
// searches (not by time, so the result is the same on any machine) and returns the best
// weights a whole search found: never worse than the AF optimum it starts from.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "fibre/report.hpp"

namespace tp::fibre {

struct ThresholdSearchOptions {
  std::size_t max_evaluations = 12;  // whole searches (each: every receptor's threshold)
  double initial_step = 0.25;        // the first simplex's size, in weight units
  // Called after each whole search with the number made so far (at most max_evaluations):
  // a program's progress line.  Empty: none.
  std::function<void(std::size_t evaluations)> progress;
};

struct ThresholdOptimum {
  std::vector<double> weights;  // Sum = 0 (to rounding), max |w| = 1
  ThresholdReport report;       // at the weights
  ThresholdReport start;        // at the AF optimum
  std::size_t evaluations = 0;  // whole searches (each: every receptor's threshold)
  std::size_t rounds = 0;       // of them, checks of the stand-ins' best
  bool improved = false;        // false: the AF optimum is returned
};

// target: the receptor index of the mode; af_weights: the AF optimum (Sum = 0, max |w| = 1).
ThresholdOptimum optimize_threshold(const Setup& setup, std::size_t target,
                                    const std::vector<double>& af_weights, const FibreModel& model,
                                    const PulseSpec& pulse, const ThresholdSettings& settings,
                                    const ThresholdSearchOptions& options);

// Bad input when the whole search's estimated work (options.max_evaluations sets of
// thresholds, thresholds_work()) exceeds kMaxSearchWork, naming --max-evaluations first;
// or when a receptor's fibre is (fibre_nodes()).  optimize_threshold() calls it first; a
// program calls it before the AF optimisation the search starts from, so that nothing runs.
void check_search_work(const Setup& setup, const FibreModel& model, const PulseSpec& pulse,
                       const ThresholdSettings& settings, const ThresholdSearchOptions& options);

// The objective: threshold(target) / lowest other threshold; a receptor without threshold
// counts as firing at settings.max_mA (the target: +infinity).
double threshold_objective(const ThresholdReport& r, std::size_t target, double max_mA);

// "SAI threshold ratio 0.8123 (AF optimum: 0.9)": the objective at the result and at the
// AF optimum; where the target has no threshold (an infinite objective), "none" and why,
// never "inf": "SAI threshold ratio none (SAI has no threshold below 100 mA, nor at the AF
// optimum)".
std::string threshold_search_summary(const ThresholdOptimum& t, std::size_t target, double max_mA);

}  // namespace tp::fibre
