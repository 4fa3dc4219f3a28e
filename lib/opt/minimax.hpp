#pragma once
// Minimax electrode weights for a mode (Eq. 32-34), fitted with Ceres.
//
// The objective, ratio(w) = max_off AF / max_target AF, is a ratio of maxima: non-smooth
// and not convex.  The method:
//   1. Surrogate.  Each maximum is replaced by the p-norm of the positive parts of the
//      sampled AF values, P_p(a) = (sum max(a_i, 0)^p)^(1/p), which tends to max(a) as p
//      grows and is homogeneous of degree 1, so the surrogate ratio keeps the problem's
//      scale invariance.  Ceres' GradientProblemSolver (L-BFGS) minimises
//          log P_p(A_off z) - log P_p(A_target z) + (|z|^2 - 1)^2 / 2
//      over z, with w = B z and B an orthonormal basis of {Sum w = 0}, so the constraint
//      holds by construction; the last term only fixes the scale (the log ratio's gradient
//      is orthogonal to z).  Continuation tightens p = 8, 32, 256, each stage
//      starting where the last ended.
//   2. Starts.  The paper's patterns (an anode and a cathode by default; a cathode with
//      anodic neighbours and a widened cathode on request) and seeded random ones.
//   3. LP seeds.  For a fixed target point the problem is a linear programme
//      (opt/lp.hpp).  The LP is solved with the target point under each electrode (the
//      left half of a mirror-symmetric array), at the top of the target's fibres, and its
//      solutions join the candidates.
//   4. Polish on the true maxima.  From each of the best candidates, the target's true
//      peak is located, the LP solved at that point over finely sampled off-target
//      fibres, and repeated while the true ratio improves; each step cannot make it worse.
//   5. The answer is the best true ratio, evaluated with the continuous maxima of
//      model/field.hpp, scaled so that max |w| = 1 (that electrode carries the current
//      limit).
//
// certify_mode() solves the LP at every sampled target point instead: the minimum over
// target points is the global optimum of the sampled problem, which the tests compare with.

#include <cstdint>
#include <string>
#include <vector>

#include <ceres/first_order_function.h>
#include <Eigen/Dense>

#include "model/field.hpp"
#include "opt/problem.hpp"

namespace tp {

// The surrogate handed to Ceres (exposed for the gradient checks).
class PNormLogRatio final : public ceres::FirstOrderFunction {
 public:
  PNormLogRatio(Eigen::MatrixXd off_rows, Eigen::MatrixXd target_rows, int log2_p);
  bool Evaluate(const double* z, double* cost, double* gradient) const override;
  int NumParameters() const override { return static_cast<int>(off_.cols()); }

 private:
  Eigen::MatrixXd off_, target_;
  int log2_p_;
};

struct OptimizeOptions {
  double max_current_mA = 2.0;
  // Efficiency trade-off: the target's largest AF at the current limit must reach this
  // (V/ms); 0 leaves the paper's problem unbounded.
  double min_target_af = 0.0;
  double surrogate_step_mm = 0.05;  // fibre sampling for the surrogate
  double polish_step_mm = 0.02;     // fibre sampling for the LP polish
  // Starts of the surrogate: the first `pattern_starts` of the paper's four patterns (anode,
  // cathode, cathode with anodic neighbours, widened cathode), then `random_starts` seeded
  // ones.  Over 189 arrays, more starts never changed a ratio (docs/optimization.md).
  int pattern_starts = 2;
  int random_starts = 0;
  int polished_candidates = 3;
  std::uint64_t seed = 1;
};

struct OptimizeResult {
  std::string mode;
  std::vector<double> weights;      // Sum w = 0, max |w| = 1, positive = cathodic
  std::vector<double> currents_mA;  // weights * max_current_mA
  Summary summary;                  // largest AF per receptor at those currents
  double ratio = 0.0;               // the mode's ratio (true maxima)
  double target_max_af = 0.0;       // target's largest AF at the current limit, V/ms
  std::string best_start;           // which start led to the answer
  int starts = 0;
  int iterations = 0;   // L-BFGS iterations, all starts and stages
  int evaluations = 0;  // surrogate evaluations
  int lp_solves = 0;
  double time_s = 0.0;
};

OptimizeResult optimize_mode(const Setup& setup, const std::string& mode,
                             const OptimizeOptions& opt);

struct Certificate {
  double optimum = 0.0;  // min over sampled target points of the LP value
  double x_mm = 0.0, y_mm = 0.0;
  Eigen::VectorXd weights;
  int lp_solves = 0;
};

// Global optimum of the sampled problem by exhaustive LP over target points.
Certificate certify_mode(const Setup& setup, const std::string& mode, double step_mm,
                         double weight_bound = 0.0);

}  // namespace tp
