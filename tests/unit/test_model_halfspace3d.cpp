// Physics checks of the 3-D half-space conductors (point3d, rect3d): closed forms, limits
// with their convergence orders, finite differences, Laplace, and the 2-D peak search.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "conductor_support.hpp"
#include "core/error.hpp"
#include "model/field.hpp"
#include "core/ranges.hpp"

using namespace tp;
using namespace tp::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRho = 3.0;  // ohm m

ConductorParams params(const std::string& model, double plane_z = 0.0, double depth = 0.0) {
  ConductorParams p;
  p.model = model;
  p.resistivity_ohm_m = kRho;
  p.plane_z_mm = plane_z;
  p.source_depth_mm = depth;
  return p;
}

// Points in the fibres' plane, at depths where the receptors lie and beyond.
const std::vector<std::pair<double, double>> kPoints = {
    {0.0, 0.9}, {0.3, 0.7}, {-1.2, 2.0}, {2.5, 1.3}, {-0.05, 0.4}, {4.0, 3.0}, {0.7, 0.25}};

}  // namespace

TEST_CASE("point3d on the surface: Psi = -rho I / (2 pi r) and the point-source AF",
          "[model][point3d]") {
  const auto c = make_conductor(params("point3d"), one_electrode(0.5, 10));
  for (auto [x, y] : kPoints) {
    const double r2 = x * x + y * y;
    const double r = std::sqrt(r2);
    // Injected (anodic) current gives rho I (2x^2 - y^2) / (2 pi r^5) along x; cathodic,
    // the project's positive current, the opposite.
    const double xx = -kRho / (2 * kPi) * (2 * x * x - y * y) / (r2 * r2 * r);
    const double yy = -kRho / (2 * kPi) * (2 * y * y - x * x) / (r2 * r2 * r);
    const D2 got = d2(*c, x, y);
    CHECK(psi(*c, x, y) == Approx(-kRho / (2 * kPi * r)).epsilon(1e-13));
    CHECK(got.xx == Approx(xx).epsilon(1e-12));
    CHECK(got.yy == Approx(yy).epsilon(1e-12));
  }
}

TEST_CASE("point3d with a buried source is the source plus its image in the surface",
          "[model][point3d]") {
  const double d = 2.0;
  const auto c = make_conductor(params("point3d", 0.0, d), one_electrode(0.5, 10));
  for (auto [x, y] : kPoints) {
    if (std::fabs(y - d) < 0.2) continue;
    const double r1 = std::hypot(x, y - d), r2 = std::hypot(x, y + d);
    CHECK(psi(*c, x, y) == Approx(-kRho / (4 * kPi) * (1 / r1 + 1 / r2)).epsilon(1e-13));
    // The insulated surface: no normal current, dPsi/dy = 0 at y = 0 (central difference).
    const double h = 1e-4;
    const double dpsi_dy_surface = (psi(*c, x, h) - psi(*c, x, -h)) / (2 * h);
    CHECK(std::fabs(dpsi_dy_surface) < 1e-9);
  }
}

TEST_CASE("3-D second derivatives match finite differences of the potential",
          "[model][rect3d][point3d]") {
  for (const std::string model : {"point3d", "rect3d"}) {
    for (double z : {0.0, 1.5}) {
      const auto c = make_conductor(params(model, z), one_electrode(0.5, 10));
      for (auto [x, y] : kPoints) {
        const double h = 1e-3 * y;
        const double p0 = psi(*c, x, y);
        const double fxx = (psi(*c, x + h, y) - 2 * p0 + psi(*c, x - h, y)) / (h * h);
        const double fyy = (psi(*c, x, y + h) - 2 * p0 + psi(*c, x, y - h)) / (h * h);
        const D2 got = d2(*c, x, y);
        const double scale = std::max(std::fabs(got.xx), std::fabs(got.yy));
        INFO(model << " z " << z << " at (" << x << ", " << y << "): " << got.xx << " vs " << fxx
                   << ", " << got.yy << " vs " << fyy);
        CHECK(std::fabs(got.xx - fxx) < 1e-5 * scale);
        CHECK(std::fabs(got.yy - fyy) < 1e-5 * scale);
      }
    }
  }
}

TEST_CASE("rect3d obeys Laplace in 3-D: Psi_xx + Psi_yy + Psi_zz = 0 below the surface",
          "[model][rect3d][laplace]") {
  for (double z : {0.0, 3.0, 6.0}) {
    const auto c = make_conductor(params("rect3d", z), one_electrode(0.5, 10));
    for (auto [x, y] : kPoints) {
      const D2 got = d2(*c, x, y);
      const double zz = rect3d_unit_zz(*c, 0, x, y);
      const double scale = std::max({std::fabs(got.xx), std::fabs(got.yy), std::fabs(zz)});
      INFO("z " << z << " at (" << x << ", " << y << ")");
      CHECK(std::fabs(got.xx + got.yy + zz) < 1e-12 * scale);
    }
  }
}

