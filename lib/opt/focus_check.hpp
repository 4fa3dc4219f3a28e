#pragma once
// A focal pattern on the continuous fibres (model/field.hpp): every receptor's largest AF,
// and the target's largest beyond the radius, the maxima the focus's bounds are stated on.

#include <utility>
#include <vector>

#include "model/field.hpp"
#include "opt/focus.hpp"

namespace tp::focus {

// A continuous maximum may exceed its sampled bound by this much (relative) before it
// joins the samples: the spill, a bound, by 1e-3; an off-target maximum, which only
// makes the objective's estimate optimistic, by 1 % (a lobe the samples missed).
inline constexpr double kCheckSpill = 1e-3;
inline constexpr double kCheckOff = 1e-2;

// The target's largest AF farther than `radius` from the focus: the faces of its box with
// the disc masked out, and the cylinder around the focus where the mask ends (a 1-D array:
// each depth's row beyond the radius, and the columns just outside it).  -inf when no
// fibre lies that far.
Peak max_beyond(const Setup& s, const Field& f, const Receptor& r, const FocusOptions& o,
                double radius);

// Every receptor's largest AF (a Summary) and the target's largest beyond the radius, on
// o.threads threads, each task with its own Field.
std::pair<Summary, Peak> check_pattern(const Setup& s, const std::vector<double>& currents,
                                       const Receptor& target, const FocusOptions& o,
                                       double radius);

// The grid points (s, t) whose value is above `over` and at least as high as each of their
// neighbours': local peaks, in the grid's order (t-major).
std::vector<std::pair<double, double>> peaks_above(const GridValues& g, double over);

}  // namespace tp::focus
