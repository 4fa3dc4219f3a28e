// The focus solver's steps (opt/focus_solver.hpp), one at a time: the samples' count and
// geometry, a round's LP optimum and its depth, the least norm among the near-optimal
// weights, the diagnosis of a focus no weights satisfy, the check and its new samples, the
// certification against fresh LPs, and the steps composed giving optimize_focus's answer.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "model/field.hpp"
#include "opt/focus.hpp"
#include "opt/focus_check.hpp"
#include "opt/focus_samples.hpp"
#include "opt/focus_solver.hpp"
#include "opt/lp.hpp"
#include "opt/problem.hpp"

using namespace tp;
using focus::Sample;
using focus::Solver;

namespace {

FocusOptions at(double x, double z = 0.0) {
  FocusOptions o;
  o.x_mm = x;
  o.z_mm = z;
  return o;
}

// How many points focus::sample_line gives from a to b at `step`.
std::size_t line_count(double a, double b, double step) {
  return b > a ? static_cast<std::size_t>(std::max(1.0, std::ceil((b - a) / step))) + 1 : 1;
}

// A 1-D array's samples of one receptor: its depths at step_at(y0), each row along x at
// step_at(y).
std::size_t samples_1d(const Setup& s, const Receptor& r) {
  const Region g = fibre_region(s, r);
  std::size_t n = 0;
  focus::sample_line(g.y0_mm, g.y1_mm, focus::step_at(g.y0_mm),
                     [&](double y) { n += line_count(g.x0_mm, g.x1_mm, focus::step_at(y)); });
  return n;
}

bool in_region(const Setup& s, const Sample& p) {
  const Region g = fibre_region(s, s.receptors[p.receptor]);
  const double e = 1e-12;
  return p.x >= g.x0_mm - e && p.x <= g.x1_mm + e && p.y >= g.y0_mm - e && p.y <= g.y1_mm + e &&
         p.z >= g.z0_mm - e && p.z <= g.z1_mm + e;
}

// Rows of samples, built apart from the solver.
Eigen::MatrixXd rows(const Setup& s, const Solver& v, const std::vector<Sample>& pts) {
  const auto c = make_conductor(s.conductor, s.array);
  return focus::rows_of(s, *c, v.samples().tables, pts, zero_sum_basis(s.array.size()));
}

// A new LP of the solver's samples as they stand (their rows and caps), apart from its own.
std::unique_ptr<TargetLp> fresh_lp(const Setup& s, const Solver& v) {
  const focus::Samples& sm = v.samples();
  return std::make_unique<TargetLp>(
      rows(s, v, sm.off), zero_sum_basis(s.array.size()), 0.0, rows(s, v, sm.capped),
      Eigen::Map<const Eigen::VectorXd>(sm.caps.data(), static_cast<Eigen::Index>(sm.caps.size())));
}

// t at each candidate depth, each on a fresh LP (infinite where infeasible).
std::vector<double> fresh_t(const Setup& s, const Solver& v) {
  std::vector<double> t;
  for (const double y : v.all_depths()) {
    const auto sol = fresh_lp(s, v)->solve(v.focus_row(y));
    t.push_back(sol ? sol->value : INFINITY);
  }
  return t;
}

// The steps in run()'s order, up to the last round's check (or the failure).
struct Steps {
  std::optional<focus::Round> round;
  Eigen::VectorXd w;
  focus::Check check;
};
Steps rounds(Solver& v) {
  Steps st;
  v.build_samples();
  for (;;) {
    st.round = v.solve_round();
    if (!st.round) {
      if (v.widen_depths()) continue;
      return st;
    }
    st.w = v.least_norm_weights(*st.round);
    st.check = v.check(*st.round, st.w);
    if (st.check.settled() || v.result().rounds >= focus::kMaxRounds) return st;
    v.augment(st.check);
  }
}

}  // namespace

