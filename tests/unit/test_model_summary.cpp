// The per-receptor maxima and mode ratios, against an independent brute-force computation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "model/field.hpp"

using namespace tp;

namespace {

// Largest AF of a receptor by exhaustive sampling of its whole fibre region (every x and
// every depth of the range, not just the boundary), from Eq. 25 written out here.
double brute_force_max(const ElectrodeArray& a, const std::vector<double>& I, double x0, double x1,
                       double y0, double y1, bool vertical, double diameter_um) {
  const double k =
      100.0 * 1e-10 / (4.0 * 1.1 * 0.02 * 2.5e-6) * 1e3 * std::pow(diameter_um / 10.0, 2);
  const double c = 3.0 / (2.0 * M_PI * a.length_mm);
  const double dx = 0.001, dy = 0.005;
  double best = -INFINITY;
  const int ny = y1 > y0 ? static_cast<int>(std::round((y1 - y0) / dy)) : 0;
  const int nx = static_cast<int>(std::round((x1 - x0) / dx));
  for (int j = 0; j <= ny; ++j) {
    const double y = y0 + (y1 - y0) * (ny ? double(j) / ny : 0.0);
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + (x1 - x0) * double(i) / nx;
      double s = 0.0;
      for (std::size_t e = 0; e < I.size(); ++e) {
        const double u = x - a.positions_mm[e];
        s += I[e] * (y * y - u * u) / std::pow(u * u + y * y, 2);
      }
      best = std::max(best, (vertical ? -1.0 : 1.0) * k * c * s);
    }
  }
  return best;
}

void check_against_brute_force(const Setup& s, const std::vector<double>& I) {
  const Summary sum = summarize(s, I);
  std::vector<double> maxima;
  for (std::size_t r = 0; r < s.receptors.size(); ++r) {
    const Receptor& rec = s.receptors[r];
    const Region reg = fibre_region(s, rec);
    const double bf =
        brute_force_max(s.array, I, reg.x0_mm, reg.x1_mm, reg.y0_mm, reg.y1_mm,
                        rec.fibre.orientation == Orientation::vertical, rec.fibre.diameter_um);
    const Peak& p = sum.peaks[r].second;
    INFO(rec.name << ": model " << p.af << " brute force " << bf);
    CHECK(p.af == Approx(bf).epsilon(1e-4).margin(1e-9));
    CHECK(p.af >= bf - 1e-12);  // refinement never does worse than the samples
    CHECK(p.x_mm >= reg.x0_mm);
    CHECK(p.x_mm <= reg.x1_mm);
    CHECK(p.y_mm >= reg.y0_mm);
    CHECK(p.y_mm <= reg.y1_mm);
    maxima.push_back(bf);
  }
  for (std::size_t m = 0; m < s.receptors.size(); ++m) {
    double off = -INFINITY;
    for (std::size_t r = 0; r < maxima.size(); ++r)
      if (r != m) off = std::max(off, maxima[r]);
    const auto& ratio = sum.ratios[m].second;
    if (maxima[m] > 1e-9) {
      REQUIRE(ratio.has_value());
      CHECK(*ratio == Approx(off / maxima[m]).epsilon(2e-4));
    } else if (maxima[m] < 0) {
      CHECK(!ratio.has_value());
    }
  }
}

}  // namespace

TEST_CASE("summary ratios match brute force for the paper's patterns", "[summary]") {
  Setup s;  // the paper's array: 8 electrodes, 1 mm pitch
  SECTION("single cathode") {
    check_against_brute_force(s, {0, 0, 0, 2, 0, 0, 0, 0});
  }
  SECTION("single anode (RA)") {
    check_against_brute_force(s, {0, 0, 0, -2, 0, 0, 0, 0});
  }
  SECTION("cathode with anodic neighbours (SAI)") {
    check_against_brute_force(s, {0, 0, -1, 2, -1, 0, 0, 0});
  }
  SECTION("widened cathode (PC)") {
    check_against_brute_force(s, {-0.5, -0.5, 0.5, 0.5, 0.5, 0.5, -0.5, -0.5});
  }
}

TEST_CASE("summary ratios match brute force for random weights and arrays", "[summary]") {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 6; ++trial) {
    Setup s;
    const int n = 3 + trial;
    s.array = ElectrodeArray::uniform(n, 0.6 + 0.3 * trial);
    std::vector<double> I(static_cast<std::size_t>(n));
    for (auto& v : I) v = u(rng);
    INFO("trial " << trial);
    check_against_brute_force(s, I);
  }
}

TEST_CASE("mode ratio: target never depolarised has no ratio", "[summary]") {
  std::vector<std::pair<std::string, Peak>> peaks = {{"A", {-1.0, 0, 1}}, {"B", {2.0, 0, 1}}};
  CHECK(!mode_ratio(peaks, "A").has_value());
  CHECK(*mode_ratio(peaks, "B") == Approx(-0.5));
  CHECK_THROWS(mode_ratio(peaks, "C"));
}

TEST_CASE("Brent's search finds a bracketed maximum in few evaluations", "[summary][maximize]") {
  // A smooth maximum at x* = 0.3 + 0.01 (from a bracket of 0.5): to the tolerance, in far
  // fewer evaluations than golden section's ~35, never below the start.
  int n = 0;
  auto f = [&](double x) {
    ++n;
    return 2.0 - std::cosh(x - 0.31) + 0.1 * std::sin(x);
  };
  // d/dx: -sinh(x - 0.31) + 0.1 cos x = 0, by Newton.
  double xs = 0.31;
  for (int k = 0; k < 50; ++k)
    xs -=
        (-std::sinh(xs - 0.31) + 0.1 * std::cos(xs)) / (-std::cosh(xs - 0.31) - 0.1 * std::sin(xs));
  const auto [x, v] = brent_max(f, 0.0, 0.5, 0.25, f(0.25), 2.5e-10);
  CHECK(std::fabs(x - xs) < 1e-7);  // a flat maximum: the position to ~sqrt(eps)
  CHECK(v == Approx(f(xs)).epsilon(1e-15));
  CHECK(n < 20);
  // Masked points (-inf) on part of the bracket: the maximum of the rest, at its edge.
  auto g = [](double u) { return u > 0.2 ? -INFINITY : -(u - 0.4) * (u - 0.4); };
  const auto [xg, vg] = brent_max(g, 0.0, 0.5, 0.1, g(0.1), 2.5e-10);
  CHECK(xg == Approx(0.2).margin(1e-8));
  CHECK(vg >= g(0.1));
  // A start that is the maximum stays.
  const auto [xh, vh] = brent_max([](double u) { return -u * u; }, -1.0, 1.0, 0.0, 0.0, 1e-9);
  CHECK(xh == Approx(0.0).margin(1e-8));
  CHECK(vh == 0.0);
}

TEST_CASE("maximize_1d finds the global maximum of a multi-modal function", "[summary][maximize]") {
  auto f = [](double x) { return std::sin(3 * x) + 0.5 * std::cos(7 * x) - 0.01 * x * x; };
  auto [x, v] = maximize_1d(f, -5.0, 5.0, 0.01);
  double best = -INFINITY;
  for (double t = -5; t <= 5; t += 1e-6) best = std::max(best, f(t));
  CHECK(v == Approx(best).epsilon(1e-12));
  CHECK(f(x) == v);
}
