#include "opt/focus_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"
#include "opt/focus_samples.hpp"

namespace tp::focus {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

Peak max_beyond(const Setup& s, const Field& f, const Receptor& r, const FocusOptions& o,
                double radius) {
  const Region g = fibre_region(s, r);
  const bool two_d = s.array.two_d();
  auto af = [&](double x, double y, double z) {
    if (!(lateral(o, two_d, x, z) > radius)) return -kInf;
    return two_d ? f.af_3d(r.fibre, fibre_axis(r), x, y, z) : f.af(r.fibre, x, y);
  };
  Peak best{-kInf, 0, 0, 0};
  auto consider = [&](double v, double x, double y, double z) {
    if (v > best.af) best = {v, x, y, z};
  };
  if (!two_d) {
    sample_line(g.y0_mm, g.y1_mm, step_at(g.y0_mm) / 2, [&](double y) {
      const auto [x, v] =
          maximize_1d([&](double xv) { return af(xv, y, 0.0); }, g.x0_mm, g.x1_mm, step_at(y) / 4);
      consider(v, x, y, g.z0_mm);
    });
    for (const double x : {o.x_mm - radius * (1 + 1e-12), o.x_mm + radius * (1 + 1e-12)})
      if (x >= g.x0_mm && x <= g.x1_mm && g.y1_mm > g.y0_mm) {
        const auto [y, v] = maximize_1d([&](double yv) { return af(x, yv, 0.0); }, g.y0_mm, g.y1_mm,
                                        step_at(g.y0_mm) / 4);
        consider(v, x, y, g.z0_mm);
      }
    return best;
  }
  auto plane = [&](double y) {
    GridValues v = f.plane_af(r, y, step_at(y) / 2);
    for (std::size_t j = 0; j < v.t.size(); ++j)
      for (std::size_t i = 0; i < v.s.size(); ++i)
        if (!(lateral(o, two_d, v.s[i], v.t[j]) > radius)) v.v[j * v.s.size() + i] = -kInf;
    const Max2d m = maximize_2d_grid([&](double x, double z) { return af(x, y, z); }, v);
    consider(m.value, m.s, y, m.t);
  };
  plane(g.y0_mm);
  if (!(g.y1_mm > g.y0_mm)) return best;
  plane(g.y1_mm);
  const double h = step_at(g.y0_mm) / 2;
  // The walls, the disc's points masked.
  auto wall = [&](bool along_x, double fixed) {
    GridValues v = f.wall_af(r, along_x, fixed, h);
    for (std::size_t i = 0; i < v.s.size(); ++i) {
      const double x = along_x ? v.s[i] : fixed, z = along_x ? fixed : v.s[i];
      if (lateral(o, two_d, x, z) > radius) continue;
      for (std::size_t j = 0; j < v.t.size(); ++j) v.v[j * v.s.size() + i] = -kInf;
    }
    return maximize_2d_grid(
        [&](double sv, double y) { return along_x ? af(sv, y, fixed) : af(fixed, y, sv); }, v);
  };
  for (const double z : {g.z0_mm, g.z1_mm}) {
    const Max2d m = wall(true, z);
    consider(m.value, m.s, m.t, z);
  }
  for (const double x : {g.x0_mm, g.x1_mm}) {
    const Max2d m = wall(false, x);
    consider(m.value, x, m.t, m.s);
  }
  // The cylinder of the radius, where the masked region's boundary lies inside the box.
  const double rr = radius * (1 + 1e-12);
  const Max2d m = maximize_2d(
      [&](double th, double y) {
        const double x = o.x_mm + rr * std::cos(th), z = o.z_mm + rr * std::sin(th);
        if (x < g.x0_mm || x > g.x1_mm || z < g.z0_mm || z > g.z1_mm) return -kInf;
        return af(x, y, z);
      },
      -kPi, kPi, g.y0_mm, g.y1_mm, std::min(h, h / std::max(rr, 1e-3)));
  consider(m.value, o.x_mm + rr * std::cos(m.s), m.t, o.z_mm + rr * std::sin(m.s));
  return best;
}

// Every receptor's largest AF (a Summary) and the target's largest beyond the radius, on
// opt.threads threads, each task with its own Field.
std::pair<Summary, Peak> check_pattern(const Setup& s, const std::vector<double>& currents,
                                       const Receptor& target, const FocusOptions& o,
                                       double radius) {
  const std::size_t n = s.receptors.size();
  std::vector<Peak> peaks(n);
  Peak far;
  parallel_for(n + 1, std::max(1u, o.threads), [&](std::size_t i) {
    const Field f(s, currents);
    if (i < n)
      peaks[i] = f.peak(s.receptors[i]);
    else
      far = max_beyond(s, f, target, o, radius);
  });
  return {summary_of(s, peaks), far};
}

std::vector<std::pair<double, double>> peaks_above(const GridValues& g, double over) {
  std::vector<std::pair<double, double>> out;
  const std::size_t ns = g.s.size(), nt = g.t.size();
  for (std::size_t j = 0; j < nt; ++j)
    for (std::size_t i = 0; i < ns; ++i) {
      const double c = g.v[j * ns + i];
      if (!(c > over)) continue;
      bool top = true;
      for (std::size_t jj = j ? j - 1 : 0; jj <= std::min(nt - 1, j + 1) && top; ++jj)
        for (std::size_t ii = i ? i - 1 : 0; ii <= std::min(ns - 1, i + 1); ++ii)
          if (g.v[jj * ns + ii] > c) {
            top = false;
            break;
          }
      if (top) out.emplace_back(g.s[i], g.t[j]);
    }
  return out;
}

}  // namespace tp::focus
