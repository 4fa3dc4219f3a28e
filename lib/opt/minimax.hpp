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
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ceres/first_order_function.h>
#include <Eigen/Dense>

#include "model/field.hpp"
#include "opt/problem.hpp"

namespace tp {

class TargetLp;  // opt/lp.hpp

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

// optimize_mode's steps over their state (Search), exposed for the unit tests:
//   Search s(setup, mode, options);   the options checked, the fine (polish) problem
//   s.surrogate();                    1-2: a candidate from each start
//   s.lp_seeds();                     3: one from the LP under each electrode
//   s.keep_best();                    the best `polished_candidates`, by ratio
//   s.polish(c) for each              4: by LP at the target's true peak
//   s.finish(best) / s.no_answer()    5: the result, or why there is none
namespace minimax {

struct Candidate {
  double ratio = 0.0;  // the true ratio (infinite when the target is never depolarised)
  Eigen::VectorXd z;   // w = B z
  std::string label;   // the start it came from
  Peak target_peak;    // where the target's largest AF lies (the polish starts there)
};

class Search {
 public:
  // Bad input for a max current not above 0, a negative minimum target AF, and as
  // make_mode_problem().
  Search(const Setup& setup, const std::string& mode, const OptimizeOptions& opt);
  ~Search();
  Search(const Search&) = delete;
  Search& operator=(const Search&) = delete;

  // z's true ratio and the target's peak, from one evaluation of every receptor's maximum.
  Candidate assess(const Eigen::VectorXd& z, std::string label) const;

  // 1-2. The surrogate minimised with continuation (p = 8, 32, 256, at most 50 L-BFGS
  // iterations each) from every start: each one that depolarises the target a candidate.
  void surrogate();
  // 3. The LP with the target point under each electrode (the left half of a
  // mirror-symmetric array), at the top of the target's fibres: each solution that
  // depolarises the target a candidate.
  void lp_seeds();
  // The best `polished_candidates` candidates, by ratio (stable).
  void keep_best();
  // 4. c polished: the LP solved at the target's true peak, again from the answer's peak
  // while the true ratio improves (at most 10 times); never worse than c.  With a minimum
  // target AF only LP solutions are admissible: c's own ratio counts as infinite.
  Candidate polish(const Candidate& c);
  // No candidate survived: bad input naming the target AF the most selective weights
  // reach (a minimum target AF), else a runtime failure.
  [[noreturn]] void no_answer() const;
  // 5. The result: Sum w = 0 exact to rounding, max |w| = 1 exactly, judged on the true
  // maxima.
  OptimizeResult finish(const Candidate& best);

  // Every step in order.
  OptimizeResult run();

  const std::vector<Candidate>& candidates() const { return candidates_; }
  const OptimizeResult& counts() const { return res_; }  // starts, iterations, LP solves
  const Eigen::MatrixXd& basis() const { return basis_; }

 private:
  TargetLp& lp();

  const Setup& setup_;
  const std::string mode_;
  const OptimizeOptions opt_;
  Eigen::MatrixXd basis_;
  ModeProblem fine_;
  std::unique_ptr<TargetLp> lp_;
  std::unique_ptr<Conductor> conductor_;
  std::vector<Candidate> candidates_;
  OptimizeResult res_;
};

}  // namespace minimax

// Global optimum of the sampled problem by exhaustive LP over target points.
Certificate certify_mode(const Setup& setup, const std::string& mode, double step_mm,
                         double weight_bound = 0.0);

}  // namespace tp