TEST_CASE("focus samples: every receptor's fibres, the target's by distance from the focus",
          "[opt][focus]") {
  const Setup s;  // the paper's 8 x 1 mm array, line2d: RA 0.7-2 mm, SAI 0.9, PC 2
  const FocusOptions o = at(-0.5);
  Solver v(s, "PC", o);
  v.build_samples();
  const focus::Samples& sm = v.samples();
  const std::size_t pc = receptor_index(s, "PC");
  const double quarter = 0.25, radius = 1.0;  // a quarter pitch; one pitch
  // Every other receptor's fibres at the step min(0.25, y / 4): RA's rows, SAI's line.
  CHECK(sm.off.size() == samples_1d(s, s.receptors[0]) + samples_1d(s, s.receptors[1]));
  for (const Sample& p : sm.off) {
    CHECK(p.receptor != pc);
    CHECK(in_region(s, p));
  }
  // PC's own line, and the two points just outside a quarter pitch and the radius.
  CHECK(sm.capped.size() + sm.inner.size() == samples_1d(s, s.receptors[pc]) + 4);
  REQUIRE(sm.caps.size() == sm.capped.size());
  REQUIRE(sm.beyond.size() == sm.capped.size());
  for (std::size_t i = 0; i < sm.capped.size(); ++i) {
    const Sample& p = sm.capped[i];
    const double d = std::fabs(p.x - o.x_mm);
    CHECK(p.receptor == pc);
    CHECK(d > quarter);
    CHECK(bool(sm.beyond[i]) == (d > radius));
    CHECK(sm.caps[i] == (d > radius ? o.spill : 1.0));
  }
  for (const Sample& p : sm.inner) CHECK(std::fabs(p.x - o.x_mm) <= quarter);
  for (const double d : {quarter, radius})
    for (const double side : {-1.0, 1.0}) {
      const double x = o.x_mm + side * d * (1 + 1e-9);
      int found = 0;
      for (const Sample& p : sm.capped) found += p.x == x;
      CHECK(found == 1);
    }
  CHECK(sm.spill_cap == o.spill);
  // The focus point's candidate depths: PC's one; RA's five down its range.
  CHECK(v.all_depths() == std::vector<double>{2.0});
  Solver ra(s, "RA", o);
  REQUIRE(ra.all_depths().size() == 5);
  for (std::size_t k = 0; k < 5; ++k)
    CHECK(ra.all_depths()[k] == Approx(0.7 + 1.3 * static_cast<double>(k) / 4).epsilon(1e-15));
}

TEST_CASE("focus samples on a grid: on the fibres, closed under the focus's mirrors",
          "[opt][focus]") {
  // A 3 x 3 grid's centre: the array and the fibres' boxes are symmetric under x -> -x and
  // z -> -z, and so are the target's samples, rings included (a multiple of 4 points).
  Setup s;
  s.array = ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.0, 1.0);
  s.conductor.model = "rect3d";
  s.lateral_margin_mm = 3.0;
  Solver v(s, "SAI", at(0.0, 0.0));
  v.build_samples();
  const focus::Samples& sm = v.samples();
  CHECK_FALSE(sm.tables.empty());  // the faces on the grid's lattice
  std::set<std::pair<long long, long long>> target;
  auto key = [](double x, double z) {
    return std::make_pair(std::llround(x * 1e8), std::llround(z * 1e8));
  };
  for (const auto* set : {&sm.capped, &sm.inner})
    for (const Sample& p : *set) {
      CHECK(in_region(s, p));
      target.insert(key(p.x, p.z));
    }
  for (const Sample& p : sm.off) CHECK(in_region(s, p));
  for (const auto& [x, z] : target) {
    CHECK(target.count({-x, z}) == 1);
    CHECK(target.count({x, -z}) == 1);
  }
  // The quarter-pitch ring (0.5 mm): a multiple of 4 points, none within it.
  const double ring = 0.5 * (1 + 1e-9);
  std::size_t on_ring = 0;
  for (const Sample& p : sm.capped)
    if (std::fabs(std::hypot(p.x, p.z) - ring) < 1e-12) ++on_ring;
  CHECK(on_ring > 0);
  CHECK(on_ring % 4 == 0);
  for (const Sample& p : sm.inner) CHECK(std::hypot(p.x, p.z) <= 0.5);
}

