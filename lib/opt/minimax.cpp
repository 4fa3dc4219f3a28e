#include "opt/minimax.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "core/number.hpp"
#include "opt/lp.hpp"

namespace tp {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// log P_p(a) and its gradient d log P / d a, p = 2^log2_p.  False when no a_i > 0.
// With r = max(a / max a, 0): r^(p-1) is the product of r^(2^k), k < log2_p (repeated
// squaring, no division), and r^p = r^(p-1) r.  Whole-array operations, so Eigen
// vectorises them.
bool log_pnorm(const Eigen::VectorXd& a, int log2_p, double& log_p, Eigen::VectorXd& grad) {
  const double m = a.maxCoeff();
  if (!(m > 0.0) || !std::isfinite(m)) return false;
  const Eigen::ArrayXd r = (a.array() / m).max(0.0);
  Eigen::ArrayXd power = r;  // r^(2^k)
  Eigen::ArrayXd g = r;      // r^(2^(k+1) - 1)
  for (int k = 1; k < log2_p; ++k) {
    power = power.square();
    g *= power;
  }
  const double s = (g * r).sum();  // sum r^p >= 1: the largest term is 1
  log_p = std::log(m) + std::log(s) / std::ldexp(1.0, log2_p);
  grad = g.matrix() / (m * s);
  return true;
}

struct Start {
  std::string label;
  Eigen::VectorXd w;
};

// The first `patterns` of the paper's four patterns, then `random_starts` seeded ones.
std::vector<Start> make_starts(std::size_t n, int patterns, int random_starts, std::uint64_t seed) {
  const auto N = static_cast<Eigen::Index>(n);
  const Eigen::Index c = (N - 1) / 2;  // the centre electrode (left of centre when N is even)
  std::vector<Start> s;
  auto balanced = [&](Eigen::VectorXd w) {  // spread the excess current over all electrodes
    w.array() -= w.mean();
    return w;
  };
  Eigen::VectorXd e = Eigen::VectorXd::Zero(N);
  e(c) = -1.0;
  s.push_back({"anode", balanced(e)});
  e(c) = 1.0;
  s.push_back({"cathode", balanced(e)});
  if (N >= 3) {
    Eigen::VectorXd w = Eigen::VectorXd::Zero(N);
    w(c) = 1.0;
    w(c - 1 >= 0 ? c - 1 : c + 2) = -0.5;
    w(c + 1) = -0.5;
    s.push_back({"cathode-with-anodic-neighbours", balanced(w)});
  }
  if (N >= 4) {
    Eigen::VectorXd w = -Eigen::VectorXd::Ones(N);
    for (Eigen::Index i = N / 4; i < N - N / 4; ++i) w(i) = 1.0;
    s.push_back({"widened-cathode", balanced(w)});
  }
  if (s.size() > static_cast<std::size_t>(std::max(patterns, 0)))
    s.resize(static_cast<std::size_t>(std::max(patterns, 0)));
  SplitMix64 rng{seed};  // portable: the same starts everywhere
  for (int k = 0; k < random_starts; ++k) {
    Eigen::VectorXd w(N);
    for (Eigen::Index i = 0; i < N; ++i) w(i) = 2.0 * rng.unit() - 1.0;
    s.push_back({"random-" + std::to_string(k + 1), balanced(w)});
  }
  return s;
}

// True when the electrode positions are mirror images about x = 0.
bool mirror_symmetric(const ElectrodeArray& array) {
  const auto& x = array.positions_mm;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!(std::fabs(x[i] + x[x.size() - 1 - i]) < 1e-12)) return false;
  return true;
}

}  // namespace

PNormLogRatio::PNormLogRatio(Eigen::MatrixXd off_rows, Eigen::MatrixXd target_rows, int log2_p)
    : off_(std::move(off_rows)), target_(std::move(target_rows)), log2_p_(log2_p) {}

bool PNormLogRatio::Evaluate(const double* zp, double* cost, double* gradient) const {
  const Eigen::Map<const Eigen::VectorXd> z(zp, off_.cols());
  double log_off = 0.0, log_target = 0.0;
  Eigen::VectorXd g_off, g_target;
  if (!log_pnorm(off_ * z, log2_p_, log_off, g_off)) return false;
  if (!log_pnorm(target_ * z, log2_p_, log_target, g_target)) return false;
  const double norm2 = z.squaredNorm();
  *cost = log_off - log_target + 0.5 * (norm2 - 1.0) * (norm2 - 1.0);
  if (gradient) {
    Eigen::Map<Eigen::VectorXd> g(gradient, off_.cols());
    g = off_.transpose() * g_off - target_.transpose() * g_target + 2.0 * (norm2 - 1.0) * z;
  }
  return std::isfinite(*cost);
}

