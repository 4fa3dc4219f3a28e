#pragma once
// A mode's weight-design problem (the paper's Eq. 32-34), in sampled, linear form.
//
// The AF at any point is linear in the electrode weights: AF(p) = g(p) . w.  A mode M asks
// for weights with Sum w = 0 that minimise
//     ratio(w) = max over off-target fibres of AF / max over fibres of receptor M of AF.
// Every receptor's fibre region is a line or a rectangle on which the AF is harmonic, so
// its maximum lies on the region's boundary (docs/model.md); the problem samples those
// boundaries (the whole regions for the 3-D models, which are harmonic in space but not in
// the fibres' plane).  Sum w = 0 is built in: w = B z with B an orthonormal basis of the
// zero-sum subspace, so every z is admissible.

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "model/field.hpp"

namespace tp {

struct SamplePoint {
  double x_mm, y_mm;
  std::size_t receptor;  // index into Setup::receptors
};

struct ModeProblem {
  std::string mode;
  std::size_t target = 0;               // index of the target receptor
  Eigen::MatrixXd basis;                // B: N x (N-1), orthonormal, columns sum to zero
  std::vector<SamplePoint> target_pts;  // samples of the target's fibre-region boundary
  std::vector<SamplePoint> off_pts;     // samples of every other receptor's boundary
  Eigen::MatrixXd target_rows;          // AF per unit z at each target sample (n_T x (N-1))
  Eigen::MatrixXd off_rows;             // the same for the off-target samples (n_O x (N-1))
};

// The most (samples x electrodes) entries a problem's matrices may hold: 3e7 doubles,
// 240 MB.  The paper's array needs ~2e4; 64 electrodes over 126 mm with 5 mm margins ~4e6.
inline constexpr double kMaxProblemEntries = 3e7;

// Orthonormal basis of {w in R^n : sum w = 0}, n x (n-1).
Eigen::MatrixXd zero_sum_basis(std::size_t n);

// Samples every receptor's fibre-region boundary at `step_mm` (both ends included); for a
// conductor not harmonic in the plane (the 3-D models), the whole region.
// With target_rows false, target_rows is left empty (target_pts is still filled).
ModeProblem make_mode_problem(const Setup& setup, const std::string& mode, double step_mm,
                              bool target_rows = true);

// AF per unit weight (V/ms per mA, one entry per electrode) of receptor r's fibres at a point.
Eigen::VectorXd unit_af(const Setup& setup, const Conductor& c, const Receptor& r, double x_mm,
                        double y_mm);

}  // namespace tp
