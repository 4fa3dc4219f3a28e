// The layered half-space's point-source response (lib/model/layered.*): the uniform limit,
// the classical two-layer image series, finite differences, and the interface conditions.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/error.hpp"
#include "model/layered.hpp"

using namespace tp;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A point current of 1 mA on the surface of a two-layer half-space (top rho1, thickness h,
// over rho2): the image series, k = (rho2 - rho1) / (rho2 + rho1) (docs/model.md).
double two_layer_series(double rho1, double rho2, double h, double r, double y) {
  const double k = (rho2 - rho1) / (rho2 + rho1);
  double s = 0.0;
  if (y < h) {
    s = 1.0 / std::hypot(r, y);
    double kn = 1.0;
    for (int n = 1; n < 2000; ++n) {
      kn *= k;
      s += kn * (1.0 / std::hypot(r, 2 * n * h - y) + 1.0 / std::hypot(r, 2 * n * h + y));
    }
  } else {
    double kn = 1.0;
    for (int n = 0; n < 2000; ++n, kn *= k) s += kn / std::hypot(r, y + 2 * n * h);
    s *= 1.0 + k;
  }
  return rho1 / (2 * kPi) * s;
}

}  // namespace

TEST_CASE("equal layers are a uniform half-space", "[model][layered]") {
  const LayeredHalfSpace uniform({{0.3, 3.0}, {1.2, 3.0}, {0.0, 3.0}});
  for (double y : {0.1, 0.3, 0.9, 2.0}) {
    for (double lambda : {0.0, 0.5, 3.0, 40.0}) {
      CHECK(uniform.kernel(lambda, y) == Approx(3.0 * std::exp(-lambda * y)).epsilon(1e-14));
    }
    CHECK(uniform.leading(y) == 3.0);
    for (double r : {0.0, 0.7, 4.0}) {
      const auto p = uniform.point(r, 0.0, y);
      const double big_r = std::hypot(r, y);
      CHECK(p.psi == Approx(3.0 / (2 * kPi * big_r)).epsilon(1e-14));
      CHECK(p.psi_yy ==
            Approx(3.0 / (2 * kPi) * (2 * y * y - r * r) / std::pow(big_r, 5)).epsilon(1e-13));
    }
  }
}

TEST_CASE("two layers match the classical image series, in both layers", "[model][layered]") {
  const double h = 1.0;
  for (auto [rho1, rho2] : {std::pair{3.0, 12.0}, std::pair{12.0, 3.0}, std::pair{1.0, 1.5}}) {
    const LayeredHalfSpace two({{h, rho1}, {0.0, rho2}});
    for (double y : {0.002, 0.4, 0.97, 1.03, 1.6, 3.5}) {
      for (double r : {0.0, 0.3, 1.0, 2.5, 7.0}) {
        const double want = two_layer_series(rho1, rho2, h, r, y);
        const double got = two.point(r, 0.0, y).psi;
        INFO("rho " << rho1 << " over " << rho2 << ", r " << r << ", y " << y << ": " << got
                    << " vs series " << want);
        CHECK(got == Approx(want).epsilon(1e-6));
      }
    }
  }
}

TEST_CASE("layered second derivatives match finite differences of the potential",
          "[model][layered]") {
  // A fingertip-like stack: a resistive top, a conductive middle, a resistive bottom.
  const LayeredHalfSpace skin({{0.2, 20.0}, {1.5, 2.0}, {0.0, 25.0}});
  for (auto [u, w, y] :
       {std::tuple{0.0, 0.0, 0.9}, std::tuple{0.6, 0.0, 0.7}, std::tuple{-1.4, 2.0, 1.2},
        std::tuple{3.0, -1.0, 2.5}, std::tuple{0.4, 0.3, 0.1}}) {
    const double hh = 2e-3 * std::min(y, 1.0);  // the field varies on the scale of the depth
    auto psi = [&](double uu, double yy) { return skin.point(uu, w, yy).psi; };
    const auto p = skin.point(u, w, y);
    const double fuu = (psi(u + hh, y) - 2 * p.psi + psi(u - hh, y)) / (hh * hh);
    const double fyy = (psi(u, y + hh) - 2 * p.psi + psi(u, y - hh)) / (hh * hh);
    const double scale = std::max(std::fabs(p.psi_uu), std::fabs(p.psi_yy));
    INFO("(" << u << ", " << w << ", " << y << "): uu " << p.psi_uu << " vs " << fuu << ", yy "
             << p.psi_yy << " vs " << fyy);
    CHECK(std::fabs(p.psi_uu - fuu) < 1e-4 * scale);
    CHECK(std::fabs(p.psi_yy - fyy) < 1e-4 * scale);
  }
}