namespace minimax {

Search::Search(const Setup& setup, const std::string& mode, const OptimizeOptions& opt)
    : setup_(setup), mode_(mode), opt_(opt) {
  if (!(opt.max_current_mA > 0.0)) bad_input("max current must be > 0 mA");
  if (opt.min_target_af < 0.0) bad_input("minimum target AF must be >= 0");
  basis_ = zero_sum_basis(setup.array.size());
  res_.mode = mode;
  fine_ = make_mode_problem(setup, mode, opt.polish_step_mm, false);
  conductor_ = make_conductor(setup.conductor, setup.array);
}

Search::~Search() = default;

Candidate Search::assess(const Eigen::VectorXd& z, std::string label) const {
  const Eigen::VectorXd w = basis_ * z;
  const Summary sum = summarize(setup_, std::vector<double>(w.data(), w.data() + w.size()));
  const auto r = mode_ratio(sum.peaks, mode_);
  return {r ? *r : kInf, z, std::move(label), sum.peaks[fine_.target].second};
}

// The surrogate only proposes candidates for the LP polish, so it is solved loosely.  Over
// 189 arrays (4, 8 and 16 electrodes, pitch 0.5 to 2.5 mm, every mode) this, with two
// pattern starts, gave the same ratios as p = 8, 16, ..., 256 at 200 iterations,
// tolerances of 1e-12 and four pattern starts (docs/optimization.md).
void Search::surrogate() {
  const ModeProblem coarse = make_mode_problem(setup_, mode_, opt_.surrogate_step_mm);
  ceres::GradientProblemSolver::Options so;
  so.line_search_direction_type = ceres::LBFGS;
  so.max_num_iterations = 50;
  so.function_tolerance = 1e-8;
  so.gradient_tolerance = 1e-6;
  so.parameter_tolerance = 1e-8;
  so.logging_type = ceres::SILENT;
  for (const Start& start :
       make_starts(setup_.array.size(), opt_.pattern_starts, opt_.random_starts, opt_.seed)) {
    ++res_.starts;
    Eigen::VectorXd z = basis_.transpose() * start.w;
    z /= z.norm();
    for (int log2_p : {3, 5, 8}) {
      ceres::GradientProblem problem(
          new PNormLogRatio(coarse.off_rows, coarse.target_rows, log2_p));
      double cost = 0.0;
      if (!problem.Evaluate(z.data(), &cost, nullptr)) break;  // target never depolarised
      Eigen::VectorXd trial = z;
      ceres::GradientProblemSolver::Summary summary;
      ceres::Solve(so, problem, trial.data(), &summary);
      res_.iterations += static_cast<int>(summary.iterations.size());
      res_.evaluations += summary.num_cost_evaluations + summary.num_gradient_evaluations;
      if (!summary.IsSolutionUsable() || !trial.allFinite()) break;
      z = trial / trial.norm();
    }
    Candidate c = assess(z, start.label);
    if (std::isfinite(c.ratio)) candidates_.push_back(std::move(c));
  }
}

TargetLp& Search::lp() {
  if (!lp_) {
    const double weight_bound =
        opt_.min_target_af > 0.0 ? opt_.max_current_mA / opt_.min_target_af : 0.0;
    lp_ = std::make_unique<TargetLp>(std::move(fine_.off_rows), basis_, weight_bound);
  }
  return *lp_;
}

// The optimum's target peak tends to sit under an electrode (an anode for a vertical
// target, a cathode for a horizontal one), a discrete choice that local descent does not
// make well.  A mirror-symmetric array has a mirror-symmetric problem: the seed under
// electrode N-1-i is the mirror image of the one under i, with the same ratio.
void Search::lp_seeds() {
  const Receptor& target = setup_.receptors[fine_.target];
  const std::size_t n = setup_.array.size();
  const std::size_t seeds = mirror_symmetric(setup_.array) ? (n + 1) / 2 : n;
  for (std::size_t i = 0; i < seeds; ++i) {
    const double x = setup_.array.positions_mm[i];
    const Eigen::VectorXd row =
        basis_.transpose() * unit_af(setup_, *conductor_, target, x, target.depth_min_mm);
    ++res_.lp_solves;
    if (const auto sol = lp().solve(row)) {
      Candidate c = assess(sol->z, "lp-under-electrode-" + std::to_string(i));
      if (std::isfinite(c.ratio)) candidates_.push_back(std::move(c));
    }
  }
}

void Search::keep_best() {
  std::stable_sort(candidates_.begin(), candidates_.end(),
                   [](const Candidate& a, const Candidate& b) { return a.ratio < b.ratio; });
  if (candidates_.size() > static_cast<std::size_t>(opt_.polished_candidates))
    candidates_.resize(static_cast<std::size_t>(opt_.polished_candidates));
}

Candidate Search::polish(const Candidate& c) {
  const Receptor& target = setup_.receptors[fine_.target];
  double r = opt_.min_target_af > 0.0 ? kInf : c.ratio;
  Eigen::VectorXd z = c.z;
  Peak pk = c.target_peak;
  for (int it = 0; it < 10; ++it) {
    const Eigen::VectorXd row =
        basis_.transpose() * unit_af(setup_, *conductor_, target, pk.x_mm, pk.y_mm);
    ++res_.lp_solves;
    const auto sol = lp().solve(row);
    if (!sol) break;
    const Candidate next = assess(sol->z, c.label);
    const bool improved =
        std::isinf(r) ? std::isfinite(next.ratio) : next.ratio < r - 1e-12 * std::fabs(r);
    if (!improved) break;
    r = next.ratio;
    z = sol->z;
    pk = next.target_peak;
  }
  return {r, z, c.label, pk};
}

void Search::no_answer() const {
  if (opt_.min_target_af > 0.0) {
    // The best unbounded candidate's target AF at the current limit, for the message.
    double unbounded_af = 0.0;
    if (!candidates_.empty()) {
      Eigen::VectorXd w = basis_ * candidates_.front().z;
      w *= opt_.max_current_mA / w.cwiseAbs().maxCoeff();
      const Field field(setup_, std::vector<double>(w.data(), w.data() + w.size()));
      unbounded_af = field.peak(setup_.receptors[fine_.target]).af;
    }
    bad_input("no weights reach a target AF of " + number_text(opt_.min_target_af) + " V/ms at " +
              number_text(opt_.max_current_mA) + " mA (the most selective weights reach " +
              number_text(unbounded_af) + " V/ms)");
  }
  failure("optimisation failed: no start depolarises receptor " + mode_);
}

// The largest divided by itself is 1, every other |w| stays <= 1 (division rounds
// monotonically), so no current exceeds the limit even by a rounding.
OptimizeResult Search::finish(const Candidate& best) {
  Eigen::VectorXd w = basis_ * best.z;
  w.array() -= w.mean();
  w /= w.cwiseAbs().maxCoeff();
  OptimizeResult res = res_;
  res.weights.assign(w.data(), w.data() + w.size());
  for (double& v : res.weights)
    if (v == 0.0) v = 0.0;  // no -0 in the output
  for (double v : res.weights) res.currents_mA.push_back(v * opt_.max_current_mA);
  res.summary = summarize(setup_, res.currents_mA);
  const auto r = mode_ratio(res.summary.peaks, mode_);
  res.ratio = r ? *r : kInf;
  res.target_max_af = res.summary.peaks[fine_.target].second.af;
  res.best_start = best.label;
  return res;
}

OptimizeResult Search::run() {
  surrogate();
  lp_seeds();
  keep_best();
  std::optional<Candidate> best;
  for (const Candidate& c : candidates_) {
    Candidate p = polish(c);
    if (std::isfinite(p.ratio) && (!best || p.ratio < best->ratio)) best = std::move(p);
  }
  if (!best) no_answer();
  return finish(*best);
}

}  // namespace minimax

OptimizeResult optimize_mode(const Setup& setup, const std::string& mode,
                             const OptimizeOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  minimax::Search search(setup, mode, opt);
  OptimizeResult res = search.run();
  res.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

Certificate certify_mode(const Setup& setup, const std::string& mode, double step_mm,
                         double weight_bound) {
  ModeProblem p = make_mode_problem(setup, mode, step_mm);
  // A mirror-symmetric array has a mirror-symmetric problem: x >= 0 suffices.
  const bool symmetric = mirror_symmetric(setup.array);
  TargetLp lp(std::move(p.off_rows), p.basis, weight_bound);
  Certificate c;
  c.optimum = kInf;
  for (Eigen::Index i = 0; i < p.target_rows.rows(); ++i) {
    const SamplePoint& pt = p.target_pts[static_cast<std::size_t>(i)];
    if (symmetric && pt.x_mm < -1e-12) continue;
    ++c.lp_solves;
    const auto sol = lp.solve(p.target_rows.row(i).transpose());
    if (sol && sol->value < c.optimum) {
      c.optimum = sol->value;
      c.x_mm = pt.x_mm;
      c.y_mm = pt.y_mm;
      c.weights = p.basis * sol->z;
    }
  }
  return c;
}

}  // namespace tp
