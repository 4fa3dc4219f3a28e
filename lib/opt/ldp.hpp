#pragma once
// Least-distance programming: the shortest vector in a polyhedron,
//     minimise |x|  subject to  G x >= h,
// by the method of Lawson and Hanson (Solving Least Squares Problems, 1974, ch. 23): the
// non-negative least-squares problem  min |E u - f|, u >= 0,  with E = [G^T; h^T] and
// f = (0, ..., 0, 1), gives x = -r_(1..n) / r_(n+1) from its residual r = E u - f, and
// no x when r = 0 (the constraints are inconsistent).  NNLS is their active-set algorithm
// (ch. 23, section 3).  Used to pick, among equally good weights, the one of least
// Sum w^2 (opt/focus.cpp): a strictly convex problem, so its answer is unique.
//
// Eigen 3.4.0 (Debian's) has no NNLS (unsupported/Eigen/NNLS came later), GLPK solves no
// quadratic programmes, and Ceres' bounded trust region converges only approximately on
// degenerate active sets: hence these ~100 lines on Eigen's QR.

#include <optional>

#include <Eigen/Dense>

namespace tp {

// min |E u - f| over u >= 0.  Deterministic; at most 3 x columns outer iterations.
Eigen::VectorXd nnls(const Eigen::MatrixXd& e, const Eigen::VectorXd& f);

// min |x| subject to g x >= h; no value when infeasible.
std::optional<Eigen::VectorXd> least_distance(const Eigen::MatrixXd& g, const Eigen::VectorXd& h);

}  // namespace tp