TEST_CASE("a rectangle shrunk to a point is point3d (O(w^2), Richardson to 1e-9)",
          "[model][rect3d][limit]") {
  const auto point = make_conductor(params("point3d"), one_electrode(0.5, 10));
  for (auto [x, y] : kPoints) {
    const D2 p = d2(*point, x, y);
    auto rect = [&](double s) {
      const auto c = make_conductor(params("rect3d"), one_electrode(s, s));
      return d2(*c, x, y);
    };
    // The finite size adds a term in s^2: halving s quarters the error, and the Richardson
    // combination (4 f(s/2) - f(s)) / 3 removes it.
    const double s = 2e-3 * y;
    const D2 a = rect(s), b = rect(s / 2);
    INFO("(" << x << ", " << y << "): point " << p.xx << ", rect " << a.xx << ", " << b.xx);
    const double ea = a.xx - p.xx, eb = b.xx - p.xx;
    CHECK(ea / eb == Approx(4.0).epsilon(0.01));
    CHECK((4 * b.xx - a.xx) / 3 == Approx(p.xx).epsilon(1e-9));
    CHECK((4 * b.yy - a.yy) / 3 == Approx(p.yy).epsilon(1e-9));
  }
}

TEST_CASE("a long rectangle is twice strip2d, with an error falling as (y/L)^2",
          "[model][rect3d][limit]") {
  // strip2d is a strip of infinite length in a full plane carrying I/L per unit length; on
  // the insulated surface of a half-space the same strip sets up twice its field.  At the
  // middle of a finite strip the missing ends add a relative error ~ (y / L)^2.
  for (auto [x, y] : kPoints) {
    auto rel_err = [&](double L) {
      const ElectrodeArray a = one_electrode(0.5, L);
      const auto strip = make_conductor(params("strip2d"), a);
      const auto rect = make_conductor(params("rect3d"), a);
      return d2(*rect, x, y).xx / (2 * d2(*strip, x, y).xx) - 1;
    };
    const double e1 = rel_err(100), e2 = rel_err(200), e3 = rel_err(400);
    INFO("(" << x << ", " << y << "): errors " << e1 << ", " << e2 << ", " << e3);
    CHECK(std::fabs(e3) < 2e-3);
    CHECK(e1 / e2 == Approx(4.0).epsilon(0.02));
    CHECK(e2 / e3 == Approx(4.0).epsilon(0.02));
  }
}

TEST_CASE("the 3-D models' peak over a fibre rectangle is found inside it, not only on its edge",
          "[model][rect3d][peak]") {
  // Vertical RA fibres from 0.7 to 2 mm under a rect3d array with a pattern whose largest
  // AF may lie inside the rectangle: the peak search must reach the largest value of a
  // dense brute-force grid, and no grid point may exceed it.
  Setup s;
  s.conductor = params("rect3d");
  const std::vector<double> currents = {0.3, -0.9, 1.2, 0.4, -1.5, 0.8, -0.6, 0.3};
  const Field field(s, currents);
  for (const Receptor& r : s.receptors) {
    const Peak p = field.peak(r);
    const Region g = fibre_region(s, r);
    double best = -INFINITY;
    const int nx = 1700, ny = g.y1_mm > g.y0_mm ? 131 : 1;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = g.x0_mm + (g.x1_mm - g.x0_mm) * i / (nx - 1.0);
        const double y = ny == 1 ? g.y0_mm : g.y0_mm + (g.y1_mm - g.y0_mm) * j / (ny - 1.0);
        best = std::max(best, field.af(r.fibre, x, y));
      }
    INFO(r.name << ": peak " << p.af << " at (" << p.x_mm << ", " << p.y_mm << "), grid " << best);
    CHECK(p.af >= best - 1e-12 * std::fabs(best));
    CHECK(p.af <= best * (1 + 1e-4) + 1e-12);
    CHECK(field.af(r.fibre, p.x_mm, p.y_mm) == Approx(p.af).epsilon(1e-14));
  }
}

TEST_CASE("point3d refuses a buried source among a receptor's fibres", "[model][point3d]") {
  Setup s;
  s.conductor = params("point3d", 0.0, 1.0);  // RA's fibres run from 0.7 to 2 mm
  CHECK_THROWS_AS(validate_setup(s), Error);
  s.conductor.source_depth_mm = 0.5;
  CHECK_NOTHROW(validate_setup(s));
  s.conductor.model = "nonesuch";
  CHECK_THROWS_AS(validate_setup(s), Error);
}

