// The layered conductor (lib/model/layered_rect.cpp): the uniform limit, the two-layer image
// series for rectangles, finite differences, Laplace, the interface conditions and reciprocity.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "conductor_support.hpp"
#include "core/error.hpp"
#include "model/conductor.hpp"
#include "model/layered.hpp"
#include "model/quadrature.hpp"
#include "model/skin.hpp"

using namespace tp;
using namespace tp::test;

namespace {

// The image series of a two-layer half-space (top rho1, thickness h, over rho2) seen at
// depth y: add(coefficient, image depth) for each image, until its weight is below 1e-17.
template <class F>
void image_series(double rho1, double rho2, double h, double y, F&& add) {
  const double k = (rho2 - rho1) / (rho2 + rho1);
  double kn = 1.0;
  if (y < h) {
    add(rho1, y);
    for (int n = 1; n < 4000 && std::fabs(kn) > 1e-17; ++n) {
      kn *= k;
      add(rho1 * kn, y - 2 * n * h);
      add(rho1 * kn, y + 2 * n * h);
    }
  } else {
    for (int n = 0; n < 4000 && std::fabs(kn) > 1e-17; ++n, kn *= k)
      add(rho1 * (1 + k) * kn, y + 2 * n * h);
  }
}

// A rectangle on a two-layer half-space (top rho1, thickness h, over rho2) by the image
// series: each image a rect3d rectangle (rho 1) seen at the image's depth |v|; the
// second derivatives of a rect3d field are even in the depth.
D2 two_layer_rect(double rho1, double rho2, double h, double w, double l, double z, double x,
                  double y) {
  ConductorParams p;
  p.model = "rect3d";
  p.resistivity_ohm_m = 1.0;
  p.plane_z_mm = z;
  const auto unit = make_conductor(p, one_electrode(w, l));
  D2 s{0, 0};
  image_series(rho1, rho2, h, y, [&](double coef, double v) {
    const D2 t = d2(*unit, x, std::fabs(v));
    s.xx += coef * t.xx;
    s.yy += coef * t.yy;
  });
  return s;
}

// A layered conductor over any array (a 2-D grid included).
std::unique_ptr<Conductor> layered_on(const ElectrodeArray& a, std::vector<Layer> layers,
                                      double plane_z = 0.0) {
  ConductorParams p;
  p.model = "layered";
  p.plane_z_mm = plane_z;
  p.skin.layers = std::move(layers);
  p.skin.layer_names.assign(p.skin.layers.size(), "x");
  return make_conductor(p, a);
}

// One w x l electrode on the layers, fibres in the plane z.
std::unique_ptr<Conductor> layered(std::vector<Layer> layers, double w = 0.5, double l = 10.0,
                                   double z = 0.0) {
  return layered_on(one_electrode(w, l), std::move(layers), z);
}

}  // namespace

TEST_CASE("layered: equal layers are rect3d", "[model][layered]") {
  ConductorParams p;
  p.model = "rect3d";
  p.resistivity_ohm_m = 3.0;
  const auto rect = make_conductor(p, one_electrode(0.5, 10));
  const auto one = layered({{0.0, 3.0}});
  const auto equal = layered({{0.3, 3.0}, {1.0, 3.0}, {0.0, 3.0}});
  for (double y : {0.05, 0.3, 0.9, 2.0})
    for (double x : {0.0, 0.2, 0.6, 3.0}) {
      const D2 want = d2(*rect, x, y);
      for (const auto* c : {one.get(), equal.get()}) {
        const D2 got = d2(*c, x, y);
        CHECK(got.xx == Approx(want.xx).epsilon(1e-6));
        CHECK(got.yy == Approx(want.yy).epsilon(1e-6));
      }
    }
}

TEST_CASE("layered: two layers match the image series of rectangles", "[model][layered]") {
  for (auto [rho1, rho2, h] :
       {std::tuple{3.0, 12.0, 0.8}, std::tuple{12.0, 3.0, 0.5}, std::tuple{30.0, 3.0, 0.4}}) {
    for (double z : {0.0, 3.0}) {
      const auto c = layered({{h, rho1}, {0.0, rho2}}, 0.5, 10.0, z);
      for (double y : {0.05, 0.3, h - 0.01, h + 0.01, 0.9, 1.7, 3.0}) {
        double scale = 0;
        for (double x : {0.0, 0.25, 1.0}) {
          const D2 t = two_layer_rect(rho1, rho2, h, 0.5, 10.0, z, x, y);
          scale = std::max({scale, std::fabs(t.xx), std::fabs(t.yy)});
        }
        for (double x : {0.0, 0.1, 0.25, 0.4, 1.0, 2.3, 6.0, 14.0}) {
          const D2 want = two_layer_rect(rho1, rho2, h, 0.5, 10.0, z, x, y);
          const D2 got = d2(*c, x, y);
          INFO("rho " << rho1 << "/" << rho2 << " h " << h << " z " << z << " at (" << x << ", "
                      << y << "): xx " << got.xx << " vs " << want.xx << ", yy " << got.yy << " vs "
                      << want.yy);
          CHECK(std::fabs(got.xx - want.xx) < 1e-6 * scale);
          CHECK(std::fabs(got.yy - want.yy) < 1e-6 * scale);
        }
      }
    }
  }
}