TEST_CASE("focus round: the LP's optimum meets every sample's bound, at the best depth",
          "[opt][focus]") {
  // RA (five candidate depths) at 0.5 with a spill of 0.5: three rounds.
  const Setup s;
  FocusOptions o = at(0.5);
  o.spill = 0.5;
  Solver v(s, "RA", o);
  v.build_samples();
  const auto round = v.solve_round();
  REQUIRE(round);
  const double t = round->lp.value;
  const Eigen::VectorXd& z = round->lp.z;
  CHECK(round->focus_row.dot(z) == Approx(1.0).epsilon(1e-9));
  const focus::Samples& sm = v.samples();
  const Eigen::MatrixXd off = rows(s, v, sm.off), capped = rows(s, v, sm.capped);
  CHECK((off * z).maxCoeff() <= t + 1e-9 * std::fabs(t));
  for (Eigen::Index i = 0; i < capped.rows(); ++i)
    CHECK(capped.row(i).dot(z) <= sm.caps[static_cast<std::size_t>(i)] + 1e-9);
  // Its depth is the best of the five, each solved on a fresh LP of the same samples.
  const std::vector<double> ts = fresh_t(s, v);
  const auto best = std::min_element(ts.begin(), ts.end());
  const double best_y = v.all_depths()[static_cast<std::size_t>(best - ts.begin())];
  CHECK(t == Approx(*best).epsilon(1e-9));
  CHECK(round->depth_mm == best_y);
  CHECK(v.result().sampled_optimum == t);
  CHECK(v.result().lp_solves == 5);
  // Rounds after the first solve at that depth alone.
  v.augment(v.check(*round, v.least_norm_weights(*round)));
  REQUIRE(v.solve_round());
  CHECK(v.depths() == std::vector<double>{round->depth_mm});
  CHECK(v.result().rounds == 2);
}

TEST_CASE("focus round: of several feasible depths, the least t", "[opt][focus]") {
  // SAI's fibres from 0.9 to 1.2 mm deep, the focus under electrode 4: the LP is feasible
  // at the top two of its five candidate depths (t about 0.104 and 0.126), and the round
  // takes the top, the better.
  Setup s;
  const std::size_t sai = receptor_index(s, "SAI");
  s.receptors[sai].depth_max_mm = 1.2;
  Solver v(s, "SAI", at(-0.5));
  v.build_samples();
  const auto round = v.solve_round();
  REQUIRE(round);
  const std::vector<double> t = fresh_t(s, v);
  REQUIRE(t.size() == 5);
  REQUIRE(std::isfinite(t[1]));
  REQUIRE(t[1] > t[0] * 1.1);  // the second depth feasible, and worse
  CHECK(round->depth_mm == v.all_depths()[0]);
  CHECK(round->lp.value == Approx(t[0]).epsilon(1e-9));
}

TEST_CASE("focus least norm: the shortest weights within the tolerance of t*", "[opt][focus]") {
  const Setup s;
  const FocusOptions o = at(-0.5);
  Solver v(s, "PC", o);
  v.build_samples();
  const auto round = v.solve_round();
  REQUIRE(round);
  const Eigen::VectorXd w = v.least_norm_weights(*round);
  CHECK(v.result().least_norm);
  CHECK(std::fabs(w.sum()) < 1e-12);
  CHECK(w.cwiseAbs().maxCoeff() == 1.0);
  // Back to z with the focus point's AF 1: no longer than the LP's vertex, every
  // off-target sample within t* (1 + tolerance), every capped one within its cap.
  const Eigen::MatrixXd basis = zero_sum_basis(s.array.size());
  Eigen::VectorXd z = basis.transpose() * w;
  z /= round->focus_row.dot(z);
  CHECK(z.norm() < round->lp.z.norm());
  const double bound = round->lp.value * (1 + o.tolerance);
  CHECK((rows(s, v, v.samples().off) * z).maxCoeff() <= bound * (1 + 1e-9));
  CHECK((rows(s, v, v.samples().capped) * z).maxCoeff() <= 1.0 + 1e-9);
}