TEST_CASE(
    "a buried point3d source comes no nearer to fibres or grid points than the smallest "
    "depth, so the AF stays within a surface source's bound",
    "[model][point3d]") {
  const double nearest = ranges::depth_mm.lo;  // 0.01 mm
  Setup s;
  s.receptors = {{"SAI", Fibre{}, 0.9, 0.9}, {"PC", Fibre{}, 2.0, 2.0}};
  s.conductor = params("point3d", 0.0, 0.9 + nearest / 2);
  CHECK_THROWS_WITH(validate_setup(s), Catch::Contains("0.005 mm from receptor SAI's fibres") &&
                                           Catch::Contains("nearer than the smallest depth"));
  s.conductor.source_depth_mm = 0.9 - nearest / 2;
  CHECK_THROWS_AS(validate_setup(s), Error);
  s.conductor.source_depth_mm = 0.9 + 1e-8;  // the review's case: an AF of 4e24 V/ms
  CHECK_THROWS_AS(validate_setup(s), Error);
  for (const double d : {0.9 + nearest, 0.9 - nearest, 2.0 + nearest, 1.45}) {
    s.conductor.source_depth_mm = d;
    INFO("source at " << d << " mm");
    CHECK_NOTHROW(validate_setup(s));
  }
  // Out of the fibres' plane by the smallest depth: as far as a surface source can be.
  s.conductor.source_depth_mm = 0.9;
  s.conductor.plane_z_mm = nearest / 2;
  CHECK_THROWS_AS(validate_setup(s), Error);
  s.conductor.plane_z_mm = nearest;
  CHECK_NOTHROW(validate_setup(s));

  // Grid points: a source at 3 mm under the electrodes at -1, 0 and 1 mm.
  Setup g;
  g.array = ElectrodeArray::uniform(3, 1.0);
  g.conductor = params("point3d", 0.0, 3.0);
  const auto c = make_conductor(g.conductor, g.array);
  auto grid = [&](double x0, double y0) { return std::pair{Axis{x0, x0 + 2, 1}, Axis{y0, y0, 1}}; };
  for (const auto& [x0, y0] :
       {std::pair{-1.0, 3.0 - nearest / 2}, std::pair{-1.0, 3.0 + 1e-8},
        std::pair{-1.0 - nearest / 2, 3.0}, std::pair{-1.0 + 0.006, 3.007}}) {
    const auto [x, y] = grid(x0, y0);
    INFO("grid from (" << x0 << ", " << y0 << ")");
    CHECK_THROWS_WITH(check_grid(g, *c, x, y), Catch::Contains("from a point source"));
  }
  for (const auto& [x0, y0] : {std::pair{-1.0, 3.0 - nearest}, std::pair{-1.0 - nearest, 3.0},
                               std::pair{-1.0 + 0.006, 3.008}}) {
    const auto [x, y] = grid(x0, y0);
    INFO("grid from (" << x0 << ", " << y0 << ")");
    CHECK_NOTHROW(check_grid(g, *c, x, y));
  }
  g.conductor.plane_z_mm = nearest / 2;
  {
    const auto cz = make_conductor(g.conductor, g.array);
    const auto [x, y] = grid(-1.0, 3.0);
    CHECK_THROWS_AS(check_grid(g, *cz, x, y), Error);
  }
  // The AF the rule allows is bounded by a surface source's at the smallest depth: the
  // buried source is half as strong (its image is 2 d away), and a point at distance r from
  // it sees at most what the surface source gives at depth r.
  Setup surface = g;
  surface.conductor = params("point3d", 0.0, 0.0);
  const auto cs = make_conductor(surface.conductor, surface.array);
  std::vector<double> xx(3), yy(3), sx(3), sy(3);
  cs->unit_second_derivatives(-1.0, nearest, sx.data(), sy.data());
  const double bound = std::max(std::fabs(sx[0]), std::fabs(sy[0]));
  for (const auto& [x, y] : {std::pair{-1.0, 3.0 - nearest}, std::pair{-1.0, 3.0 + nearest},
                             std::pair{-1.0 - nearest, 3.0}, std::pair{-1.0 + 0.006, 3.008}}) {
    c->unit_second_derivatives(x, y, xx.data(), yy.data());
    INFO("(" << x << ", " << y << "): " << xx[0] << ", " << yy[0] << " against " << bound);
    CHECK(std::isfinite(xx[0]));
    CHECK(std::max(std::fabs(xx[0]), std::fabs(yy[0])) <= bound);
  }
}
