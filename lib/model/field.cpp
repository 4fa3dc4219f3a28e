#include "model/field.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/number.hpp"
#include "model/lattice.hpp"
#include "core/ranges.hpp"

namespace tp {

void refuse_sample_count(const char* what, double count) {
  bad_input(std::string(what) + ": " + number_text(count) + " samples, more than the cap of " +
            number_text(kMaxSamples) +
            " (fibres too shallow for the region's extent: deeper fibres, a smaller margin or a "
            "smaller array)");
}

Field::Field(const Setup& setup, std::vector<double> currents_mA)
    : setup_(setup),
      conductor_(make_conductor(setup.conductor, setup.array)),
      currents_(std::move(currents_mA)),
      scratch_(2 * setup.array.size()) {
  if (currents_.size() != setup.array.size())
    bad_input("weights: expected " + std::to_string(setup.array.size()) + " values, got " +
              std::to_string(currents_.size()));
  for (double c : currents_)
    if (!std::isfinite(c)) bad_input("weights: non-finite value");
  const ElectrodeArray& a = setup.array;
  if (a.two_d()) {
    std::vector<double> x, z;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (currents_[i] != 0.0) {
        x.push_back(a.positions_mm[i]);
        z.push_back(a.z_mm[i]);
        active_currents_.push_back(currents_[i]);
      }
    if (!x.empty() && x.size() < a.size())
      active_conductor_ =
          make_conductor(setup.conductor,
                         ElectrodeArray::pads(std::move(x), std::move(z), a.width_mm, a.length_mm));
  }
}

void Field::second_derivatives(double x_mm, double y_mm, double& xx, double& yy) const {
  const std::size_t n = currents_.size();
  double* bx = scratch_.data();
  double* by = bx + n;
  conductor_->unit_second_derivatives(x_mm, y_mm, bx, by);
  xx = 0.0;
  yy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    xx += currents_[i] * bx[i];
    yy += currents_[i] * by[i];
  }
}

double Field::af(const Fibre& fibre, double x_mm, double y_mm) const {
  // Only the derivative along the fibre.
  const bool horizontal = fibre.orientation == Orientation::horizontal;
  double* b = scratch_.data();
  conductor_->unit_second_derivatives(x_mm, y_mm, horizontal ? b : nullptr,
                                      horizontal ? nullptr : b);
  double d = 0.0;
  for (std::size_t i = 0; i < currents_.size(); ++i) d += currents_[i] * b[i];
  return fibre_factor_mm2_per_ms(fibre) * d;
}

double Field::af_3d(const Fibre& fibre, const FibreAxis& axis, double x_mm, double y_mm,
                    double z_mm) const {
  double* b = scratch_.data();
  const bool sparse = active_conductor_ != nullptr;
  (sparse ? active_conductor_ : conductor_)->unit_d2_along(x_mm, y_mm, z_mm, axis, b);
  const std::vector<double>& c = sparse ? active_currents_ : currents_;
  double d = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) d += c[i] * b[i];
  return fibre_factor_mm2_per_ms(fibre) * d;
}

double Field::from_pads(const std::vector<double>& k, double ff) const {
  double d = 0.0;
  for (std::size_t p = 0; p < k.size(); ++p) d += currents_[p] * k[p];
  return ff * d;
}

