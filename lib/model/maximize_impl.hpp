#pragma once
// Implementation of tp::maximize_1d (included by field.hpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace tp {

// The most samples of one fibre (or one boundary segment) the models take: with the
// documented ranges (lib/model/ranges.hpp) the largest is ~6e6 (1100 mm of fibre at the
// 0.2 um step of a 0.01 mm depth).
inline constexpr double kMaxSamples = 1e7;
// Throws tp::Error (bad input) naming the count and the cap.
[[noreturn]] void refuse_sample_count(const char* what, double count);

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
    // Golden-section search on the bracket around sample i.
    double lo = i == 0 ? a : t - h;
    double hi = i + 1 == n ? b : t + h;
    constexpr double g = 0.6180339887498949;
    double c = hi - g * (hi - lo), d = lo + g * (hi - lo);
    double fc = f(c), fd = f(d);
    // To 1e-9 of the position: the value near a maximum is off by the square of that,
    // far below double rounding for the smooth fields of the models.
    for (int it = 0; it < 200 && hi - lo > 1e-9 * (1.0 + std::fabs(t)); ++it) {
      if (fc >= fd) {
        hi = d;
        d = c;
        fd = fc;
        c = hi - g * (hi - lo);
        fc = f(c);
      } else {
        lo = c;
        c = d;
        fc = fd;
        d = lo + g * (hi - lo);
        fd = f(d);
      }
    }
    const double tm = fc >= fd ? c : d;
    const double fm = fc >= fd ? fc : fd;
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
    // Golden-section searches along a line through the point, within a grid step.
    auto along = [&](double& x, double lo, double hi, double cell, auto&& g) {
      if (!(cell > 0.0)) return;
      const auto [xn, vn] =
          maximize_1d(g, std::max(lo, x - cell), std::min(hi, x + cell), cell / 4);
      if (vn > val) {
        x = xn;
        val = vn;
      }
    };
    for (int round = 0; round < 40; ++round) {
      const double sp = s, tp = t;
      along(s, s0, s1, hs, [&](double sv) { return f(sv, t); });
      along(t, t0, t1, ht, [&](double tv) { return f(s, tv); });
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
