#pragma once
// Implementation of tp::maximize_1d (included by field.hpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace tp {

// The most samples of one fibre (or one boundary segment) the models take: with the
// documented ranges (lib/core/ranges.hpp) the largest is ~6e6 (1100 mm of fibre at the
// 0.2 um step of a 0.01 mm depth).
inline constexpr double kMaxSamples = 1e7;
// Throws tp::Error (bad input) naming the count and the cap.
[[noreturn]] void refuse_sample_count(const char* what, double count);

// The refinements' tolerance near x: a bracket of 1e-9 (1 + |x|) mm at the end.
inline double refine_tol(double x) {
  return 2.5e-10 * (1.0 + std::fabs(x));
}

// The maximum of f on [lo, hi] by Brent's method (R. P. Brent, Algorithms for Minimization
// without Derivatives, 1973, ch. 5: parabolic interpolation through the best three points,
// a golden-section step where the parabola's step is not trusted), starting from x in
// [lo, hi] with f(x) = fx known.  Stops when the bracket is within 4 tol; returns the best
// point seen and its value (never below fx).  A value of -inf (a masked point) is a point
// below every other.
template <class F>
std::pair<double, double> brent_max(F&& f, double lo, double hi, double x, double fx, double tol) {
  constexpr double kGold = 0.3819660112501051;  // (3 - sqrt 5) / 2
  // Minimise g = -f.
  double gx = -fx, w = x, gw = gx, v = x, gv = gx;
  double d = 0.0, e = 0.0;
  for (int it = 0; it < 200; ++it) {
    const double m = 0.5 * (lo + hi), tol2 = 2.0 * tol;
    if (std::fabs(x - m) <= tol2 - 0.5 * (hi - lo)) break;
    bool golden = true;
    if (std::fabs(e) > tol) {
      double r = (x - w) * (gx - gv);
      double q = (x - v) * (gx - gw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::fabs(q);
      const double e_prev = e;
      e = d;
      // The parabola's step, if finite, inside the bracket and under half the step before
      // last (else the search would not shrink).
      if (std::isfinite(p) && std::isfinite(q) && std::fabs(p) < std::fabs(0.5 * q * e_prev) &&
          p > q * (lo - x) && p < q * (hi - x)) {
        d = p / q;
        const double u = x + d;
        if (u - lo < tol2 || hi - u < tol2) d = x < m ? tol : -tol;
        golden = false;
      }
    }
    if (golden) {
      e = x < m ? hi - x : lo - x;
      d = kGold * e;
    }
    const double u = std::fabs(d) >= tol ? x + d : x + (d > 0.0 ? tol : -tol);
    const double gu = -f(u);
    if (gu <= gx) {
      if (u < x)
        hi = x;
      else
        lo = x;
      v = w;
      gv = gw;
      w = x;
      gw = gx;
      x = u;
      gx = gu;
    } else {
      if (u < x)
        lo = u;
      else
        hi = u;
      if (gu <= gw || w == x) {
        v = w;
        gv = gw;
        w = u;
        gw = gu;
      } else if (gu <= gv || v == x || v == w) {
        v = u;
        gv = gu;
      }
    }
  }
  return {x, -gx};
}

template <class F>
std::pair<double, double> maximize_1d(F&& f, double a, double b, double step) {
  if (!(b > a)) return {a, f(a)};
  // The count in floating point first: a huge or non-finite one is refused, never
  // converted (a double beyond size_t's range is undefined behaviour).
  const double samples = std::ceil((b - a) / step) + 1;
  if (!(samples <= kMaxSamples)) refuse_sample_count("a fibre's samples", samples);
  const auto n = static_cast<std::size_t>(samples);
  const double h = (b - a) / static_cast<double>(n - 1);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = f(i + 1 == n ? b : a + static_cast<double>(i) * h);
  std::pair<double, double> best{a, v[0]};
  for (std::size_t i = 0; i < n; ++i) {
    const double t = i + 1 == n ? b : a + static_cast<double>(i) * h;
    if (v[i] > best.second) best = {t, v[i]};
    const bool left_ok = i == 0 || v[i] >= v[i - 1];
    const bool right_ok = i + 1 == n || v[i] >= v[i + 1];
    if (!(left_ok && right_ok)) continue;
    // Brent's search (parabolic steps, golden-section ones where a parabola cannot be
    // trusted) on the bracket around sample i, from the sample.
    const double lo = i == 0 ? a : t - h;
    const double hi = i + 1 == n ? b : t + h;
    const auto [tm, fm] = brent_max(f, lo, hi, t, v[i], refine_tol(t));
    if (fm > best.second) best = {tm, fm};
  }
  return best;
}

template <class F>
Max2d maximize_2d_grid(F&& f, const GridValues& grid) {
  const std::vector<double>& gs = grid.s;
  const std::vector<double>& gt = grid.t;
  const std::vector<double>& v = grid.v;
  const std::size_t ns = gs.size(), nt = gt.size();
  const double s0 = gs.front(), s1 = gs.back(), t0 = gt.front(), t1 = gt.back();
  const double hs = grid.hs, ht = grid.ht;
  auto sat = [&](std::size_t i) { return gs[i]; };
  auto tat = [&](std::size_t j) { return gt[j]; };
  Max2d best{s0, t0, v[0]};
  std::vector<std::pair<double, std::size_t>> peaks;  // the local maxima: value, index
  for (std::size_t j = 0; j < nt; ++j)
    for (std::size_t i = 0; i < ns; ++i) {
      const double c = v[j * ns + i];
      if (c > best.value) best = {sat(i), tat(j), c};
      if (!(c > -INFINITY)) continue;  // a masked point (-inf) is no maximum to refine
      // A local maximum: no neighbour higher, and one lower (a plateau, as of all-zero
      // weights, has nothing to refine: its value is the grid's).
      bool peak_here = true, above_one = false;
      for (int dj = -1; dj <= 1 && peak_here; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (!(di || dj)) continue;
          const long ii = static_cast<long>(i) + di, jj = static_cast<long>(j) + dj;
          if (ii < 0 || jj < 0 || ii >= static_cast<long>(ns) || jj >= static_cast<long>(nt))
            continue;
          const double n = v[static_cast<std::size_t>(jj) * ns + static_cast<std::size_t>(ii)];
          if (n > c) {
            peak_here = false;
            break;
          }
          if (n < c) above_one = true;
        }
      if (above_one && peak_here) peaks.emplace_back(c, j * ns + i);
    }
  // Highest first; a local maximum more than a quarter below the best found is not
  // refined (within a grid step of a smooth field a maximum rises by far less: at the
  // steps the models use, a few per cent).
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  for (const auto& [c, k] : peaks) {
    if (c < best.value - 0.25 * std::fabs(best.value)) break;
    double s = sat(k % ns), t = tat(k / ns), val = c;
    // Searches along a line through the point: in the first round a scan within a grid
    // step (the line's maximum may lie anywhere in it), then Brent's search within a
    // quarter step of where the last round left it (the rounds move it less and less).
    auto along = [&](double& x, double lo, double hi, double cell, bool scan, auto&& g) {
      if (!(cell > 0.0)) return;
      const auto [xn, vn] =
          scan ? maximize_1d(g, std::max(lo, x - cell), std::min(hi, x + cell), cell / 4)
               : brent_max(g, std::max(lo, x - cell / 4), std::min(hi, x + cell / 4), x, val,
                           refine_tol(x));
      if (vn > val) {
        x = xn;
        val = vn;
      }
    };
    for (int round = 0; round < 40; ++round) {
      const double sp = s, tp = t;
      along(s, s0, s1, hs, round == 0, [&](double sv) { return f(sv, t); });
      along(t, t0, t1, ht, round == 0, [&](double tv) { return f(s, tv); });
      if (std::fabs(s - sp) < 1e-9 && std::fabs(t - tp) < 1e-9) break;
    }
    if (val > best.value) best = {s, t, val};
  }
  return best;
}

inline GridValues uniform_grid(double s0, double s1, double t0, double t1, double step) {
  const double ns_d = std::ceil((s1 - s0) / step) + 1, nt_d = std::ceil((t1 - t0) / step) + 1;
  if (!(ns_d * nt_d <= kMaxSamples)) refuse_sample_count("a fibre region's grid", ns_d * nt_d);
  const auto ns = static_cast<std::size_t>(ns_d), nt = static_cast<std::size_t>(nt_d);
  GridValues g;
  g.hs = ns > 1 ? (s1 - s0) / static_cast<double>(ns - 1) : 0.0;
  g.ht = nt > 1 ? (t1 - t0) / static_cast<double>(nt - 1) : 0.0;
  for (std::size_t i = 0; i < ns; ++i)
    g.s.push_back(i + 1 == ns ? s1 : s0 + static_cast<double>(i) * g.hs);
  for (std::size_t j = 0; j < nt; ++j)
    g.t.push_back(j + 1 == nt ? t1 : t0 + static_cast<double>(j) * g.ht);
  return g;
}

template <class F>
Max2d maximize_2d(F&& f, double s0, double s1, double t0, double t1, double step) {
  GridValues g = uniform_grid(s0, s1, t0, t1, step);
  g.v.reserve(g.s.size() * g.t.size());
  for (const double t : g.t)
    for (const double s : g.s) g.v.push_back(f(s, t));
  return maximize_2d_grid(f, g);
}

}  // namespace tp
