#pragma once
// The derivative-free search the fibre objectives share (threshold_objective.hpp,
// selectivity_design.hpp): Nelder-Mead over the weights' zero-sum subspace.  The objectives
// are piecewise constant (thresholds on an amplitude lattice, fractions of populations), so
// only the order of values counts, which Nelder-Mead alone uses.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

namespace tp::fibre {

// z (n - 1 free weights) -> w: the last weight balances the sum; scaled to max |w| = 1.
// Empty when every weight is 0 (or not finite).
inline std::vector<double> zero_sum_weights(const std::vector<double>& z) {
  std::vector<double> w(z);
  w.push_back(-std::accumulate(z.begin(), z.end(), 0.0));
  double m = 0.0;
  for (double x : w) m = std::max(m, std::fabs(x));
  if (!(m > 0.0) || !std::isfinite(m)) return {};
  for (double& x : w) x /= m;  // the largest becomes exactly +-1
  return w;
}

// Nelder-Mead from x0 (whose value is f0), a first simplex of one step along each
// coordinate, until the simplex is smaller than 1e-3 or count() reaches cap.
template <class F, class C>
void nelder_mead(const std::vector<double>& x0, double f0, double initial_step, std::size_t cap,
                 F&& evaluate, C&& count) {
  const std::size_t d = x0.size();
  std::vector<std::vector<double>> x(d + 1, x0);
  std::vector<double> f(d + 1, f0);
  for (std::size_t k = 0; k < d && count() < cap; ++k) {
    x[k + 1][k] += x[k + 1][k] > 0 ? -initial_step : initial_step;
    f[k + 1] = evaluate(x[k + 1]);
  }
  std::vector<std::size_t> order(d + 1);
  auto point = [&](const std::vector<double>& c, const std::vector<double>& p, double t) {
    std::vector<double> r(d);
    for (std::size_t i = 0; i < d; ++i) r[i] = c[i] + t * (p[i] - c[i]);
    return r;
  };
  while (count() + 2 <= cap) {
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return f[a] < f[b]; });
    const std::size_t lo = order.front(), hi = order.back(), next = order[d - 1];
    double size = 0.0;
    for (std::size_t k = 0; k <= d; ++k)
      for (std::size_t i = 0; i < d; ++i) size = std::max(size, std::fabs(x[k][i] - x[lo][i]));
    if (size < 1e-3) break;
    std::vector<double> c(d, 0.0);
    for (std::size_t k = 0; k <= d; ++k)
      if (k != hi)
        for (std::size_t i = 0; i < d; ++i) c[i] += x[k][i] / static_cast<double>(d);
    const std::vector<double> xr = point(c, x[hi], -1.0);
    const double fr = evaluate(xr);
    if (fr < f[lo]) {
      const std::vector<double> xe = point(c, x[hi], -2.0);
      const double fe = evaluate(xe);
      if (fe < fr) {
        x[hi] = xe;
        f[hi] = fe;
      } else {
        x[hi] = xr;
        f[hi] = fr;
      }
    } else if (fr < f[next]) {
      x[hi] = xr;
      f[hi] = fr;
    } else {
      const bool outside = fr < f[hi];
      const std::vector<double> xc = point(c, outside ? xr : x[hi], 0.5);
      const double fc = evaluate(xc);
      if (fc < std::min(fr, f[hi])) {
        x[hi] = xc;
        f[hi] = fc;
      } else {  // shrink towards the best
        for (std::size_t k = 0; k <= d && count() < cap; ++k) {
          if (k == lo) continue;
          x[k] = point(x[lo], x[k], 0.5);
          f[k] = evaluate(x[k]);
        }
      }
    }
  }
}

}  // namespace tp::fibre
