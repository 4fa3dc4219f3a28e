#include "model/setup.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "core/text.hpp"

namespace tp {

void check_model_depth(const Setup& setup, double depth_mm, const std::string& what) {
  if (setup.conductor.model != "layered") return;
  const Skin& skin = effective_skin(setup.conductor);
  if (depth_mm > skin.valid_to_mm)
    bad_input(what + " " + number_beside(depth_mm, skin.valid_to_mm) +
              " mm is below the skin model's validity (" + skin.name + ": to " +
              number_text(skin.valid_to_mm) + " mm, valid_to_mm)");
}

namespace {

// The nearest a buried point source may come to a receptor's fibres or a grid point: the
// smallest depth of the range, the nearest a surface source can, so that the documented
// bound on the AF (ranges.hpp) holds everywhere.
constexpr double kNearest_mm = ranges::depth_mm.lo;
// Rounding: a distance this little (relatively) under kNearest_mm is taken as kNearest_mm.
constexpr double kRounding = 1e-9;

}  // namespace

void validate_setup(const Setup& setup) {
  const auto conductor =
      make_conductor(setup.conductor, setup.array);  // the name, and the model's own checks
  for (const Receptor& r : setup.receptors) {
    check_model_depth(setup, r.depth_max_mm, "receptor " + r.name + ": depth");
    if (r.azimuth_deg != 0.0 && !setup.array.two_d())
      bad_input("receptor " + r.name +
                ": azimuth_deg applies under a 2-D array (grid or pads); "
                "a 1-D array's fibres run along x");
  }
  const ConductorParams& c = setup.conductor;
  if (const double d = conductor->buried_source_depth_mm(); d > 0.0) {
    // The sources lie at depth d under the electrodes; every receptor's fibres at every x
    // across the array, over its depths, in the plane z = plane_z_mm (1-D) or over every z
    // of the pads (2-D).
    for (const Receptor& r : setup.receptors) {
      const double gap = d < r.depth_min_mm   ? r.depth_min_mm - d
                         : d > r.depth_max_mm ? d - r.depth_max_mm
                                              : 0.0;
      const double distance_mm = setup.array.two_d() ? gap : std::hypot(gap, c.plane_z_mm);
      if (distance_mm < kNearest_mm * (1.0 - kRounding))
        bad_input("model.source_depth_mm: " + number_text(d) + " mm is " +
                  number_beside(distance_mm, kNearest_mm) + " mm from receptor " + r.name +
                  "'s fibres (" +
                  (r.depth_max_mm > r.depth_min_mm ? "depths " + number_text(r.depth_min_mm) +
                                                         " to " + number_text(r.depth_max_mm)
                                                   : "depth " + number_text(r.depth_min_mm)) +
                  " mm), nearer than the smallest depth (" + number_text(kNearest_mm) +
                  " mm), where the field is singular or beyond its documented bound");
    }
  }
}

namespace {

// The farthest a point of [x0, x1] x [z0, z1] lies from a pad centre, laterally.
double lateral_reach_mm(const ElectrodeArray& a, double x0, double x1, double z0, double z1) {
  const double dx = std::max(std::fabs(x1 - a.x_min_mm()), std::fabs(a.x_max_mm() - x0));
  if (!a.two_d()) return dx;
  const double dz = std::max(std::fabs(z1 - a.z_min_mm()), std::fabs(a.z_max_mm() - z0));
  return std::hypot(dx, dz);
}

}  // namespace

void check_fibre_reach(const Setup& setup, const Conductor& conductor) {
  for (const Receptor& r : setup.receptors) {
    const Region g = fibre_region(setup, r);
    const double reach_mm = lateral_reach_mm(setup.array, g.x0_mm, g.x1_mm, g.z0_mm, g.z1_mm);
    conductor.check_reach(reach_mm, g.y0_mm, g.y1_mm, "receptor " + r.name + "'s fibres");
  }
}

void check_grid(const Setup& setup, const Conductor& conductor, const Axis& x, const Axis& y) {
  const std::size_t ny = y.count(), nx = x.count();
  // The farthest any point is from an electrode, along x.
  const double reach_mm = lateral_reach_mm(setup.array, x.at(0), x.at(nx - 1),
                                           setup.conductor.plane_z_mm, setup.conductor.plane_z_mm);
  for (std::size_t j = 0; j < ny; ++j)
    conductor.check_reach(reach_mm, y.at(j), y.at(j), "a grid row");
  const ConductorParams& c = setup.conductor;
  const double d = conductor.buried_source_depth_mm();
  if (!(d > 0.0)) return;
  const double near_mm = kNearest_mm * (1.0 - kRounding);
  // The rows near the source's depth (y is increasing), then the columns near an electrode:
  // a point nearer than kNearest_mm to a source (x_e, d, z_e), the grid in z = plane_z_mm.
  for (std::size_t e = 0; e < setup.array.size(); ++e) {
    const double xe = setup.array.positions_mm[e];
    const double dz = c.plane_z_mm - setup.array.z_of(e);
    if (!(std::fabs(dz) < near_mm)) continue;
    for (std::size_t j = 0; j < ny; ++j) {
      const double yj = y.at(j);
      const double off2 = (yj - d) * (yj - d) + dz * dz;
      if (!(off2 < near_mm * near_mm)) continue;
      const double half_mm = std::sqrt(near_mm * near_mm - off2);  // |x - x_e| below this
      // The columns within half_mm of xe: x is increasing with a positive step.
      const double first = std::ceil((xe - half_mm - x.min) / x.step);
      for (double i = std::max(0.0, first - 1.0); i < static_cast<double>(nx); ++i) {
        const double xi = x.at(static_cast<std::size_t>(i));
        if (xi >= xe + half_mm) break;
        if (std::fabs(xi - xe) < half_mm)
          bad_input("grid point (" + number_text(xi) + ", " + number_text(yj) + ") mm is " +
                    number_beside(std::sqrt((xi - xe) * (xi - xe) + off2), kNearest_mm) +
                    " mm from a point source (model.source_depth_mm " + number_text(d) +
                    " mm under the electrode at " + number_text(xe) +
                    " mm), nearer than the smallest depth (" + number_text(kNearest_mm) +
                    " mm), where the field is singular or beyond its documented bound: move "
                    "the grid or the source");
      }
    }
  }
}

void check_plane(const Setup& setup, const Conductor& conductor, const Axis& x, const Axis& z,
                 double y_mm) {
  const std::size_t nx = x.count(), nz = z.count();
  conductor.check_reach(lateral_reach_mm(setup.array, x.at(0), x.at(nx - 1), z.at(0), z.at(nz - 1)),
                        y_mm, y_mm, "the plane");
  const double d = conductor.buried_source_depth_mm();
  if (!(d > 0.0)) return;
  const double near_mm = kNearest_mm * (1.0 - kRounding);
  const double dy = y_mm - d;
  if (!(std::fabs(dy) < near_mm)) return;
  // The grid point nearest each source: the nearest along x and along z.
  auto nearest = [](const Axis& a, std::size_t n, double v) {
    const double i = std::clamp(std::round((v - a.min) / a.step), 0.0, static_cast<double>(n - 1));
    return a.at(static_cast<std::size_t>(i));
  };
  for (std::size_t e = 0; e < setup.array.size(); ++e) {
    const double xe = setup.array.positions_mm[e], ze = setup.array.z_of(e);
    const double xi = nearest(x, nx, xe), zi = nearest(z, nz, ze);
    const double dist = std::sqrt((xi - xe) * (xi - xe) + dy * dy + (zi - ze) * (zi - ze));
    if (dist < near_mm)
      bad_input("grid point (" + number_text(xi) + ", " + number_text(zi) + ") mm at depth " +
                number_text(y_mm) + " mm is " + number_beside(dist, kNearest_mm) +
                " mm from a point source (model.source_depth_mm " + number_text(d) +
                " mm under the pad at (" + number_text(xe) + ", " + number_text(ze) +
                ") mm), nearer than the smallest depth (" + number_text(kNearest_mm) +
                " mm), where the field is singular or beyond its documented bound: move the "
                "plane or the source");
  }
}

void check_points(const Setup& setup, const Conductor& conductor, const PointBox& box,
                  const std::function<void(const PointVisitor&)>& each) {
  const ElectrodeArray& a = setup.array;
  const ConductorParams& c = setup.conductor;
  const double dx = std::max(std::fabs(box.x1_mm - a.x_min_mm()), std::fabs(a.x_max_mm() - box.x0_mm));
  double reach = dx;
  if (box.has_z || a.two_d()) {
    const double zl = box.has_z ? box.z0_mm : c.plane_z_mm, zh = box.has_z ? box.z1_mm : c.plane_z_mm;
    reach = std::hypot(dx, std::max(std::fabs(zh - a.z_min_mm()), std::fabs(a.z_max_mm() - zl)));
  } else if (c.plane_z_mm != 0.0) {
    reach = std::hypot(dx, c.plane_z_mm);
  }
  conductor.check_reach(reach, box.y0_mm, box.y1_mm, "a point");
  const double d = conductor.buried_source_depth_mm();
  if (!(d > 0.0)) return;
  const double near_mm = kNearest_mm * (1.0 - kRounding);
  each([&](double x, double y, double z) {
    for (std::size_t e = 0; e < a.size(); ++e) {
      const double r = std::sqrt(std::pow(x - a.positions_mm[e], 2) + std::pow(y - d, 2) +
                                 std::pow(z - a.z_of(e), 2));
      if (r < near_mm)
        bad_input("point (" + number_text(x) + ", " + number_text(y) + ") mm is " +
                  number_text(r) + " mm from a point source (model.source_depth_mm " +
                  number_text(d) + " mm under the electrode at " + number_text(a.positions_mm[e]) +
                  " mm), nearer than the smallest depth (" + number_text(kNearest_mm) +
                  " mm), where the field is singular or beyond its documented bound: move the "
                  "points or the source");
    }
  });
}

Region fibre_region(const Setup& setup, const Receptor& r) {
  const ElectrodeArray& a = setup.array;
  if (a.two_d()) {
    // Horizontal fibres over the pads plus the margin, in x and z; vertical ones ascend
    // under the pads' area.
    const bool vertical = r.fibre.orientation == Orientation::vertical;
    const double mx = vertical ? 0.5 * a.width_mm : setup.lateral_margin_mm;
    const double mz = vertical ? 0.5 * a.length_mm : setup.lateral_margin_mm;
    return {a.x_min_mm() - mx, a.x_max_mm() + mx, r.depth_min_mm,
            r.depth_max_mm,    a.z_min_mm() - mz, a.z_max_mm() + mz};
  }
  const double z = setup.conductor.plane_z_mm;
  return {a.x_min_mm() - setup.lateral_margin_mm,
          a.x_max_mm() + setup.lateral_margin_mm,
          r.depth_min_mm,
          r.depth_max_mm,
          z,
          z};
}

}  // namespace tp
