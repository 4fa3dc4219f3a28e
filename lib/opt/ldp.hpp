#pragma once
// Least-distance programming: the shortest vector in a polyhedron,
//     minimise |x|  subject to  G x >= h,
// by the method of Lawson and Hanson (Solving Least Squares Problems, 1974, ch. 23): the
// non-negative least-squares problem  min |E u - f|, u >= 0,  with E = [G^T; h^T] and
// f = (0, ..., 0, 1), gives x = -r_(1..n) / r_(n+1) from its residual r = E u - f, and
// no x when r = 0 (the constraints are inconsistent).  NNLS is their active-set algorithm
// (ch. 23, section 3).  Used to pick, among equally good weights, the one of least
// Sum w^2 (opt/focus_solver.cpp): a strictly convex problem, so its answer is unique.
//
// Eigen 3.4.0 (Debian's) has no NNLS (unsupported/Eigen/NNLS came later), GLPK solves no
// quadratic programmes, and Ceres' bounded trust region converges only approximately on
// degenerate active sets: hence these ~100 lines on Eigen's QR.

#include <optional>
#include <vector>

#include <Eigen/Dense>

namespace tp {

// min |E u - f| over u >= 0.  Deterministic; at most 3 x columns outer iterations.
Eigen::VectorXd nnls(const Eigen::MatrixXd& e, const Eigen::VectorXd& f);

// min |x| subject to g x >= h; no value when infeasible.
std::optional<Eigen::VectorXd> least_distance(const Eigen::MatrixXd& g, const Eigen::VectorXd& h);

// Rows of inequalities a z <= b as a problem grown in rounds holds them: row-major blocks.
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowBlock = Eigen::Map<const RowMajorMatrix>;

struct LeastNorm {
  Eigen::VectorXd z;   // the least |z|; `start` when not found
  bool found = false;  // else the relaxed set looked empty to rounding, or 51 passes did not end
  int passes = 0;      // least-distance programmes solved
};

// The least |z| subject to e . z = 1 and a z <= b, the rows of a given as blocks (b: one
// bound per row, in the blocks' order), by an active set of least-distance programmes.
// The equality is eliminated: z = z0 + Q v, with z0 = e / |e|^2 and Q an orthonormal basis
// of e's complement, so |z|^2 = |z0|^2 + |v|^2, and each row a z <= b becomes
// -(a Q) v >= a z0 - b (solved with unit rows, in units of |z0|, so that no test depends
// on the rows' scale).  The working set starts with the rows `start` (a feasible point: an
// LP's optimum) holds within 1e-3 scale of their bounds; each pass adds the (at most 64)
// rows its answer violates most, by more than 1e-9 scale, until it violates none.  `scale`
// is the size of the bounds (at least 1).  Deterministic.
LeastNorm least_norm_on_plane(const std::vector<RowBlock>& a, const Eigen::VectorXd& b,
                              const Eigen::VectorXd& e, const Eigen::VectorXd& start, double scale);

}  // namespace tp
