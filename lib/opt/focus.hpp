#pragma once
// A focal pattern: weights that make receptor M fire at a chosen place (issue 21, a pixel).
//
// For a focus (x_f, z_f) on the skin (a 1-D array: x_f in the fibres' plane):
//     minimise   t = largest off-target AF / the target's AF at the focus
//     subject to the target's AF at the focus point p* is its largest, to within a quarter
//                pitch: AF_M(q) <= AF_M(p*) wherever q lies farther than pitch / 4 from
//                the focus (laterally), and AF_M(q) <= spill x AF_M(p*) farther than the
//                radius; Sum w = 0.
// With AF_M(p*) = 1 this is a linear programme over the sampled fibres (opt/lp.hpp, the
// capped rows holding the target's own samples); p* is the focus at the target's depth (a
// vertical target: the best of five depths down its segment).  Among the weights within
// `tolerance` of the optimum t*, at the same p*, the answer is the one of least Sum w^2
// (opt/ldp.hpp): unique, so symmetric when the problem is.  It is then checked on the
// continuous fibres (model/field.hpp): where a true maximum breaks a bound by more than
// the check's tolerance, that point (with its mirror images through the focus, and the
// receptor's other lobes above the bound) joins the samples and the problem is solved
// again; a spill beyond its bound also lowers the cap of every sample beyond the radius by
// the excess found.

#include <optional>
#include <string>
#include <vector>

#include "model/field.hpp"

namespace tp {

struct FocusOptions {
  double x_mm = 0.0, z_mm = 0.0;  // the focus (z: 2-D arrays)
  double radius_mm = 0.0;         // 0: one pitch
  double spill = 0.3;             // (0, 1]
  double max_current_mA = 2.0;
  double tolerance = 1e-3;  // least Sum w^2 among weights within this of the best t
  unsigned threads = 1;     // the checks on the continuous fibres run on these
  bool certify = false;     // also the best t over every place the peak may take
};

struct FocusResult {
  std::string mode;
  std::vector<double> weights;  // Sum w = 0, max |w| = 1, positive = cathodic
  std::vector<double> currents_mA;
  Summary summary;               // every receptor's largest AF at the current limit
  double ratio = 0.0;            // the mode's ratio (true maxima)
  double target_max_af = 0.0;    // V/ms at the current limit
  double spill = 0.0;            // the target's largest AF beyond the radius over its peak
  double sampled_optimum = 0.0;  // t* of the sampled problem
  double pitch_mm = 0.0, radius_mm = 0.0;
  double target_depth_mm = 0.0;  // p*'s depth
  int lp_solves = 0, rounds = 0;
  bool least_norm = false;  // the least Sum w^2 was found (else the LP's vertex, said so)
  bool bounds_hold = true;  // evaluate_focus(): the peak at the focus, the spill within bound
  std::size_t samples = 0;
  // certify: the least t of the last round's LP over the target's samples within a quarter
  // pitch of the focus (and p*'s candidates), where, and how many were solved.
  std::optional<double> certified_optimum;
  Peak certified_at;
  std::size_t certified_points = 0;
  double time_s = 0.0;
};

// The array's pitch: a uniform array's or grid's (the smaller of its two), else the least
// distance between two electrode centres (a lone electrode: its width, at least 0.01 mm).
double nominal_pitch_mm(const ElectrodeArray& a);

// Bad input (exit 2) for a focus outside the array's extent plus one pitch, a spill
// outside (0, 1] or a radius not in (0, 1000] mm.
void check_focus(const Setup& setup, const FocusOptions& opt);

// Why no weights satisfy a focus.
struct FocusFailure {
  enum class Kind {
    nowhere,      // no weights put the target's peak there at all
    impossible,   // value: the least spill on the samples, above 1
    least_spill,  // value: the least spill on the samples (a lower bound)
    caps,         // value: the spill reached on the continuous fibres
    rounds        // value: the spill after `rounds` rounds, the peak at (peak_x, peak_z)
  } kind = Kind::nowhere;
  double value = 0.0;
  int rounds = 0;
  double peak_x_mm = 0.0, peak_z_mm = 0.0;
};
// Its one-line message, naming the focus of `opt` and the spill.
std::string focus_failure_text(const Setup& setup, const std::string& mode, const FocusOptions& opt,
                               const FocusFailure& why);

// Bad input as check_focus(); a runtime failure (exit 1) when no weights satisfy the
// focus, naming the least spill reachable (focus_failure_text).
FocusResult optimize_focus(const Setup& setup, const std::string& mode, const FocusOptions& opt);
// The same, but when no weights satisfy the focus: no value, and `why`.
std::optional<FocusResult> try_optimize_focus(const Setup& setup, const std::string& mode,
                                              const FocusOptions& opt, FocusFailure& why);

// A given pattern (weights, one per pad) judged as a pixel at the focus on the continuous
// fibres: every receptor's largest AF, the mode's ratio, the target's spill beyond the
// radius; bounds_hold when its peak lies within a quarter pitch of the focus and the spill
// is within the bound (to the check's 1e-3).  The solver's fields stay empty.
FocusResult evaluate_focus(const Setup& setup, const std::string& mode, const FocusOptions& opt,
                           const std::vector<double>& weights);

}  // namespace tp
