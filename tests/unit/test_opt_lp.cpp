// The linear programmes (lib/opt/lp): the target-point LP's constraints and optimality, an
// LP grown by append, scale invariance, and a GLPK failure as an error that prints nothing.
// Catch's prefixed names, as in the minimax tests beside them (glog's CHECK clashes).
#define CATCH_CONFIG_PREFIX_ALL
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include <unistd.h>

#include "core/error.hpp"
#include "opt/lp.hpp"
#include "opt/minimax.hpp"
#include "opt_support.hpp"

using namespace tp;
using tp::test::stdout_of;

CATCH_TEST_CASE("the target-point LP meets its constraints and is optimal among random weights",
                "[opt][lp]") {
  Setup s;
  const ModeProblem p = make_mode_problem(s, "SAI", 0.05);
  TargetLp lp(p.off_rows, p.basis, 0.0);
  const Eigen::Index mid = p.target_rows.rows() / 2;
  const Eigen::VectorXd a = p.target_rows.row(mid).transpose();
  const auto sol = lp.solve(a);
  CATCH_REQUIRE(sol);
  CATCH_CHECK(a.dot(sol->z) == Approx(1.0).epsilon(1e-9));
  CATCH_CHECK((p.off_rows * sol->z).maxCoeff() == Approx(sol->value).epsilon(1e-8));
  // No random zero-sum pattern, scaled to the same target AF, does better.
  std::srand(3);
  for (int k = 0; k < 2000; ++k) {
    Eigen::VectorXd z = Eigen::VectorXd::Random(a.size());
    const double t = a.dot(z);
    if (!(t > 1e-6)) continue;
    z /= t;
    CATCH_CHECK((p.off_rows * z).maxCoeff() >= sol->value - 1e-9);
  }
}

CATCH_TEST_CASE("an LP grown by append and re-capped gives the LP built at once", "[opt][lp]") {
  // The focus's rounds: samples in two parts, off-target and capped rows in each, then every
  // cap lowered.  The grown LP (warm, its rows and basis kept) and a fresh one with the final
  // rows and caps reach the same optimum, and both answers meet every row.
  Setup s;
  const ModeProblem p = make_mode_problem(s, "SAI", 0.05);
  const Eigen::Index n = p.off_rows.rows(), half = n / 2;
  const Eigen::Index mid = p.target_rows.rows() / 2;
  const Eigen::VectorXd a = p.target_rows.row(mid).transpose();
  TargetLp loose(p.off_rows, p.basis, 0.0);
  const auto l = loose.solve(a);
  CATCH_REQUIRE(l);
  // Capped rows: the two highest off-target samples of each half at the loose optimum, held
  // at 0.9 of it, then at 0.8.
  auto top2 = [&](Eigen::Index from, Eigen::Index count) {
    const Eigen::VectorXd v = p.off_rows.middleRows(from, count) * l->z;
    Eigen::Index i = 0, j = 0;
    v.maxCoeff(&i);
    Eigen::VectorXd w = v;
    w(i) = -INFINITY;
    w.maxCoeff(&j);
    Eigen::MatrixXd m(2, p.basis.cols());
    m << p.off_rows.row(from + i), p.off_rows.row(from + j);
    return m;
  };
  const Eigen::MatrixXd cap1 = top2(0, half), cap2 = top2(half, n - half);
  const double t = l->value;
  TargetLp grown(p.off_rows.topRows(half), p.basis, 0.0, cap1, Eigen::Vector2d(0.9 * t, 0.95 * t));
  CATCH_REQUIRE(grown.solve(a));
  grown.append(p.off_rows.bottomRows(n - half), cap2, Eigen::Vector2d(0.92 * t, 0.97 * t));
  // Each cap its own value: a cap given to the wrong row would change the optimum.
  const Eigen::Vector4d caps = Eigen::Vector4d(0.8, 0.85, 0.75, 0.9) * t;
  grown.set_caps(caps);
  const auto g = grown.solve(a);
  Eigen::MatrixXd all_caps(4, p.basis.cols());
  all_caps << cap1, cap2;
  TargetLp fresh(p.off_rows, p.basis, 0.0, all_caps, caps);
  const auto f = fresh.solve(a);
  CATCH_REQUIRE(g);
  CATCH_REQUIRE(f);
  CATCH_CHECK(g->value == Approx(f->value).epsilon(1e-7));
  for (const auto* sol : {&*g, &*f}) {
    CATCH_CHECK(a.dot(sol->z) == Approx(1.0).epsilon(1e-9));
    CATCH_CHECK((p.off_rows * sol->z).maxCoeff() <= sol->value * (1 + 1e-7));
    CATCH_CHECK(((all_caps * sol->z).array() <= caps.array() * (1 + 1e-7)).all());
  }
  // The caps bind: with them the optimum is higher.
  CATCH_CHECK(f->value > t * (1 + 1e-6));
  CATCH_CHECK_THROWS_AS(grown.set_caps(Eigen::Vector2d(0.1, 0.1)), Error);
}

CATCH_TEST_CASE("a GLPK failure is an error, never abort(), and prints nothing",
                "[opt][lp][glpk]") {
  std::string printed;
  bool thrown = false;
  printed = stdout_of([&] {
    try {
      provoke_glpk_error();
    } catch (const Error& e) {
      thrown = true;
      CATCH_CHECK(e.code() == ExitCode::failure);
      CATCH_CHECK(std::string(e.what()).find("GLPK") != std::string::npos);
    }
  });
  CATCH_CHECK(thrown);
  CATCH_CHECK(printed.empty());
  // GLPK works again afterwards (its environment was rebuilt).
  const Eigen::MatrixXd basis = zero_sum_basis(3);
  Eigen::MatrixXd off(2, 2);
  off << 1, 0, 0, 1;
  TargetLp lp(off, basis, 0.0);
  Eigen::VectorXd target(2);
  target << 1, 1;
  const auto sol = lp.solve(target);
  CATCH_REQUIRE(sol);
  CATCH_CHECK(sol->value == Approx(0.5));  // z = (0.5, 0.5): both off rows at 0.5
}

CATCH_TEST_CASE("the LP is scale invariant: absurd AF scales give the same ratio", "[opt][lp]") {
  const Eigen::MatrixXd basis = zero_sum_basis(4);
  Eigen::MatrixXd off(3, 3);
  off << 1, -2, 0.5, 0.3, 1, -1, -0.2, 0.7, 1;
  Eigen::VectorXd target(3);
  target << 2, 1, 0.5;
  TargetLp plain(off, basis, 0.0);
  const auto a = plain.solve(target);
  CATCH_REQUIRE(a);
  for (double s : {1e-200, 1e-30, 1e30, 1e200}) {
    TargetLp scaled(off * s, basis, 0.0);
    const auto b = scaled.solve(target * s);
    CATCH_REQUIRE(b);
    CATCH_CHECK(b->value == Approx(a->value).epsilon(1e-9));
    CATCH_CHECK((b->z * s - a->z).norm() <= 1e-9 * a->z.norm());
  }
  Eigen::MatrixXd bad = off;
  bad(1, 1) = std::numeric_limits<double>::infinity();
  CATCH_CHECK_THROWS_AS(TargetLp(bad, basis, 0.0), Error);
}
