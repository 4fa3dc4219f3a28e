// Physics checks of the conductor model and the activating function.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "model/field.hpp"

using namespace tp;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Eq. 23 written out independently: AF of a horizontal myelinated 10 um fibre for a
// cathodic current I (mA) on a line electrode of length L (mm) at x0, tissue 3 ohm*m,
// McNeal's fibre: G/C = 100 d^2 / (4 rho_i c_node l_node).
double eq23(double I_mA, double x0, double x, double y) {
  const double d = 10e-6, rho_i = 1.1, c_node = 0.02, l_node = 2.5e-6;
  const double k_mm2_per_ms = 100.0 * d * d / (4.0 * rho_i * c_node * l_node) * 1e3;
  const double rho = 3.0, L = 10.0;
  const double u = x - x0;
  return k_mm2_per_ms * rho * I_mA / (2.0 * kPi * L) * (y * y - u * u) / std::pow(u * u + y * y, 2);
}

const Fibre kHorizontal{Orientation::horizontal, 10.0, true};
const Fibre kVertical{Orientation::vertical, 10.0, true};

std::vector<double> random_weights(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> w(n);
  for (auto& v : w) v = u(rng);
  return w;
}

}  // namespace

TEST_CASE("one electrode's AF equals Eq. 23 at many points", "[model][eq23]") {
  Setup s;
  s.array = ElectrodeArray::uniform(1, 1.0);
  const Field f(s, {1.5});
  int checked = 0;
  for (double x = -4.0; x <= 4.0; x += 0.173)
    for (double y = 0.11; y <= 3.5; y += 0.097) {
      const double expect = eq23(1.5, 0.0, x, y);
      CHECK(f.af(kHorizontal, x, y) == Approx(expect).epsilon(1e-12).margin(1e-12));
      ++checked;
    }
  CHECK(checked > 1500);
  // The reference fibre factor itself: 45.45 mm^2/ms for a myelinated 10 um fibre.
  CHECK(fibre_factor_mm2_per_ms(kHorizontal) == Approx(1e-8 / 2.2e-7 * 1e3));
}

TEST_CASE("an array's AF is the superposition of Eq. 23 (Eq. 25)", "[model][eq25]") {
  Setup s;
  s.array = ElectrodeArray::uniform(5, 1.3);
  const std::vector<double> I = {0.3, -1.0, 2.0, -0.9, -0.4};
  const Field f(s, I);
  for (double x = -6; x <= 6; x += 0.31)
    for (double y = 0.2; y <= 3; y += 0.23) {
      double expect = 0;
      for (std::size_t i = 0; i < I.size(); ++i)
        expect += eq23(I[i], s.array.positions_mm[i], x, y);
      CHECK(f.af(kHorizontal, x, y) == Approx(expect).epsilon(1e-11).margin(1e-11));
    }
}

TEST_CASE("analytic second derivatives match finite differences of the potential",
          "[model][laplace]") {
  for (const std::string model : {"line2d", "strip2d"}) {
    Setup s;
    s.array = ElectrodeArray::uniform(4, 1.0);
    s.conductor.model = model;
    auto c = make_conductor(s.conductor, s.array);
    std::vector<double> xx(4), yy(4), p0(4), pxm(4), pxp(4), pym(4), pyp(4);
    const double h = 1e-3;
    for (double x = -3; x <= 3; x += 0.37)
      for (double y = 0.4; y <= 3; y += 0.29) {
        c->unit_second_derivatives(x, y, xx.data(), yy.data());
        c->unit_potentials(x, y, p0.data());
        c->unit_potentials(x - h, y, pxm.data());
        c->unit_potentials(x + h, y, pxp.data());
        c->unit_potentials(x, y - h, pym.data());
        c->unit_potentials(x, y + h, pyp.data());
        for (int i = 0; i < 4; ++i) {
          const double fd_xx = (pxm[i] - 2 * p0[i] + pxp[i]) / (h * h);
          const double fd_yy = (pym[i] - 2 * p0[i] + pyp[i]) / (h * h);
          const double scale = std::fabs(xx[i]) + 1e-3;
          INFO(model << " electrode " << i << " at (" << x << ", " << y << ")");
          CHECK(std::fabs(fd_xx - xx[i]) < 1e-4 * scale + 1e-6);
          CHECK(std::fabs(fd_yy - yy[i]) < 1e-4 * scale + 1e-6);
          // Laplace (Eq. 26/27): d2Psi/dx2 = -d2Psi/dy2 in 2-D, independently of the code's own.
          CHECK(std::fabs(fd_xx + fd_yy) < 1e-4 * scale + 1e-6);
        }
      }
  }
}

TEST_CASE("af_v = -af_h for any weights in 2-D (Eq. 27)", "[model][laplace]") {
  std::mt19937 rng(7);
  Setup s;
  const Field f(s, random_weights(rng, 8));
  for (double x = -6; x <= 6; x += 0.5)
    for (double y = 0.2; y <= 3; y += 0.2) CHECK(f.af(kVertical, x, y) == -f.af(kHorizontal, x, y));
}

TEST_CASE("the AF is harmonic away from the electrodes (Eq. 28-30)", "[model][harmonic]") {
  std::mt19937 rng(11);
  for (const std::string model : {"line2d", "strip2d"}) {
    Setup s;
    s.conductor.model = model;
    const Field f(s, random_weights(rng, 8));
    const double h = 2e-3;
    for (double x = -6; x <= 6; x += 0.41)
      for (double y = 0.5; y <= 3; y += 0.27) {
        auto a = [&](double xv, double yv) { return f.af(kHorizontal, xv, yv); };
        const double dxx = (a(x - h, y) - 2 * a(x, y) + a(x + h, y)) / (h * h);
        const double dyy = (a(x, y - h) - 2 * a(x, y) + a(x, y + h)) / (h * h);
        INFO(model << " at (" << x << ", " << y << "): dxx " << dxx << " dyy " << dyy);
        CHECK(std::fabs(dxx + dyy) < 1e-3 * (std::fabs(dxx) + std::fabs(dyy)) + 1e-3);
      }
  }
}