namespace {

// The fingertip-like stacks of the tests: a resistive stratum corneum (hydrated, dry), a
// thin viable epidermis, the dermis and the fat.
std::vector<Layer> fingertip_like(double sc_rho) {
  return {{0.35, sc_rho}, {0.25, 10.0}, {1.4, 2.3}, {0.0, 45.0}};
}

}  // namespace

TEST_CASE("layered: a fingertip stack matches the point response integrated over the rectangle",
          "[model][layered][numerics]") {
  // An independent path: LayeredHalfSpace::point (its own Hankel rule, and d2/dy2 directly
  // rather than by Laplace) integrated over the 0.5 x 10 mm rectangle by 2-D quadrature.
  for (double sc : {1500.0, 5000.0}) {
    const LayeredHalfSpace stack(fingertip_like(sc));
    const auto c = layered(fingertip_like(sc));
    for (auto [x, y] : {std::pair{0.0, 0.7}, std::pair{0.45, 0.9}, std::pair{1.5, 2.0},
                        std::pair{0.2, 0.5}, std::pair{3.0, 2.6}}) {
      ConductorParams p;
      p.model = "rect3d";
      p.resistivity_ohm_m = stack.leading(y);
      const D2 lead = d2(*make_conductor(p, one_electrode(0.5, 10)), x, y);
      const double cpi = stack.leading(y) / (2 * 3.14159265358979323846);
      auto rem = [&](double a, double b) {
        const auto pt = stack.point(a, b, y);
        const double r2 = a * a + b * b + y * y, r5 = r2 * r2 * std::sqrt(r2);
        return std::pair{pt.psi_uu - cpi * (3 * a * a - r2) / r5,
                         pt.psi_yy - cpi * (3 * y * y - r2) / r5};
      };
      // Both integrands at once: each point response is one Hankel integral.
      double ixx = 0, iyy = 0;
      {
        static const GaussLegendre<8> gl;  // the library's rule (model/quadrature.hpp)
        const auto& gx = gl.x;
        const auto& gw = gl.w;
        const int pa = 2, pb = 16;
        const double wa = 0.5 / pa, wb = 10.0 / pb;
        for (int i = 0; i < pa; ++i)
          for (int qi = 0; qi < 8; ++qi)
            for (int j = 0; j < pb; ++j)
              for (int qj = 0; qj < 8; ++qj) {
                const double a = x - 0.25 + wa * (i + 0.5 + 0.5 * gx[static_cast<std::size_t>(qi)]);
                const double b = -5.0 + wb * (j + 0.5 + 0.5 * gx[static_cast<std::size_t>(qj)]);
                const double wt = 0.25 * wa * wb * gw[static_cast<std::size_t>(qi)] *
                                  gw[static_cast<std::size_t>(qj)];
                const auto [uu, yy] = rem(a, b);
                ixx += wt * uu;
                iyy += wt * yy;
              }
      }
      const D2 want{lead.xx - ixx / 5.0, lead.yy - iyy / 5.0};
      const D2 got = d2(*c, x, y);
      const double scale = std::max(std::fabs(want.xx), std::fabs(want.yy));
      INFO("sc " << sc << " at (" << x << ", " << y << "): xx " << got.xx << " vs " << want.xx
                 << ", yy " << got.yy << " vs " << want.yy);
      CHECK(std::fabs(got.xx - want.xx) < 1e-6 * scale);
      CHECK(std::fabs(got.yy - want.yy) < 1e-6 * scale);
    }
  }
}