GridValues Field::plane_af(const Receptor& r, double y, double step) const {
  const Region reg = fibre_region(setup_, r);
  const FibreAxis axis = fibre_axis(r);
  const auto lat = grid_lattice(setup_.array, reg.x0_mm, reg.x1_mm, reg.z0_mm, reg.z1_mm, step);
  GridValues g;
  if (!lat) {
    g = uniform_grid(reg.x0_mm, reg.x1_mm, reg.z0_mm, reg.z1_mm, step);
    g.v.reserve(g.s.size() * g.t.size());
    for (const double z : g.t)
      for (const double x : g.s) g.v.push_back(af_3d(r.fibre, axis, x, y, z));
    return g;
  }
  // The lattice's values by correlation of the lone pad's table with the currents; the
  // region's edges off the lattice evaluated directly.
  const auto t = pad_table(setup_.conductor, setup_.array, *lat, y, axis);
  g.hs = lat->hx;
  g.ht = lat->hz;
  g.s = lat->x_axis(reg.x0_mm, reg.x1_mm);
  g.t = lat->z_axis(reg.z0_mm, reg.z1_mm);
  const double ff = fibre_factor_mm2_per_ms(r.fibre);
  const ElectrodeArray& arr = setup_.array;
  const auto ncur = static_cast<std::size_t>(arr.columns) * static_cast<std::size_t>(arr.rows);
  std::vector<double> k(ncur);
  g.v.reserve(g.s.size() * g.t.size());
  for (std::size_t j = 0; j < g.t.size(); ++j) {
    const bool z_lat = !(lat->z0_off && j == 0) && !(lat->z1_off && j + 1 == g.t.size());
    for (std::size_t i = 0; i < g.s.size(); ++i) {
      const bool x_lat = !(lat->x0_off && i == 0) && !(lat->x1_off && i + 1 == g.s.size());
      if (!(x_lat && z_lat)) {
        g.v.push_back(af_3d(r.fibre, axis, g.s[i], y, g.t[j]));
        continue;
      }
      const int a = lat->a0 + static_cast<int>(i) - (lat->x0_off ? 1 : 0);
      const int b = lat->b0 + static_cast<int>(j) - (lat->z0_off ? 1 : 0);
      t->pads_at(arr, *lat, a, b, k.data());
      g.v.push_back(from_pads(k, ff));
    }
  }
  return g;
}

GridValues Field::wall_af(const Receptor& r, bool along_x, double fixed_mm, double step) const {
  const Region reg = fibre_region(setup_, r);
  const FibreAxis axis = fibre_axis(r);
  const double s0 = along_x ? reg.x0_mm : reg.z0_mm, s1 = along_x ? reg.x1_mm : reg.z1_mm;
  GridValues g = uniform_grid(s0, s1, reg.y0_mm, reg.y1_mm, step);
  auto direct = [&](double s, double y) {
    return along_x ? af_3d(r.fibre, axis, s, y, fixed_mm) : af_3d(r.fibre, axis, fixed_mm, y, s);
  };
  auto lat = grid_lattice(setup_.array, reg.x0_mm, reg.x1_mm, reg.z0_mm, reg.z1_mm, step);
  // The lattice's step may be finer than the uniform grid's (down to half): its points too
  // within the bound, else the uniform grid.
  if (lat) {
    const double lines = along_x ? lat->a1 - lat->a0 + 3 : lat->b1 - lat->b0 + 3;
    if (!(lines * static_cast<double>(g.t.size()) <= kMaxSamples)) lat.reset();
  }
  const auto t =
      lat ? wall_table(setup_.conductor, setup_.array, *lat, along_x, fixed_mm, g.t, axis)
          : nullptr;
  if (!t) {
    g.v.reserve(g.s.size() * g.t.size());
    for (const double y : g.t)
      for (const double s : g.s) g.v.push_back(direct(s, y));
    return g;
  }
  // The lattice's lines by correlation of the lone pad's table with the currents; the
  // region's edges off the lattice evaluated directly.
  g.s = along_x ? lat->x_axis(s0, s1) : lat->z_axis(s0, s1);
  g.hs = along_x ? lat->hx : lat->hz;
  const bool off0 = along_x ? lat->x0_off : lat->z0_off, off1 = along_x ? lat->x1_off : lat->z1_off;
  const int i0 = along_x ? lat->a0 : lat->b0;
  const double ff = fibre_factor_mm2_per_ms(r.fibre);
  std::vector<double> k(setup_.array.size());
  g.v.reserve(g.s.size() * g.t.size());
  for (std::size_t j = 0; j < g.t.size(); ++j)
    for (std::size_t i = 0; i < g.s.size(); ++i) {
      if ((off0 && i == 0) || (off1 && i + 1 == g.s.size())) {
        g.v.push_back(direct(g.s[i], g.t[j]));
        continue;
      }
      t->pads_at(setup_.array, *lat, i0 + static_cast<int>(i) - (off0 ? 1 : 0), j, k.data());
      g.v.push_back(from_pads(k, ff));
    }
  return g;
}