TEST_CASE("under one electrode the AF falls as 1/y^2", "[model][decay]") {
  Setup s;
  s.array = ElectrodeArray::uniform(1, 1.0);
  const Field f(s, {1.0});
  const double ref = f.af(kHorizontal, 0.0, 1.0);
  REQUIRE(ref > 0.0);
  for (double y = 0.1; y <= 5.0; y += 0.1) CHECK(f.af(kHorizontal, 0.0, y) * y * y == Approx(ref));
  CHECK(f.af(kHorizontal, 0.0, 0.5) == Approx(4.0 * f.af(kHorizontal, 0.0, 1.0)));
}

TEST_CASE("cathodic depolarises horizontal fibres below and anodic flips the sign",
          "[model][sign]") {
  Setup s;
  s.array = ElectrodeArray::uniform(1, 1.0);
  const Field cath(s, {1.0}), anod(s, {-1.0});
  CHECK(cath.af(kHorizontal, 0.0, 1.0) > 0.0);  // Fig. 4: cathode excites horizontal fibres
  CHECK(cath.af(kVertical, 0.0, 1.0) < 0.0);    // Fig. 6: ... and not vertical ones
  CHECK(anod.af(kVertical, 0.0, 1.0) > 0.0);    // Fig. 7: anode excites vertical fibres
  for (double x = -3; x <= 3; x += 0.25)
    for (double y = 0.3; y <= 2.5; y += 0.3) {
      CHECK(anod.af(kHorizontal, x, y) == -cath.af(kHorizontal, x, y));
      CHECK(anod.af(kVertical, x, y) == -cath.af(kVertical, x, y));
    }
}

TEST_CASE("fibre factor scales with d^2 (myelinated) and d (unmyelinated)", "[model][fibre]") {
  const Fibre m10{Orientation::horizontal, 10.0, true}, m20{Orientation::horizontal, 20.0, true};
  const Fibre m4{Orientation::vertical, 4.0, true};
  const Fibre u10{Orientation::horizontal, 10.0, false}, u20{Orientation::horizontal, 20.0, false};
  CHECK(fibre_factor_mm2_per_ms(m20) == Approx(4.0 * fibre_factor_mm2_per_ms(m10)));
  CHECK(fibre_factor_mm2_per_ms(m4) == Approx(0.16 * fibre_factor_mm2_per_ms(m10)));
  CHECK(fibre_factor_mm2_per_ms(u20) == Approx(2.0 * fibre_factor_mm2_per_ms(u10)));
  // Sec. 4.1: a myelinated fibre is far more excitable than an unmyelinated one of equal size.
  CHECK(fibre_factor_mm2_per_ms(m10) > 10.0 * fibre_factor_mm2_per_ms(u10));
}

TEST_CASE("maximum principle: SAI's largest AF is at least PC's for equal diameters",
          "[model][maxprinciple]") {
  std::mt19937 rng(2024);
  for (int n : {2, 4, 8, 12}) {
    for (int trial = 0; trial < 25; ++trial) {
      Setup s;
      s.array = ElectrodeArray::uniform(n, 0.5 + 0.25 * (trial % 7));
      std::vector<double> w = random_weights(rng, static_cast<std::size_t>(n));
      if (trial % 2 == 0) {  // half the trials zero-sum, as every mode is
        double sum = 0;
        for (double v : w) sum += v;
        for (double& v : w) v -= sum / n;
      }
      const Field f(s, w);
      const Peak sai = f.peak(s.receptors[1]), pc = f.peak(s.receptors[2]);
      REQUIRE(s.receptors[1].fibre.diameter_um == s.receptors[2].fibre.diameter_um);
      INFO("n " << n << " trial " << trial << " SAI " << sai.af << " PC " << pc.af);
      CHECK(sai.af >= pc.af - 1e-12 * std::fabs(pc.af));
    }
  }
}

TEST_CASE("default receptor table is the paper's Table 1", "[model][receptors]") {
  const auto& r = default_receptors();
  REQUIRE(r.size() == 3);
  CHECK(r[0].name == "RA");
  CHECK(r[0].fibre.orientation == Orientation::vertical);
  CHECK(r[0].depth_min_mm == 0.7);
  CHECK(r[0].fibre.diameter_um == 4.0);
  CHECK(r[1].name == "SAI");
  CHECK(r[1].fibre.orientation == Orientation::horizontal);
  CHECK(r[1].depth_min_mm == 0.9);
  CHECK(r[1].fibre.diameter_um == 10.0);
  CHECK(r[2].name == "PC");
  CHECK(r[2].depth_min_mm == 2.0);
  CHECK(r[2].fibre.diameter_um == 10.0);
  for (const auto& e : r) CHECK(e.fibre.myelinated);
}

TEST_CASE("strip2d tends to line2d for narrow electrodes and far points", "[model][strip2d]") {
  Setup line, strip;
  line.array = strip.array = ElectrodeArray::uniform(3, 1.0, 0.01);
  strip.conductor.model = "strip2d";
  const Field a(line, {1.0, -2.0, 1.0}), b(strip, {1.0, -2.0, 1.0});
  for (double x = -3; x <= 3; x += 0.5)
    CHECK(b.af(kHorizontal, x, 1.0) == Approx(a.af(kHorizontal, x, 1.0)).epsilon(1e-4));
}