TEST_CASE("layered: second derivatives match finite differences of the potential, and Laplace",
          "[model][layered]") {
  // The potential comes from a separate table (the remainder by J0, integrated over the
  // rectangle in 2-D); the second derivatives from J1 and edge integrals.
  const auto c = layered(fingertip_like(1500.0), 0.5, 10.0, 2.0);
  for (auto [x, y] :
       {std::pair{0.0, 0.8}, std::pair{0.3, 1.1}, std::pair{1.7, 1.5}, std::pair{0.6, 2.4}}) {
    const double h = 2e-3;
    const double p0 = psi(*c, x, y);
    const double fxx = (psi(*c, x + h, y) - 2 * p0 + psi(*c, x - h, y)) / (h * h);
    const double fyy = (psi(*c, x, y + h) - 2 * p0 + psi(*c, x, y - h)) / (h * h);
    const D2 got = d2(*c, x, y);
    const double scale = std::max(std::fabs(got.xx), std::fabs(got.yy));
    INFO("(" << x << ", " << y << "): xx " << got.xx << " vs " << fxx << ", yy " << got.yy << " vs "
             << fyy);
    CHECK(std::fabs(got.xx - fxx) < 1e-4 * scale);
    CHECK(std::fabs(got.yy - fyy) < 1e-4 * scale);
    const double zz = layered_unit_zz(*c, 0, x, y);
    CHECK(std::fabs(got.xx + got.yy + zz) < 1e-9 * scale);
  }
}

TEST_CASE("layered: across each interface the potential and the normal current are continuous",
          "[model][layered]") {
  const auto layers = fingertip_like(1500.0);
  const auto c = layered(layers);
  double top = 0;
  for (std::size_t k = 0; k + 1 < layers.size(); ++k) {
    top += layers[k].thickness_mm;
    const double rho_above = layers[k].resistivity_ohm_m,
                 rho_below = layers[k + 1].resistivity_ohm_m;
    for (double x : {0.0, 0.4, 2.0}) {
      auto psi = [&](double y) {
        double v = 0;
        c->unit_potentials(x, y, &v);
        return v;
      };
      const double e = 1e-9, d = 2e-3;
      // In the stratum corneum (rho 1500 over 10) the closed-form part C_0 / R is ~600 times
      // the total and the remainder cancels it: 1e-9 of each leaves ~1e-6 of the total there.
      const double tol = k == 0 ? 1e-5 : 1e-7;
      CHECK(psi(top - e) == Approx(psi(top + e)).epsilon(tol));
      const double dy_above =
          (3 * psi(top - e) - 4 * psi(top - e - d) + psi(top - e - 2 * d)) / (2 * d);
      const double dy_below =
          (-3 * psi(top + e) + 4 * psi(top + e + d) - psi(top + e + 2 * d)) / (2 * d);
      INFO("interface " << k << " at " << top << " mm, x " << x << ": dPsi/dy " << dy_above
                        << " above, " << dy_below << " below");
      CHECK(dy_above / rho_above == Approx(dy_below / rho_below).epsilon(2e-3));
      // The horizontal AF (d2/dx2, along the interface) is continuous too.
      CHECK(d2(*c, x, top - e).xx == Approx(d2(*c, x, top + e).xx).epsilon(10 * tol));
    }
  }
}

TEST_CASE("layered: bad stacks and depths are refused", "[model][layered]") {
  CHECK_THROWS_AS(layered({{0.0, 3.0}, {0.0, 3.0}}), Error);
  CHECK_THROWS_AS(layered({{0.1, -3.0}, {0.0, 3.0}}), Error);
  const auto c = layered(fingertip_like(1500.0));
  double xx = 0, yy = 0;
  CHECK_THROWS_AS(c->unit_second_derivatives(0.0, 0.0, &xx, &yy), Error);
  CHECK_THROWS_AS(c->unit_second_derivatives(0.0, NAN, &xx, &yy), Error);
  ConductorParams p;
  p.model = "layered";
  ElectrodeArray line = one_electrode(0.0, 10.0);  // the paper's line electrode has no area
  CHECK_THROWS_AS(make_conductor(p, line), Error);
}