TEST_CASE("focus diagnosis: the least spill on the samples, a tight lower bound", "[opt][focus]") {
  // SAI between two electrodes 1 mm apart under line2d: no spill up to 1 puts its peak
  // there; under rect3d the least spill is about 0.65, above the 0.3 asked.
  Setup s;
  {
    Solver v(s, "SAI", at(0.0));
    v.build_samples();
    CHECK_FALSE(v.solve_round());
    CHECK_FALSE(v.widen_depths());  // one depth: nothing more to try
    const FocusFailure why = v.diagnose();
    CHECK(why.kind == FocusFailure::Kind::impossible);
    CHECK(why.value > 1.0);
  }
  s.conductor.model = "rect3d";
  Solver v(s, "SAI", at(0.0));
  v.build_samples();
  CHECK_FALSE(v.solve_round());
  const FocusFailure why = v.diagnose();
  CHECK(why.kind == FocusFailure::Kind::least_spill);
  CHECK(why.value > 0.3);
  CHECK(why.value < 1.0);
  CHECK_THAT(focus_failure_text(s, "SAI", at(0.0), why),
             Catch::Contains("the least spill reachable is"));
  // The bound is the samples' own: a spill a little above it is feasible on them, a
  // little below it is not.
  for (const double f : {1 + 1e-3, 1 - 1e-3}) {
    FocusOptions o = at(0.0);
    o.spill = why.value * f;
    Solver u(s, "SAI", o);
    u.build_samples();
    CHECK(u.solve_round().has_value() == (f > 1));
  }
}

TEST_CASE("focus check and augment: the points that break a bound join, with their mirrors",
          "[opt][focus]") {
  // PC under electrode 4: two rounds.
  const Setup s;
  const FocusOptions o = at(-0.5);
  Solver v(s, "PC", o);
  v.build_samples();
  const auto round = v.solve_round();
  REQUIRE(round);
  const Eigen::VectorXd w = v.least_norm_weights(*round);
  const focus::Check c = v.check(*round, w);
  REQUIRE_FALSE(c.settled());
  // The check's figures are those of the weights on the continuous fibres.
  const FocusResult judged =
      evaluate_focus(s, "PC", o, std::vector<double>(w.data(), w.data() + 8));
  CHECK(c.target_af == judged.target_max_af);
  CHECK(v.result().spill == judged.spill);
  CHECK(v.result().ratio == judged.ratio);
  const std::size_t off_before = v.samples().off.size();
  const std::size_t target_before = v.samples().capped.size() + v.samples().inner.size();
  const double cap_before = v.samples().spill_cap;
  v.augment(c);
  const focus::Samples& sm = v.samples();
  // Each point, and its mirror image through the focus when that lies on the fibres.
  auto count = [&](const std::vector<Sample>& pts, double x, double y) {
    int n = 0;
    for (const Sample& p : pts) n += std::fabs(p.x - x) < 1e-12 && p.y == y;
    return n;
  };
  std::size_t off_added = 0;
  for (const Sample& p : c.add_off) {
    CHECK(count(sm.off, p.x, p.y) >= 1);
    const Region g = fibre_region(s, s.receptors[p.receptor]);
    const double mx = 2 * o.x_mm - p.x;
    const bool mirrored = mx >= g.x0_mm && mx <= g.x1_mm;
    if (mirrored) CHECK(count(sm.off, mx, p.y) >= 1);
    off_added += mirrored ? 2 : 1;
  }
  CHECK(sm.off.size() == off_before + off_added);
  CHECK(sm.capped.size() + sm.inner.size() >= target_before + c.add_target.size());
  // A spill over its bound lowers the cap beyond the radius by the excess.
  if (c.spill_over) {
    CHECK(sm.spill_cap == Approx(cap_before * o.spill * c.target_af / c.far.af));
    for (std::size_t i = 0; i < sm.caps.size(); ++i)
      if (sm.beyond[i]) CHECK(sm.caps[i] == sm.spill_cap);
  } else {
    CHECK(sm.spill_cap == cap_before);
  }
  // The next round settles it: the peak within a quarter pitch, the spill within bound.
  const auto next = v.solve_round();
  REQUIRE(next);
  const focus::Check d = v.check(*next, v.least_norm_weights(*next));
  CHECK(d.settled());
  CHECK(d.bounds_hold);
  CHECK_FALSE(d.peak_away);
  CHECK(v.result().spill <= o.spill * (1 + focus::kCheckSpill));
}

