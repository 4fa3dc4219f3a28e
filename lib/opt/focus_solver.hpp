#pragma once
// The focus solver (opt/focus.hpp's try_optimize_focus) in named steps over its state, in
// the manner of Ceres' minimisers (IterationZero, ComputeTrustRegionStep, ...):
//
//   Solver s(setup, mode, options);   the focus checked, the target's candidate depths
//   s.build_samples();                every receptor's samples and the target's rings
//   for each round:
//     s.solve_round();                the LP at each candidate depth: t*, or no weights
//       (none: s.widen_depths() to try every depth again, else s.diagnose(): why)
//     s.least_norm_weights(round);    the least Sum w^2 within the tolerance of t*
//     s.check(round, w);              the weights on the continuous fibres
//     (settled: done; else s.augment(check): the points found join the samples)
//   s.certify();                      with --certify: the best over the peak's places
//   s.finish(w);                      the result
//
// run() is that sequence.  Each step is exposed for the unit tests (test_opt_focus.cpp).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "model/field.hpp"
#include "opt/focus.hpp"
#include "opt/focus_samples.hpp"
#include "opt/lp.hpp"

namespace tp::focus {

// The rounds end here: the bounds then hold on the continuous fibres or no weights do.
inline constexpr int kMaxRounds = 8;

// The samples of a focus problem.  The target's own are capped: at 1 (its AF at the focus
// point) between a quarter pitch and the radius, at spill_cap beyond it; those within a
// quarter pitch (`inner`, where the peak may lie) are not in the problem.
struct Samples {
  std::vector<Sample> off;     // every other receptor's: at most t
  std::vector<Sample> capped;  // the target's beyond a quarter pitch
  std::vector<double> caps;    // per capped sample: its bound
  std::vector<char> beyond;    // per capped sample: beyond the radius
  std::vector<Sample> inner;   // the target's within a quarter pitch of the focus
  std::vector<PlaneTable> tables;
  // The spill, lowered by the excess the checks find between the samples (augment), so
  // that the bound holds on the continuous fibres and not only at the samples.
  double spill_cap = 0.0;
  std::size_t size() const { return off.size() + capped.size(); }
};

// One round's LP optimum: t* at the best candidate depth.
struct Round {
  LpSolution lp;              // t* (value) and z
  Eigen::VectorXd focus_row;  // the focus point's row at that depth (its AF is 1)
  double depth_mm = 0.0;
};

// The weights on the continuous fibres, and what must join the samples.
struct Check {
  Summary summary;
  Peak far;                 // the target's largest AF beyond the radius
  double target_af = 0.0;   // its largest anywhere
  bool peak_away = false;   // that peak lies farther than a quarter pitch from the focus
  bool spill_over = false;  // far.af over the spill of target_af
  std::vector<Sample> add_off, add_target;  // the points breaking a bound
  // Never a silent violation: the peak at the focus, the spill within the check's tolerance.
  bool bounds_hold = false;
  bool settled() const { return add_off.empty() && add_target.empty() && !spill_over; }
};

class Solver {
 public:
  // Bad input as try_optimize_focus: the focus (check_focus), fewer than 2 pads or
  // receptors, an unknown mode, fibres the conductor cannot reach.
  Solver(const Setup& setup, const std::string& mode, const FocusOptions& opt);
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  // Every other receptor's samples (off), the target's (capped or inner), and on the
  // target's fibres the circles of a quarter pitch and of the radius (a 1-D array: those
  // points) just outside, where the bounds change.  Bad input beyond kMaxProblemEntries.
  void build_samples();

  // The samples added since the last round join the LP (one for every round: the rows
  // the last solves needed stay in, with their basis), then the LP is solved at each
  // candidate depth: the least t, or none when no weights put the peak at the focus.  The
  // depth is chosen in round 1; later rounds solve at that one.  A runtime failure when
  // the rounds' samples pass kMaxProblemEntries.
  std::optional<Round> solve_round();

  // After a round with no weights at the depth chosen in round 1: every candidate depth
  // from then on (true), or false when they were all tried already.
  bool widen_depths();

  // Why no weights satisfy the focus, when a round found none at any depth: round 1 on
  // the samples (least_spill()), a later one on the caps the checks lowered.
  FocusFailure diagnose() const;
  // The least spill any weights reach with the peak at the focus on the samples: the
  // same LP with the target's samples beyond the radius as the off-target rows; infinite
  // when no weights put the peak there at all.
  double least_spill() const;

  // Among the z within the tolerance of t* (every sample within its bound, t relaxed to
  // t* (1 + tolerance), the focus row's AF 1), the least |z| = |w| (opt/ldp.hpp); the LP's
  // own z when that is not found (result().least_norm false).  As weights: Sum w = 0
  // exactly to rounding, max |w| = 1.
  Eigen::VectorXd least_norm_weights(const Round& round);

  // The weights on the continuous fibres (at opt.max_current_mA): the bounds as the issue
  // states them, on the true maxima.  Every off-target peak above t (1 + tolerance) of the
  // target's by more than kCheckOff joins add_off (a grid's: with its other lobes above
  // that on the faces at its depths); the target's peak when away from the focus, and its
  // largest AF beyond the radius when over the spill by more than kCheckSpill, join
  // add_target.  Fills the result's summary, ratio, target AF and spill.
  Check check(const Round& round, const Eigen::VectorXd& w);

  // The check's points join the samples with their mirror images through the focus that
  // lie on the fibres; a spill over the bound first lowers the cap beyond the radius by
  // the excess found (every such sample's, and the new ones').
  void augment(const Check& c);

  // The best t over every place the peak may take: the last round's LP (its rows and
  // caps) with its target at each inner sample and at each candidate depth under the
  // focus.  Fills the result's certified_optimum, certified_at and certified_points.
  void certify();

  // The result with weights w (least_norm_weights'), the samples and solves counted.
  FocusResult finish(const Eigen::VectorXd& w);

  // Every step in order: the result, or none and `why`.
  std::optional<FocusResult> run(FocusFailure& why);

  const Samples& samples() const { return samples_; }
  const FocusResult& result() const { return res_; }
  const std::vector<double>& depths() const { return depths_; }  // this round's candidates
  const std::vector<double>& all_depths() const { return all_depths_; }
  // The focus point's row (AF per unit z) at depth y.
  Eigen::VectorXd focus_row(double y) const;

 private:
  Sample focus_sample(double y) const;
  void add_target_sample(const Sample& p);
  void add_rings(std::vector<Sample>& own) const;
  void add_lobes(std::size_t r, double over, const Field& field, std::vector<Sample>& out) const;
  template <class Add>
  void with_mirrors(const Sample& p, Add&& add) const;

  const Setup& setup_;
  const FocusOptions opt_;
  const std::size_t target_;
  const bool two_d_;
  double quarter_mm_ = 0.0;
  std::unique_ptr<Conductor> conductor_;
  Eigen::MatrixXd basis_;
  FocusResult res_;
  Samples samples_;
  std::vector<double> depths_, all_depths_;
  std::optional<double> best_depth_;
  bool all_depths_again_ = false;  // the chosen depth failed: every candidate from then on
  std::vector<double> last_caps_;  // the caps of the last round's LP
  SampleRows a_off_, a_cap_;       // the samples' rows, extended by each round's
  std::unique_ptr<TargetLp> lp_;
};

}  // namespace tp::focus
