#include "opt/ldp.hpp"

#include <cmath>
#include <vector>

#include "core/error.hpp"

namespace tp {

Eigen::VectorXd nnls(const Eigen::MatrixXd& e, const Eigen::VectorXd& f) {
  const Eigen::Index n = e.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> in_p(static_cast<std::size_t>(n), false);
  const double tol = 1e-13 * std::max(1.0, e.cwiseAbs().maxCoeff()) * std::max(1.0, f.norm()) *
                     static_cast<double>(std::max<Eigen::Index>(1, e.rows()));
  // Least squares on the passive columns; the others zero.
  auto solve_p = [&]() {
    std::vector<Eigen::Index> cols;
    for (Eigen::Index j = 0; j < n; ++j)
      if (in_p[static_cast<std::size_t>(j)]) cols.push_back(j);
    Eigen::MatrixXd ep(e.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k)
      ep.col(static_cast<Eigen::Index>(k)) = e.col(cols[k]);
    const Eigen::VectorXd sp = ep.colPivHouseholderQr().solve(f);
    Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < cols.size(); ++k) s(cols[k]) = sp(static_cast<Eigen::Index>(k));
    return s;
  };
  const int max_outer = 3 * static_cast<int>(std::max<Eigen::Index>(n, 1)) + 10;
  for (int outer = 0; outer < max_outer; ++outer) {
    const Eigen::VectorXd w = e.transpose() * (f - e * x);
    Eigen::Index t = -1;
    double best = tol;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!in_p[static_cast<std::size_t>(j)] && w(j) > best) {
        best = w(j);
        t = j;
      }
    if (t < 0) return x;  // Kuhn-Tucker conditions hold
    in_p[static_cast<std::size_t>(t)] = true;
    for (int inner = 0; inner <= n; ++inner) {
      const Eigen::VectorXd s = solve_p();
      double alpha = INFINITY;
      for (Eigen::Index j = 0; j < n; ++j)
        if (in_p[static_cast<std::size_t>(j)] && s(j) <= 0.0)
          alpha = std::min(alpha, x(j) / (x(j) - s(j)));
      if (!std::isfinite(alpha)) {  // every passive component positive
        x = s;
        break;
      }
      x += alpha * (s - x);
      for (Eigen::Index j = 0; j < n; ++j)
        if (in_p[static_cast<std::size_t>(j)] && x(j) <= tol) {
          in_p[static_cast<std::size_t>(j)] = false;
          x(j) = 0.0;
        }
    }
  }
  failure("least-distance programme: the active-set iteration did not converge");
}

std::optional<Eigen::VectorXd> least_distance(const Eigen::MatrixXd& g, const Eigen::VectorXd& h) {
  const Eigen::Index n = g.cols(), m = g.rows();
  if (h.size() != m) failure("least-distance programme: G and h disagree");
  if (m == 0) return Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd e(n + 1, m);
  e.topRows(n) = g.transpose();
  e.row(n) = h.transpose();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n + 1);
  f(n) = 1.0;
  const Eigen::VectorXd u = nnls(e, f);
  const Eigen::VectorXd r = e * u - f;
  // r_(n+1) = h . u - 1 < 0 unless the constraints are inconsistent (r = 0).
  if (!(r(n) < -1e-12)) return std::nullopt;
  return Eigen::VectorXd(-r.head(n) / r(n));
}

}  // namespace tp
