#include "opt/ldp.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
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

namespace {

// The rows of least_norm_on_plane's blocks by their index over all blocks.
class BlockRows {
 public:
  explicit BlockRows(const std::vector<RowBlock>& a) : a_(a) {
    for (const RowBlock& m : a) {
      first_.push_back(rows_);
      rows_ += m.rows();
    }
  }
  Eigen::Index rows() const { return rows_; }
  Eigen::RowVectorXd row(Eigen::Index i) const {
    std::size_t k = a_.size() - 1;
    while (first_[k] > i) --k;
    return Eigen::RowVectorXd(a_[k].row(i - first_[k]));
  }
  // a z - b, every row.
  Eigen::VectorXd excess(const Eigen::VectorXd& z, const Eigen::VectorXd& b) const {
    Eigen::VectorXd v(rows_);
    for (std::size_t k = 0; k < a_.size(); ++k) v.segment(first_[k], a_[k].rows()) = a_[k] * z;
    return Eigen::VectorXd(v - b);
  }

 private:
  const std::vector<RowBlock>& a_;
  std::vector<Eigen::Index> first_;
  Eigen::Index rows_ = 0;
};

// The least-distance programme in v of the working rows: -(a Q) v >= a z0 - b, each row
// divided by |a Q| and the bound also by zs (v in units of zs).
std::pair<Eigen::MatrixXd, Eigen::VectorXd> reduced_rows(const BlockRows& a,
                                                         const Eigen::VectorXd& b,
                                                         const std::vector<Eigen::Index>& work,
                                                         const Eigen::MatrixXd& q,
                                                         const Eigen::VectorXd& z0, double zs) {
  Eigen::MatrixXd g(static_cast<Eigen::Index>(work.size()), q.cols());
  Eigen::VectorXd h(static_cast<Eigen::Index>(work.size()));
  for (std::size_t k = 0; k < work.size(); ++k) {
    const Eigen::RowVectorXd r = a.row(work[k]);
    const Eigen::RowVectorXd aq = -(r * q);
    const double norm = std::max(aq.norm(), 1e-300);
    g.row(static_cast<Eigen::Index>(k)) = aq / norm;
    h(static_cast<Eigen::Index>(k)) = (r.dot(z0) - b(work[k])) / (norm * zs);
  }
  return {std::move(g), std::move(h)};
}

// The rows outside the working set that ex exceeds tol on, the most violated first (ties by
// index), at most `most`.
std::vector<Eigen::Index> most_violated(const Eigen::VectorXd& ex, double tol,
                                        const std::vector<bool>& in_work, std::size_t most) {
  std::vector<std::pair<double, Eigen::Index>> violated;
  for (Eigen::Index i = 0; i < ex.size(); ++i)
    if (ex(i) > tol && !in_work[static_cast<std::size_t>(i)]) violated.emplace_back(ex(i), i);
  const std::size_t k = std::min(most, violated.size());
  std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(k),
                    violated.end(), [](const auto& l, const auto& r) {
                      return l.first > r.first || (l.first == r.first && l.second < r.second);
                    });
  std::vector<Eigen::Index> out;
  for (std::size_t i = 0; i < k; ++i) out.push_back(violated[i].second);
  return out;
}

}  // namespace

LeastNorm least_norm_on_plane(const std::vector<RowBlock>& blocks, const Eigen::VectorXd& b,
                              const Eigen::VectorXd& e, const Eigen::VectorXd& start,
                              double scale) {
  if (blocks.empty()) failure("least norm: no rows");
  const BlockRows a(blocks);
  const Eigen::Index n_all = a.rows();
  if (b.size() != n_all || e.size() != start.size())
    failure("least norm: the rows, bounds and point disagree");
  const Eigen::VectorXd z0 = e / e.squaredNorm();
  Eigen::MatrixXd q;
  {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(e);
    const Eigen::MatrixXd full = qr.householderQ();
    q = full.rightCols(e.size() - 1);
  }
  // Working set: the rows `start` holds (nearly) tight.
  std::vector<Eigen::Index> work;
  std::vector<bool> in_work(static_cast<std::size_t>(n_all), false);
  {
    const Eigen::VectorXd ex = a.excess(start, b);
    for (Eigen::Index i = 0; i < n_all; ++i)
      if (ex(i) > -1e-3 * scale) {
        work.push_back(i);
        in_work[static_cast<std::size_t>(i)] = true;
      }
  }
  LeastNorm out;
  out.z = start;
  const double zs = z0.norm();
  for (int pass = 0;; ++pass) {
    const auto [g, h] = reduced_rows(a, b, work, q, z0, zs);
    auto v = least_distance(g, h);
    ++out.passes;
    if (!v) break;  // rounding made the relaxed set look empty: keep `start`
    *v *= zs;
    const Eigen::VectorXd zc = z0 + q * *v;
    const std::vector<Eigen::Index> add = most_violated(a.excess(zc, b), 1e-9 * scale, in_work, 64);
    if (add.empty() || pass > 50) {
      if (add.empty()) {
        out.z = zc;
        out.found = true;
      }
      break;
    }
    for (const Eigen::Index i : add) {
      work.push_back(i);
      in_work[static_cast<std::size_t>(i)] = true;
    }
  }
  return out;
}

}  // namespace tp