TEST_CASE("skin files: the built-ins parse, bad ones are refused naming the field",
          "[model][skin]") {
  const Skin& gel = builtin_skin("fingertip");
  CHECK(gel.layers.size() == 4);
  CHECK(builtin_skin("fingertip-dry").layers[0].resistivity_ohm_m >
        gel.layers[0].resistivity_ohm_m);
  CHECK_THROWS_AS(builtin_skin("palm"), Error);
  auto refused = [](const char* text, const char* field) {
    try {
      skin_from_json(nlohmann::ordered_json::parse(text), "skin");
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(field) != std::string::npos);
      return;
    }
    FAIL("accepted: " << text);
  };
  refused(R"({"valid_to_mm": 3, "layers": []})", "no layers");
  refused(R"({"valid_to_mm": 3})", "layers");
  refused(R"({"layers": [{"resistivity_ohm_m": 3}]})", "valid_to_mm");
  refused(R"({"valid_to_mm": 3, "layers": [{"thickness_mm": 0, "resistivity_ohm_m": 3},
              {"resistivity_ohm_m": 3}]})",
          "layers[0].thickness_mm");
  refused(R"({"valid_to_mm": 3, "layers": [{"thickness_mm": 0.3, "resistivity_ohm_m": -1},
              {"resistivity_ohm_m": 3}]})",
          "layers[0].resistivity_ohm_m");
  refused(R"({"valid_to_mm": 3, "layers": [{"thickness_mm": 0.3, "resistivity_ohm_m": 1},
              {"resistivity_ohm_m": 0}]})",
          "layers[1].resistivity_ohm_m");
  refused(R"({"valid_to_mm": 3, "layers": [{"thickness_mm": 0.3, "resistivity_ohm_m": 1}]})",
          "semi-infinite");
  refused(R"({"valid_to_mm": 3, "layers": [{"resistivity_ohm_m": 1, "colour": 2}]})", "colour");
}

TEST_CASE(
    "layered: check_reach refuses what the Hankel rule cannot evaluate, over a depth "
    "range, and what it accepts evaluates",
    "[model][layered]") {
  // tests/cli/inputs/skin-thin-5um.json: a 5 um top layer, the hardest case in range.
  const auto c = layered({{0.005, 1500.0}, {0.595, 10.0}, {1.4, 2.3}, {0.0, 45.0}});
  // 550 mm from an electrode: a shallow point would need a rule of over 5e5 panels.
  CHECK_THROWS_WITH(c->check_reach(550.0, 0.02, 0.02, "a grid row"),
                    Catch::Contains("a grid row at depth 0.02 mm, up to 550 mm") &&
                        Catch::Contains("Hankel rule"));
  // A range is refused when any depth in it would be, however deep its ends are.
  CHECK_THROWS_AS(c->check_reach(550.0, 0.02, 1.0, "fibres"), Error);
  CHECK_THROWS_AS(c->check_reach(550.0, 0.015, 3.0, "fibres"), Error);
  CHECK_NOTHROW(c->check_reach(550.0, 0.7, 1.0, "fibres"));
  CHECK_NOTHROW(c->check_reach(550.0, 1.0, 1.0, "fibres"));
  CHECK_THROWS_AS(c->check_reach(10.0, 0.0, 1.0, "fibres"), Error);  // depth must be > 0
  // Accepted: every depth of the range evaluates, potentials and second derivatives.
  CHECK_NOTHROW(c->check_reach(20.0, 0.02, 0.7, "fibres"));
  for (const double y : {0.02, 0.1, 0.6, 0.7}) {
    for (const double x : {0.0, 20.0}) {
      double xx = 0, yy = 0, psi = 0;
      INFO("(" << x << ", " << y << ")");
      REQUIRE_NOTHROW(c->unit_second_derivatives(x, y, &xx, &yy));
      REQUIRE_NOTHROW(c->unit_potentials(x, y, &psi));
      CHECK((std::isfinite(xx) && std::isfinite(yy) && std::isfinite(psi)));
    }
  }
}

