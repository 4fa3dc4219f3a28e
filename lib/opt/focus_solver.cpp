#include "opt/focus_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "core/error.hpp"
#include "core/number.hpp"
#include "opt/focus_check.hpp"
#include "opt/ldp.hpp"
#include "opt/problem.hpp"

namespace tp::focus {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The target's index, after the checks that come before any work (bad input).
std::size_t checked_target(const Setup& setup, const std::string& mode, const FocusOptions& opt) {
  check_focus(setup, opt);
  if (setup.array.size() < 2) bad_input("optimisation needs at least 2 electrodes");
  if (setup.receptors.size() < 2) bad_input("optimisation needs at least 2 receptors");
  return receptor_index(setup, mode);
}

// The focus point's candidate depths: the target's depth, or five down its range.
std::vector<double> candidate_depths(const Receptor& r) {
  std::vector<double> depths;
  if (r.depth_max_mm > r.depth_min_mm)
    for (int k = 0; k <= 4; ++k)
      depths.push_back(r.depth_min_mm + (r.depth_max_mm - r.depth_min_mm) * k / 4.0);
  else
    depths.push_back(r.depth_min_mm);
  return depths;
}

// t relaxed by the tolerance: the bound of every off-target sample around the least norm.
double relaxed_t(const Round& round, double tolerance) {
  return round.lp.value + tolerance * std::fabs(round.lp.value);
}

Eigen::Map<const Eigen::VectorXd> vector_of(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// A reflection through the focus: x -> 2 x_f - x, z -> 2 z_f - z, or both.
struct Mirror {
  bool x, z;
};

}  // namespace

Solver::Solver(const Setup& setup, const std::string& mode, const FocusOptions& opt)
    : setup_(setup),
      opt_(opt),
      target_(checked_target(setup, mode, opt)),
      two_d_(setup.array.two_d()),
      a_off_(0),
      a_cap_(0) {
  res_.mode = mode;
  res_.pitch_mm = nominal_pitch_mm(setup.array);
  res_.radius_mm = opt.radius_mm > 0.0 ? opt.radius_mm : res_.pitch_mm;
  quarter_mm_ = res_.pitch_mm / 4.0;
  conductor_ = make_conductor(setup.conductor, setup.array);
  check_fibre_reach(setup, *conductor_);
  basis_ = zero_sum_basis(setup.array.size());
  a_off_ = SampleRows(basis_.cols());
  a_cap_ = SampleRows(basis_.cols());
  all_depths_ = depths_ = candidate_depths(setup.receptors[target_]);
}

Sample Solver::focus_sample(double y) const {
  return {opt_.x_mm, y, two_d_ ? opt_.z_mm : setup_.conductor.plane_z_mm, target_};
}

Eigen::VectorXd Solver::focus_row(double y) const {
  const std::vector<Sample> p = {focus_sample(y)};
  return Eigen::VectorXd(
      rows_of(setup_, *conductor_, samples_.tables, p, basis_).row(0).transpose());
}

void Solver::add_target_sample(const Sample& p) {
  const double d = lateral(opt_, two_d_, p.x, p.z);
  if (d > res_.radius_mm) {
    samples_.capped.push_back(p);
    samples_.caps.push_back(samples_.spill_cap);
    samples_.beyond.push_back(1);
  } else if (d > quarter_mm_) {
    samples_.capped.push_back(p);
    samples_.caps.push_back(1.0);
    samples_.beyond.push_back(0);
  } else {
    samples_.inner.push_back(p);
  }
}

// The circles of a quarter pitch and of the radius just outside, at each of the target's
// depths (a 1-D array: the two points at each distance).
void Solver::add_rings(std::vector<Sample>& own) const {
  const Region g = fibre_region(setup_, setup_.receptors[target_]);
  for (const double rad : {quarter_mm_, res_.radius_mm}) {
    const double rr = rad * (1 + 1e-9);
    auto ring = [&](double y) {
      if (!two_d_) {
        for (const double x : {opt_.x_mm - rr, opt_.x_mm + rr})
          if (x >= g.x0_mm && x <= g.x1_mm) own.push_back({x, y, g.z0_mm, target_});
        return;
      }
      // A multiple of 4, so that the ring is closed under the mirrors x and z.
      const double n = 4 * std::ceil(2 * kPi * rr / step_at(y) / 4);
      if (!(n < kMaxSamples)) refuse_sample_count("a focus circle", n);
      for (double k = 0; k < n; ++k) {
        // The quarter turns exactly (cos and sin of pi are not 0 in floating point: the
        // ring's points on the focus's axes would fall a rounding off them, and out of a
        // region one sample thick, as a grid of one row with no margin).
        const double th = 2 * kPi * k / n;
        const double quarter_turns = 4 * k / n;
        const bool axis = quarter_turns == std::floor(quarter_turns);
        const double c = axis ? std::round(std::cos(th)) : std::cos(th);
        const double sn = axis ? std::round(std::sin(th)) : std::sin(th);
        const double x = opt_.x_mm + rr * c, z = opt_.z_mm + rr * sn;
        if (x >= g.x0_mm && x <= g.x1_mm && z >= g.z0_mm && z <= g.z1_mm)
          own.push_back({x, y, z, target_});
      }
    };
    sample_line(g.y0_mm, g.y1_mm, step_at(g.y0_mm), ring);
  }
}

void Solver::build_samples() {
  samples_.spill_cap = opt_.spill;
  for (std::size_t r = 0; r < setup_.receptors.size(); ++r) {
    if (r != target_) {
      sample_receptor(setup_, r, samples_.off, samples_.tables);
      continue;
    }
    std::vector<Sample> own;
    sample_receptor(setup_, r, own, samples_.tables);
    add_rings(own);
    for (const Sample& p : own) add_target_sample(p);
  }
  const double entries =
      static_cast<double>(samples_.size()) * static_cast<double>(setup_.array.size());
  if (entries > kMaxProblemEntries)
    bad_input("focus problem of " + std::to_string(samples_.size()) + " samples x " +
              std::to_string(setup_.array.size()) + " electrodes = " + number_text(entries) +
              ", more than the cap of " + number_text(kMaxProblemEntries) +
              " (fewer pads, or a smaller margin)");
}

std::optional<Round> Solver::solve_round() {
  ++res_.rounds;
  // The rounds add samples: the cap holds for them too.
  const double now =
      static_cast<double>(samples_.size()) * static_cast<double>(setup_.array.size());
  if (now > kMaxProblemEntries)
    failure("focus problem: the samples the rounds added make " + number_text(now) +
            " entries, more than the cap of " + number_text(kMaxProblemEntries));
  const Eigen::Index off_had = a_off_.n, cap_had = a_cap_.n;
  extend_rows(a_off_, setup_, *conductor_, samples_.tables, samples_.off, basis_);
  extend_rows(a_cap_, setup_, *conductor_, samples_.tables, samples_.capped, basis_);
  const Eigen::VectorXd b_cap = vector_of(samples_.caps);
  if (!lp_) {
    lp_ = std::make_unique<TargetLp>(a_off_.all(), basis_, 0.0, a_cap_.all(), b_cap);
  } else {
    lp_->append(a_off_.from(off_had), a_cap_.from(cap_had), b_cap.tail(a_cap_.n - cap_had));
    lp_->set_caps(b_cap);
  }
  // The depth is chosen in the first round; later rounds add samples at the same one.
  if (res_.rounds == 2 && best_depth_ && !all_depths_again_) depths_ = {*best_depth_};
  last_caps_ = samples_.caps;
  std::optional<Round> best;
  for (const double y : depths_) {
    Eigen::VectorXd row = focus_row(y);
    ++res_.lp_solves;
    const auto sol = lp_->solve(row);
    if (sol && (!best || sol->value < best->lp.value - 1e-12 * std::fabs(best->lp.value))) {
      best = Round{*sol, std::move(row), y};
      res_.target_depth_mm = y;
      best_depth_ = y;
    }
  }
  if (best) res_.sampled_optimum = best->lp.value;
  return best;
}

bool Solver::widen_depths() {
  if (!(depths_.size() < all_depths_.size())) return false;
  depths_ = all_depths_;
  all_depths_again_ = true;
  --res_.rounds;  // the same round, solved again
  return true;
}

double Solver::least_spill() const {
  std::vector<Sample> far, near;
  std::vector<double> near_caps;
  for (std::size_t i = 0; i < samples_.capped.size(); ++i) {
    if (samples_.beyond[i]) {
      far.push_back(samples_.capped[i]);
    } else {
      near.push_back(samples_.capped[i]);
      near_caps.push_back(1.0);
    }
  }
  double least = kInf;
  if (far.empty()) return least;
  TargetLp aux(rows_of(setup_, *conductor_, samples_.tables, far, basis_), basis_, 0.0,
               rows_of(setup_, *conductor_, samples_.tables, near, basis_), vector_of(near_caps));
  for (const double y : depths_)
    if (const auto s = aux.solve(focus_row(y))) least = std::min(least, s->value);
  return least;
}

FocusFailure Solver::diagnose() const {
  // The caps were lowered by the checks, and no weights meet them: the spill reached on
  // the continuous fibres is the last round's.
  if (res_.rounds > 1) return {FocusFailure::Kind::caps, res_.spill};
  const double least = least_spill();
  return {!std::isfinite(least) ? FocusFailure::Kind::nowhere
          : least > 1.0         ? FocusFailure::Kind::impossible
                                : FocusFailure::Kind::least_spill,
          least};
}

Eigen::VectorXd Solver::least_norm_weights(const Round& round) {
  Eigen::VectorXd bound(a_off_.n + a_cap_.n);
  bound.head(a_off_.n).setConstant(relaxed_t(round, opt_.tolerance));
  bound.tail(a_cap_.n) = vector_of(last_caps_);
  const LeastNorm ln = least_norm_on_plane({a_off_.all(), a_cap_.all()}, bound, round.focus_row,
                                           round.lp.z, std::max(1.0, std::fabs(round.lp.value)));
  res_.least_norm = ln.found;
  Eigen::VectorXd w = basis_ * ln.z;
  w.array() -= w.mean();
  w /= w.cwiseAbs().maxCoeff();
  return w;
}

// Receptor r's other lobes above `over` on the faces at its depths, found between the
// samples at once rather than one per round.
void Solver::add_lobes(std::size_t r, double over, const Field& field,
                       std::vector<Sample>& out) const {
  const Region g = fibre_region(setup_, setup_.receptors[r]);
  for (const double y : {g.y0_mm, g.y1_mm}) {
    if (y == g.y1_mm && !(g.y1_mm > g.y0_mm)) break;
    for (const auto& [px, pz] :
         peaks_above(field.plane_af(setup_.receptors[r], y, step_at(y) / 2), over))
      out.push_back({px, y, pz, r});
  }
}

Check Solver::check(const Round& round, const Eigen::VectorXd& w) {
  std::vector<double> currents;
  for (Eigen::Index i = 0; i < w.size(); ++i) currents.push_back(w(i) * opt_.max_current_mA);
  Check c;
  std::tie(c.summary, c.far) =
      check_pattern(setup_, currents, setup_.receptors[target_], opt_, res_.radius_mm);
  const Peak& peak = c.summary.peaks[target_].second;
  c.target_af = peak.af;
  const double plane_z = setup_.conductor.plane_z_mm;
  const double t_bound = relaxed_t(round, opt_.tolerance);
  std::optional<Field> field;  // for a grid's lobes
  for (std::size_t r = 0; r < setup_.receptors.size(); ++r) {
    if (r == target_) continue;
    const Peak& p = c.summary.peaks[r].second;
    const double over = t_bound * c.target_af * (1 + kCheckOff);
    if (!(p.af > over)) continue;
    c.add_off.push_back({p.x_mm, p.y_mm, two_d_ ? p.z_mm : plane_z, r});
    if (!two_d_) continue;
    if (!field) field.emplace(setup_, currents);
    add_lobes(r, over, *field, c.add_off);
  }
  c.peak_away = lateral(opt_, two_d_, peak.x_mm, peak.z_mm) > quarter_mm_;
  if (c.peak_away)
    c.add_target.push_back({peak.x_mm, peak.y_mm, two_d_ ? peak.z_mm : plane_z, target_});
  const double spill_af = opt_.spill * c.target_af;
  c.spill_over = c.far.af > spill_af;
  // Many lobes may sit at the cap, each exceeding it between samples by about as much: the
  // cap is lowered by any excess found (augment), the point added when it is more than
  // the check's tolerance.
  if (c.far.af > spill_af * (1 + kCheckSpill))
    c.add_target.push_back({c.far.x_mm, c.far.y_mm, two_d_ ? c.far.z_mm : plane_z, target_});
  res_.summary = c.summary;
  res_.target_max_af = c.target_af;
  res_.spill = std::max(0.0, c.far.af) / c.target_af;
  const auto ratio = mode_ratio(c.summary.peaks, res_.mode);
  res_.ratio = ratio ? *ratio : kInf;
  c.bounds_hold = !(c.peak_away || res_.spill > opt_.spill * (1 + kCheckSpill));
  return c;
}

// p, and its mirror images through the focus that lie within its receptor's fibres: the
// array's symmetries that fix the focus (the answer's too), and near the focus, where the
// pattern is nearly symmetric whatever the array, its next lobes (else found one per round).
template <class Add>
void Solver::with_mirrors(const Sample& p, Add&& add) const {
  add(p);
  const Region g = fibre_region(setup_, setup_.receptors[p.receptor]);
  for (const Mirror m : {Mirror{true, false}, Mirror{false, true}, Mirror{true, true}}) {
    if (m.z && !two_d_) continue;
    const double mx = m.x ? 2 * opt_.x_mm - p.x : p.x, mz = m.z ? 2 * opt_.z_mm - p.z : p.z;
    if (mx >= g.x0_mm && mx <= g.x1_mm && (!two_d_ || (mz >= g.z0_mm && mz <= g.z1_mm)))
      add(Sample{mx, p.y, mz, p.receptor});
  }
}

void Solver::augment(const Check& c) {
  if (c.spill_over) {
    samples_.spill_cap *= opt_.spill * c.target_af / c.far.af;
    for (std::size_t i = 0; i < samples_.caps.size(); ++i)
      if (samples_.beyond[i]) samples_.caps[i] = samples_.spill_cap;
  }
  for (const Sample& p : c.add_off)
    with_mirrors(p, [&](const Sample& s) { samples_.off.push_back(s); });
  for (const Sample& p : c.add_target)
    with_mirrors(p, [&](const Sample& s) { add_target_sample(s); });
}

void Solver::certify() {
  if (!lp_) failure("focus: certify before a round");
  // p* is one of the candidates, so the certified optimum is at most t*.  (The rounds' LP
  // holds the last round's rows: it added none.)
  lp_->set_caps(vector_of(last_caps_));
  std::vector<Sample> cands = samples_.inner;
  for (const double y : all_depths_) cands.push_back(focus_sample(y));
  const Eigen::MatrixXd rows = rows_of(setup_, *conductor_, samples_.tables, cands, basis_);
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    ++res_.lp_solves;
    const auto sol = lp_->solve(rows.row(i).transpose());
    if (sol && (!res_.certified_optimum || sol->value < *res_.certified_optimum)) {
      res_.certified_optimum = sol->value;
      const Sample& c = cands[static_cast<std::size_t>(i)];
      res_.certified_at = {sol->value, c.x, c.y, c.z};
    }
  }
  res_.certified_points = cands.size();
}

FocusResult Solver::finish(const Eigen::VectorXd& w) {
  res_.samples = samples_.size();
  res_.weights.assign(w.data(), w.data() + w.size());
  for (double& v : res_.weights)
    if (v == 0.0) v = 0.0;  // no -0 in the output
  res_.currents_mA.clear();
  for (double v : res_.weights) res_.currents_mA.push_back(v * opt_.max_current_mA);
  return res_;
}

std::optional<FocusResult> Solver::run(FocusFailure& why) {
  build_samples();
  Eigen::VectorXd w;
  for (;;) {
    const std::optional<Round> round = solve_round();
    if (!round) {
      if (widen_depths()) continue;
      why = diagnose();
      return std::nullopt;
    }
    w = least_norm_weights(*round);
    const Check c = check(*round, w);
    if (c.settled() || res_.rounds >= kMaxRounds) {
      if (c.bounds_hold) break;
      const Peak& peak = c.summary.peaks[target_].second;
      why = {FocusFailure::Kind::rounds, res_.spill, res_.rounds, peak.x_mm, peak.z_mm};
      return std::nullopt;
    }
    augment(c);
  }
  if (opt_.certify) certify();
  return finish(w);
}

}  // namespace tp::focus