TEST_CASE("focus certify: a feasible pixel's best over its peak's places, by fresh LPs",
          "[opt][focus]") {
  // PC at the paper's array's centre (feasible): the certified optimum is the least over
  // the target's samples within a quarter pitch and the candidate depths under the focus,
  // each solved here on a new LP with the last round's rows and caps.
  const Setup s;
  FocusOptions o = at(0.0);
  o.certify = true;
  Solver v(s, "PC", o);
  const Steps st = rounds(v);
  REQUIRE(st.round);
  REQUIRE(st.check.bounds_hold);
  v.certify();
  const FocusResult& r = v.result();
  REQUIRE(r.certified_optimum);
  const focus::Samples& sm = v.samples();
  std::vector<Sample> cands = sm.inner;
  const std::size_t pc = receptor_index(s, "PC");
  for (const double y : v.all_depths()) cands.push_back({0.0, y, s.conductor.plane_z_mm, pc});
  CHECK(r.certified_points == cands.size());
  CHECK(r.certified_points > 2);
  const Eigen::MatrixXd targets = rows(s, v, cands);
  const auto fresh = fresh_lp(s, v);
  double best = INFINITY;
  for (Eigen::Index i = 0; i < targets.rows(); ++i)
    if (const auto sol = fresh->solve(targets.row(i).transpose()))
      best = std::min(best, sol->value);
  CHECK(*r.certified_optimum == Approx(best).epsilon(1e-9));
  CHECK(*r.certified_optimum <= r.sampled_optimum * (1 + 1e-9));
  CHECK(std::fabs(r.certified_at.x_mm) <= r.pitch_mm / 4 + 1e-12);
}

TEST_CASE("focus steps composed: optimize_focus's answer, bit for bit", "[opt][focus]") {
  // The steps one at a time (test_opt_focus's rounds()) and Solver::run() give the answer
  // optimize_focus prints, on a 1-D array and a grid.
  Setup grid;
  grid.array = ElectrodeArray::grid_of(3, 2, 2.0, 2.0, 1.0, 1.0);
  grid.conductor.model = "rect3d";
  const std::vector<std::tuple<Setup, std::string, FocusOptions>> cases = {
      {Setup{}, "PC", at(-0.5)}, {Setup{}, "RA", at(0.5)}, {grid, "SAI", at(2.0, 1.0)}};
  for (const auto& [s, mode, o] : cases) {
    const FocusResult direct = optimize_focus(s, mode, o);
    Solver v(s, mode, o);
    const Steps st = rounds(v);
    REQUIRE(st.round);
    REQUIRE(st.check.bounds_hold);
    const FocusResult stepped = v.finish(st.w);
    INFO(mode);
    CHECK(stepped.weights == direct.weights);
    CHECK(stepped.rounds == direct.rounds);
    CHECK(stepped.samples == direct.samples);
    CHECK(stepped.lp_solves == direct.lp_solves);
    CHECK(stepped.ratio == direct.ratio);
    Solver u(s, mode, o);
    FocusFailure why;
    const auto run = u.run(why);
    REQUIRE(run);
    CHECK(run->weights == direct.weights);
  }
}
