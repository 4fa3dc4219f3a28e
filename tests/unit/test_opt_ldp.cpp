// The least-norm active set (opt/ldp.hpp, least_norm_on_plane): the least |z| with
// e . z = 1 and a z <= b, against closed forms and against every active set of a small
// problem; blocks, scale and an empty relaxed set.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "opt/ldp.hpp"

using namespace tp;

namespace {

RowMajorMatrix rows(int r, int c, std::initializer_list<double> v) {
  RowMajorMatrix m(r, c);
  auto it = v.begin();
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) m(i, j) = *it++;
  return m;
}

Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd x(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double d : v) x(i++) = d;
  return x;
}

RowBlock block(const RowMajorMatrix& m) {
  return RowBlock(m.data(), m.rows(), m.cols());
}

// min |z| with e . z = 1 and every row of a within its bound, by brute force: on each
// set S of rows held at their bounds, the least-norm z of [e; a_S] z = [1; b_S]; the
// least of those feasible.  (The optimum is one of them: its active rows'.)
Eigen::VectorXd brute_force(const RowMajorMatrix& a, const Eigen::VectorXd& b,
                            const Eigen::VectorXd& e) {
  const auto m = static_cast<int>(a.rows());
  Eigen::VectorXd best;
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<Eigen::Index> s;
    for (int i = 0; i < m; ++i)
      if (mask & (1 << i)) s.push_back(i);
    if (static_cast<Eigen::Index>(s.size()) >= e.size()) continue;
    Eigen::MatrixXd k(static_cast<Eigen::Index>(s.size()) + 1, e.size());
    Eigen::VectorXd rhs(k.rows());
    k.row(0) = e.transpose();
    rhs(0) = 1.0;
    for (std::size_t j = 0; j < s.size(); ++j) {
      k.row(static_cast<Eigen::Index>(j) + 1) = a.row(s[j]);
      rhs(static_cast<Eigen::Index>(j) + 1) = b(s[j]);
    }
    const Eigen::VectorXd z = k.completeOrthogonalDecomposition().solve(rhs);
    if ((k * z - rhs).norm() > 1e-9) continue;  // inconsistent
    if (((a * z - b).array() > 1e-9).any()) continue;
    if (best.size() == 0 || z.norm() < best.norm()) best = z;
  }
  return best;
}

}  // namespace

TEST_CASE("least norm on a plane: the projection of the origin when no row binds", "[opt][ldp]") {
  // e . z = 1 alone: z = e / |e|^2; the row z_1 <= 100 never binds.
  const Eigen::VectorXd e = vec({1.0, 2.0, 2.0});
  const RowMajorMatrix a = rows(1, 3, {1.0, 0.0, 0.0});
  const LeastNorm r = least_norm_on_plane({block(a)}, vec({100.0}), e, vec({1.0, 0.0, 0.0}), 1.0);
  REQUIRE(r.found);
  CHECK((r.z - e / 9.0).norm() < 1e-14);
  CHECK(r.passes == 1);
}

TEST_CASE("least norm on a plane: rows that bind, joined as the passes find them violated",
          "[opt][ldp]") {
  // z_1 = 1, z_2 >= 1, z_3 <= -2: the least |z| is (1, 1, -2).  The start (1, 3, -5) holds
  // no row tight: both join the working set as violated, over the passes.
  const Eigen::VectorXd e = vec({1.0, 0.0, 0.0});
  const RowMajorMatrix a = rows(3, 3, {0, -1, 0, 0, 0, 1, 0, 1, 1});
  const Eigen::VectorXd b = vec({-1.0, -2.0, 50.0});
  const LeastNorm r = least_norm_on_plane({block(a)}, b, e, vec({1.0, 3.0, -5.0}), 1.0);
  REQUIRE(r.found);
  CHECK((r.z - vec({1.0, 1.0, -2.0})).norm() < 1e-12);
  CHECK(r.passes >= 2);
}

TEST_CASE("least norm on a plane: every active set of a small problem, in two blocks",
          "[opt][ldp]") {
  // Four variables, six rows: the active set's answer is the brute force's, and the rows
  // given as one block or two give the same z.
  const Eigen::VectorXd e = vec({0.7, -0.2, 0.4, 0.1});
  const RowMajorMatrix a = rows(6, 4, {0.3,  1.2,  -0.5, 0.2,   //
                                       -1.1, 0.2,  0.7,  0.4,   //
                                       0.4,  -0.9, 1.3,  -0.6,  //
                                       0.8,  0.1,  0.2,  1.5,   //
                                       -0.2, -0.6, -0.3, 0.9,   //
                                       1.0,  0.5,  -0.8, -0.3});
  // A feasible start: a point on the plane, and bounds above its rows.
  const Eigen::VectorXd start = vec({1.0, 1.0, 1.25, 0.0});
  REQUIRE(std::fabs(e.dot(start) - 1.0) < 1e-12);
  const Eigen::VectorXd b = a * start + vec({0.05, 0.3, 0.0, 0.2, 0.01, 0.4});
  const Eigen::VectorXd expected = brute_force(a, b, e);
  REQUIRE(expected.size() == 4);
  const LeastNorm one = least_norm_on_plane({block(a)}, b, e, start, 1.0);
  REQUIRE(one.found);
  INFO("least norm " << one.z.transpose() << ", brute force " << expected.transpose());
  CHECK((one.z - expected).norm() < 1e-10);
  CHECK(one.z.norm() < start.norm());
  // Three rows bind: the answer is not the plane's nearest point to the origin.
  CHECK(((a * one.z - b).array().abs() < 1e-9).count() == 3);
  CHECK((one.z - e / e.squaredNorm()).norm() > 0.1);
  CHECK(std::fabs(e.dot(one.z) - 1.0) < 1e-12);
  CHECK(((a * one.z - b).array() <= 1e-9).all());
  // The same rows in two blocks (3 + 3), and with an empty block between them.
  const RowMajorMatrix top = a.topRows(3), bottom = a.bottomRows(3);
  const RowMajorMatrix none(0, 4);
  const LeastNorm two =
      least_norm_on_plane({block(top), block(none), block(bottom)}, b, e, start, 1.0);
  REQUIRE(two.found);
  CHECK((two.z - one.z).norm() < 1e-12);
}