namespace {

std::vector<double> along3(const Conductor& c, double x, double y, double z, const FibreAxis& e) {
  std::vector<double> out(c.size());
  c.unit_d2_along(x, y, z, e, out.data());
  return out;
}

double largest(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

const FibreAxis kAlongX{}, kDown{true, 0.0, 0.0}, kAlongZ{false, 0.0, 1.0},
    kSlant{false, 0.6, -0.8};

}  // namespace

TEST_CASE("layered, 2-D arrays: a grid matches the two-layer image series along every axis",
          "[model][layered][array2d]") {
  // The image series of rect3d grids: each image the whole grid (rho 1) seen at the image's
  // depth; every axis's second derivative of a rect3d field is even in the depth.
  const ElectrodeArray grid = ElectrodeArray::grid_of(3, 2, 2.0, 1.5, 1.0, 1.0);
  ConductorParams rp;
  rp.model = "rect3d";
  rp.resistivity_ohm_m = 1.0;
  const auto unit = make_conductor(rp, grid);
  for (auto [rho1, rho2, h] : {std::tuple{3.0, 12.0, 0.8}, std::tuple{30.0, 3.0, 0.4}}) {
    const auto c = layered_on(grid, {{h, rho1}, {0.0, rho2}});
    for (auto [x, y, z] : {std::tuple{0.0, 0.3, 0.0}, std::tuple{1.2, h - 0.01, -0.4},
                           std::tuple{-2.5, h + 0.01, 1.9}, std::tuple{0.7, 0.9, 0.75},
                           std::tuple{4.0, 2.0, -3.0}, std::tuple{-9.0, 1.3, 6.0}}) {
      for (const FibreAxis& e : {kAlongX, kDown, kAlongZ, kSlant}) {
        std::vector<double> want(grid.size(), 0.0);
        image_series(rho1, rho2, h, y, [&](double coef, double v) {
          const auto t = along3(*unit, x, std::fabs(v), z, e);
          for (std::size_t i = 0; i < t.size(); ++i) want[i] += coef * t[i];
        });
        const auto got = along3(*c, x, y, z, e);
        const double scale = largest(want);
        for (std::size_t i = 0; i < grid.size(); ++i) {
          INFO("rho " << rho1 << "/" << rho2 << " at (" << x << ", " << y << ", " << z << ") axis "
                      << e.vertical << "/" << e.cos_az << "/" << e.sin_az << " pad " << i << ": "
                      << got[i] << " vs " << want[i]);
          CHECK(std::fabs(got[i] - want[i]) < 1e-6 * scale);
        }
      }
    }
  }
}

TEST_CASE("layered, 2-D arrays: a grid of one row is the 1-D array of the same pads",
          "[model][layered][array2d]") {
  // Two separate tabulations: the 1-D array's edge integrals over (u, y) tiles, the grid's
  // corner functions over (a, b, y) tiles.
  const auto layers = fingertip_like(1500.0);
  const ElectrodeArray line = ElectrodeArray::uniform(5, 2.0, 1.0, 1.5);
  const ElectrodeArray grid = ElectrodeArray::grid_of(5, 1, 2.0, 2.0, 1.0, 1.5);
  const auto c2 = layered_on(grid, layers);
  for (auto [x, y, z] :
       {std::tuple{0.0, 0.9, 0.0}, std::tuple{0.3, 0.7, -0.4}, std::tuple{-1.2, 2.0, 1.1},
        std::tuple{2.5, 1.3, 2.9}, std::tuple{-3.1, 0.65, 0.2}, std::tuple{4.0, 3.0, -2.0}}) {
    const auto c1 = layered_on(line, layers, z);
    std::vector<double> xx(5), yy(5);
    c1->unit_second_derivatives(x, y, xx.data(), yy.data());
    const auto gx = along3(*c2, x, y, z, kAlongX), gy = along3(*c2, x, y, z, kDown);
    const double scale = std::max(largest(xx), largest(yy));
    for (std::size_t i = 0; i < 5; ++i) {
      INFO("(" << x << ", " << y << ", " << z << ") pad " << i << ": xx " << gx[i] << " vs "
               << xx[i] << ", yy " << gy[i] << " vs " << yy[i]);
      CHECK(std::fabs(gx[i] - xx[i]) <= 1e-9 * scale);
      CHECK(std::fabs(gy[i] - yy[i]) <= 1e-9 * scale);
    }
  }
}

TEST_CASE("layered, 2-D arrays: second derivatives along any axis match finite differences",
          "[model][layered][array2d]") {
  // The potential: the remainder by J0 integrated over each pad in 2-D; the derivatives:
  // J1 and the corner functions.
  const ElectrodeArray grid = ElectrodeArray::grid_of(2, 2, 2.0, 1.5, 1.0, 1.0);
  const auto c = layered_on(grid, fingertip_like(1500.0));
  for (auto [x, y, z] :
       {std::tuple{0.2, 0.8, -0.3}, std::tuple{1.7, 1.5, 1.0}, std::tuple{-0.6, 2.4, 0.1}}) {
    for (const FibreAxis& e : {kAlongX, kAlongZ, kSlant}) {
      const auto exact = along3(*c, x, y, z, e);
      const double h = 2e-3;
      std::vector<double> p(4), m(4), o(4);
      c->unit_potentials_3d(x + h * e.cos_az, y, z + h * e.sin_az, p.data());
      c->unit_potentials_3d(x - h * e.cos_az, y, z - h * e.sin_az, m.data());
      c->unit_potentials_3d(x, y, z, o.data());
      const double scale = largest(exact);
      for (std::size_t i = 0; i < 4; ++i) {
        const double fd = (p[i] - 2 * o[i] + m[i]) / (h * h);
        INFO("(" << x << ", " << y << ", " << z << ") pad " << i << ": " << exact[i] << " vs "
                 << fd);
        CHECK(std::fabs(exact[i] - fd) < 1e-4 * scale);
      }
    }
  }
}