Peak Field::peak_3d(const Receptor& r) const {
  // The AF of a fibre along a fixed axis is d2Psi/ds2 times a constant: harmonic in space
  // within each layer of the conductor, so its largest over the box of fibres lies on the
  // box's faces (maximum principle), and on the planes of the layers' interfaces inside it.
  const Region reg = fibre_region(setup_, r);
  const FibreAxis axis = fibre_axis(r);
  // The work, before any: each face's grid times the pads.
  {
    const double h = reg.y0_mm / 10.0;
    const double plane =
        (std::ceil((reg.x1_mm - reg.x0_mm) / h) + 1) * (std::ceil((reg.z1_mm - reg.z0_mm) / h) + 1);
    const double work =
        plane * (reg.y1_mm > reg.y0_mm ? 2.0 : 1.0) * static_cast<double>(setup_.array.size());
    if (!(work <= kMaxFieldWork))
      bad_input("receptor " + r.name + "'s fibres: an estimated " + number_text(work) +
                " pad evaluations to find their largest AF, more than the bound of " +
                number_text(kMaxFieldWork) + " (fibres " + number_text(reg.y0_mm) +
                " mm deep over " + number_text(reg.x1_mm - reg.x0_mm) + " x " +
                number_text(reg.z1_mm - reg.z0_mm) + " mm under " + setup_.array.describe() +
                ": deeper fibres, a smaller margin or fewer pads)");
  }
  Peak best;
  bool first = true;
  // A face: the plane y = const over x and z, sampled at a tenth of its depth (the AF
  // varies on the scale of the depth).
  auto plane = [&](double y) {
    const Max2d m =
        maximize_2d_grid([&](double x, double z) { return af_3d(r.fibre, axis, x, y, z); },
                         plane_af(r, y, y / 10.0));
    if (first || m.value > best.af) best = {m.value, m.s, y, m.t};
    first = false;
  };
  plane(reg.y0_mm);
  if (reg.y1_mm > reg.y0_mm) {
    plane(reg.y1_mm);
    for (const double y : conductor_->interfaces_mm())
      if (y > reg.y0_mm && y < reg.y1_mm) plane(y);
    const double step = reg.y0_mm / 10.0;
    auto side = [&](bool along_x, double fixed) {
      const Max2d m = maximize_2d_grid(
          [&](double s, double y) {
            return along_x ? af_3d(r.fibre, axis, s, y, fixed) : af_3d(r.fibre, axis, fixed, y, s);
          },
          wall_af(r, along_x, fixed, step));
      const Peak p = along_x ? Peak{m.value, m.s, m.t, fixed} : Peak{m.value, fixed, m.t, m.s};
      if (p.af > best.af) best = p;
    };
    side(true, reg.z0_mm);
    side(true, reg.z1_mm);
    side(false, reg.x0_mm);
    side(false, reg.x1_mm);
  }
  return best;
}