TEST_CASE("across an interface the potential and the normal current are continuous",
          "[model][layered]") {
  const double h = 0.8;
  const LayeredHalfSpace two({{h, 30.0}, {0.0, 3.0}});
  for (double r : {0.0, 0.5, 2.0}) {
    const double e = 1e-9, d = 1e-3;
    auto psi = [&](double y) { return two.point(r, 0.0, y).psi; };
    const double above = psi(h - e), below = psi(h + e);
    CHECK(above == Approx(below).epsilon(1e-7));
    // One-sided second-order derivatives on each side; the current density is -dPsi/dy / rho.
    const double dy_above = (3 * psi(h - e) - 4 * psi(h - e - d) + psi(h - e - 2 * d)) / (2 * d);
    const double dy_below = (-3 * psi(h + e) + 4 * psi(h + e + d) - psi(h + e + 2 * d)) / (2 * d);
    INFO("r " << r << ": dPsi/dy " << dy_above << " above, " << dy_below << " below");
    CHECK(dy_above / 30.0 == Approx(dy_below / 3.0).epsilon(1e-4));
    CHECK(std::fabs(dy_above / dy_below - 10.0) < 0.01);  // the slope jumps by rho1 / rho2
  }
}

TEST_CASE("a layered stack refuses no layers and non-positive values", "[model][layered]") {
  CHECK_THROWS_AS(LayeredHalfSpace({}), Error);
  CHECK_THROWS_AS(LayeredHalfSpace({{0.0, 3.0}, {0.0, 3.0}}), Error);
  CHECK_THROWS_AS(LayeredHalfSpace({{0.1, -3.0}, {0.0, 3.0}}), Error);
  CHECK_THROWS_AS(LayeredHalfSpace({{0.1, 3.0}, {0.0, 0.0}}), Error);
  CHECK_THROWS_AS(LayeredHalfSpace({{NAN, 3.0}, {0.0, 3.0}}), Error);
  CHECK_NOTHROW(LayeredHalfSpace({{0.0, 3.0}}));  // one semi-infinite layer
}

TEST_CASE("reciprocity: source and receiver swapped give the same kernel", "[model][layered]") {
  // kernel_between solves the layered half-space directly (a linear system per lambda), an
  // independent derivation from kernel()'s resistivity-transform recursion.
  const LayeredHalfSpace skin({{0.35, 1500.0}, {0.25, 10.0}, {1.4, 2.3}, {0.0, 45.0}});
  const LayeredHalfSpace two({{0.8, 3.0}, {0.0, 12.0}});
  for (const auto* s : {&skin, &two}) {
    for (double lambda : {0.01, 0.3, 1.0, 4.0, 15.0}) {
      // A surface source: the direct solution equals kernel(), and swapping it with a
      // receiver at depth y (a source at y, received at the surface) changes nothing.
      for (double y : {0.1, 0.5, 0.7, 0.9, 2.0, 2.6}) {
        const double k = s->kernel(lambda, y);
        INFO("lambda " << lambda << ", y " << y);
        CHECK(s->kernel_between(lambda, 0.0, y) == Approx(k).epsilon(1e-11).margin(1e-300));
        CHECK(s->kernel_between(lambda, y, 0.0) == Approx(k).epsilon(1e-11).margin(1e-300));
      }
      // Buried sources: inside one layer (the dermis), and across layers.
      for (auto [d, y] : {std::pair{0.9, 1.6}, std::pair{0.7, 1.95}, std::pair{0.2, 1.2},
                          std::pair{0.5, 3.0}, std::pair{2.1, 2.4}}) {
        INFO("lambda " << lambda << ", source " << d << ", receiver " << y);
        CHECK(s->kernel_between(lambda, d, y) ==
              Approx(s->kernel_between(lambda, y, d)).epsilon(1e-11).margin(1e-300));
      }
    }
  }
  // A source buried in a uniform half-space: its image in the insulated surface.
  const LayeredHalfSpace uniform({{0.5, 3.0}, {0.0, 3.0}});
  for (double lambda : {0.2, 2.0})
    CHECK(uniform.kernel_between(lambda, 0.8, 1.5) ==
          Approx(1.5 * (std::exp(-lambda * 0.7) + std::exp(-lambda * 2.3))).epsilon(1e-13));
}
