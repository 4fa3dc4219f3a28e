#pragma once
// Implementation of tp::maximize_1d (included by field.hpp).

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

}  // namespace tp