Peak Field::peak(const Receptor& r) const {
  if (setup_.array.two_d()) return peak_3d(r);
  const Region reg = fibre_region(setup_, r);
  // Sampling step: the AF varies on the scale of the depth, so a 50th of it (at most
  // 0.02 mm) resolves every local maximum before refinement.
  const double step = std::min(0.02, reg.y0_mm / 50.0);
  Peak best;
  bool first = true;
  auto consider = [&](double af, double x, double y) {
    if (first || af > best.af) best = {af, x, y};
    first = false;
  };
  auto along_x = [&](double y) {
    auto [x, v] =
        maximize_1d([&](double xv) { return af(r.fibre, xv, y); }, reg.x0_mm, reg.x1_mm, step);
    consider(v, x, y);
  };
  auto along_y = [&](double x) {
    auto [y, v] =
        maximize_1d([&](double yv) { return af(r.fibre, x, yv); }, reg.y0_mm, reg.y1_mm, step);
    consider(v, x, y);
  };
  along_x(reg.y0_mm);
  if (reg.y1_mm > reg.y0_mm) {
    // The boundary.  When the AF is harmonic in the plane (the 2-D models, Eq. 28-30), its
    // maximum over the rectangle of fibres lies there (maximum principle, Sec. 5.3).
    along_x(reg.y1_mm);
    along_y(reg.x0_mm);
    along_y(reg.x1_mm);
    // The 3-D models are harmonic in space but not in the fibres' plane: search the
    // interior too.  A grid at a tenth of the shallowest depth (the AF varies on the
    // scale of the depth), then every grid point above its 8 neighbours refined by
    // alternating line searches along x and y (maximize_1d).
    if (!conductor_->planar_harmonic()) {
      const double h = reg.y0_mm / 10.0;
      const double nx_d = std::ceil((reg.x1_mm - reg.x0_mm) / h) + 1;
      const double ny_d = std::ceil((reg.y1_mm - reg.y0_mm) / h) + 1;
      if (!(nx_d * ny_d <= kMaxSamples)) refuse_sample_count("a fibre region's grid", nx_d * ny_d);
      const auto nx = static_cast<std::size_t>(nx_d), ny = static_cast<std::size_t>(ny_d);
      const double hx = (reg.x1_mm - reg.x0_mm) / static_cast<double>(nx - 1);
      const double hy = (reg.y1_mm - reg.y0_mm) / static_cast<double>(ny - 1);
      std::vector<double> v(nx * ny);
      auto xat = [&](std::size_t i) {
        return i + 1 == nx ? reg.x1_mm : reg.x0_mm + static_cast<double>(i) * hx;
      };
      auto yat = [&](std::size_t j) {
        return j + 1 == ny ? reg.y1_mm : reg.y0_mm + static_cast<double>(j) * hy;
      };
      for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) v[j * nx + i] = af(r.fibre, xat(i), yat(j));
      for (std::size_t j = 1; j + 1 < ny; ++j)
        for (std::size_t i = 1; i + 1 < nx; ++i) {
          const double c = v[j * nx + i];
          bool peak_here = true;
          for (int dj = -1; dj <= 1 && peak_here; ++dj)
            for (int di = -1; di <= 1; ++di)
              if ((di || dj) && v[(j + dj) * nx + (i + di)] > c) peak_here = false;
          if (!peak_here) continue;
          double x = xat(i), y = yat(j), val = c;
          // One line search through the point (a scan, then Brent's), within a grid step.
          auto along = [&](double& t, double lo, double hi, double cell, auto&& f) {
            const auto [tn, vn] =
                maximize_1d(f, std::max(lo, t - cell), std::min(hi, t + cell), cell / 4);
            if (vn >= val) {
              t = tn;
              val = vn;
            }
          };
          for (int round = 0; round < 40; ++round) {
            const double x0 = x, y0 = y;
            along(x, reg.x0_mm, reg.x1_mm, hx, [&](double xv) { return af(r.fibre, xv, y); });
            along(y, reg.y0_mm, reg.y1_mm, hy, [&](double yv) { return af(r.fibre, x, yv); });
            if (std::fabs(x - x0) < 1e-9 && std::fabs(y - y0) < 1e-9) break;
          }
          consider(val, x, y);
        }
    }
  }
  return best;
}

std::size_t receptor_index(const Setup& setup, const std::string& mode) {
  for (std::size_t r = 0; r < setup.receptors.size(); ++r)
    if (setup.receptors[r].name == mode) return r;
  std::string names;
  for (const auto& r : setup.receptors) names += (names.empty() ? "" : ", ") + r.name;
  bad_input("unknown mode " + quoted_text(mode) + " (expected one of " + names + ")");
}

std::optional<double> mode_ratio(const std::vector<std::pair<std::string, Peak>>& peaks,
                                 const std::string& mode) {
  const Peak* target = nullptr;
  double off = -INFINITY;
  for (const auto& [name, p] : peaks) {
    if (name == mode)
      target = &p;
    else
      off = std::max(off, p.af);
  }
  if (!target) bad_input("unknown mode " + quoted_text(mode));
  if (!(target->af > 0.0) || peaks.size() < 2) return std::nullopt;
  return off / target->af;
}

Summary summarize(const Setup& setup, const std::vector<double>& currents_mA) {
  Field field(setup, currents_mA);
  check_fibre_reach(setup, field.conductor());  // before any work
  std::vector<Peak> peaks;
  for (const auto& r : setup.receptors) peaks.push_back(field.peak(r));
  return summary_of(setup, peaks);
}

Summary summary_of(const Setup& setup, const std::vector<Peak>& peaks) {
  Summary s;
  for (std::size_t i = 0; i < setup.receptors.size(); ++i)
    s.peaks.emplace_back(setup.receptors[i].name, peaks[i]);
  for (const auto& r : setup.receptors) s.ratios.emplace_back(r.name, mode_ratio(s.peaks, r.name));
  return s;
}

}  // namespace tp