TEST_CASE("least norm on a plane: the rows' scale changes nothing", "[opt][ldp]") {
  // Rows and bounds a million times larger (an AF's units): the same z.
  const Eigen::VectorXd e = vec({1.0, 1.0, 0.0});
  const RowMajorMatrix a = rows(2, 3, {1, 0, 1, 0, -1, 1});
  const Eigen::VectorXd b = vec({0.2, -0.4});
  const Eigen::VectorXd start = vec({0.0, 1.0, 0.0});
  const LeastNorm small = least_norm_on_plane({block(a)}, b, e, start, 1.0);
  const RowMajorMatrix big = a * 1e6;
  const LeastNorm large = least_norm_on_plane({block(big)}, b * 1e6, e, start, 1.0);
  REQUIRE(small.found);
  REQUIRE(large.found);
  CHECK((small.z - large.z).norm() < 1e-12);
  CHECK((small.z - brute_force(a, b, e)).norm() < 1e-12);
}

TEST_CASE("least norm on a plane: an empty set keeps the start, said so", "[opt][ldp]") {
  // z_1 = 1 and z_1 <= 0 cannot both hold: not found, and z is the start.
  const Eigen::VectorXd e = vec({1.0, 0.0});
  const RowMajorMatrix a = rows(1, 2, {1.0, 0.0});
  const Eigen::VectorXd start = vec({1.0, 0.5});
  const LeastNorm r = least_norm_on_plane({block(a)}, vec({0.0}), e, start, 1.0);
  CHECK_FALSE(r.found);
  CHECK(r.z == start);
}

TEST_CASE("least distance: the projection onto a half-space and a wedge, and infeasibility",
          "[focus][ldp]") {
  // min |x| subject to a . x >= b (b > 0): x = a b / |a|^2.
  Eigen::MatrixXd g(1, 3);
  g << 1.0, 2.0, -2.0;
  Eigen::VectorXd h(1);
  h << 3.0;
  const auto x = least_distance(g, h);
  REQUIRE(x);
  CHECK((*x - g.row(0).transpose() * (3.0 / 9.0)).norm() < 1e-14);
  // A wedge x1 >= 1, x2 >= 2 (and a slack constraint x1 + x2 >= -5): (1, 2).
  Eigen::MatrixXd w(3, 2);
  w << 1, 0, 0, 1, 1, 1;
  Eigen::VectorXd hw(3);
  hw << 1, 2, -5;
  const auto y = least_distance(w, hw);
  REQUIRE(y);
  CHECK(std::fabs((*y)(0) - 1.0) < 1e-13);
  CHECK(std::fabs((*y)(1) - 2.0) < 1e-13);
  // x >= 1 and -x >= 0 cannot both hold.
  Eigen::MatrixXd c(2, 1);
  c << 1, -1;
  Eigen::VectorXd hc(2);
  hc << 1, 0;
  CHECK_FALSE(least_distance(c, hc));
  // Against a brute-force search over every active set of a random 4 x 3 problem.
  Eigen::MatrixXd e(4, 3);
  e << 0.3, -1.2, 0.5, 1.1, 0.2, -0.7, -0.4, 0.9, 1.3, 0.8, 0.1, 0.2;
  Eigen::VectorXd f(4);
  f << 1.0, -0.5, 0.7, 0.2;
  const Eigen::VectorXd u = nnls(e, f);
  double best = INFINITY;
  for (int mask = 0; mask < 8; ++mask) {
    std::vector<int> cols;
    for (int j = 0; j < 3; ++j)
      if (mask & (1 << j)) cols.push_back(j);
    Eigen::MatrixXd ep(4, static_cast<Eigen::Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k)
      ep.col(static_cast<Eigen::Index>(k)) = e.col(cols[k]);
    Eigen::VectorXd s =
        cols.empty() ? Eigen::VectorXd() : Eigen::VectorXd(ep.colPivHouseholderQr().solve(f));
    if ((s.array() < 0).any()) continue;
    best = std::min(best, (ep * s - f).norm());
  }
  CHECK((u.array() >= 0).all());
  CHECK((e * u - f).norm() == Approx(best).epsilon(1e-12));
}
