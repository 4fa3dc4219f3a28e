// The tactile gamut (render/gamut.hpp, issue 40 item 4): a colour some intensities make
// comes back to itself; one outside the gamut is answered no worse than a brute-force
// search over a fine grid of intensities (each mode off, or on from its onset colour up), for
// independent and dependent mode colours, with and without onset colours.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "render/gamut.hpp"

using namespace tp;

namespace {
// A fixed stream in [0, 1) (the same numbers on every machine).
struct Stream {
  std::uint64_t s = 0x9e3779b97f4a7c15ULL;
  double next() {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    return static_cast<double>(s >> 11) / 9007199254740992.0;
  }
};

double distance(const Rgb& a, const Rgb& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// The least error over each mode off or on at 0, 1 / n, ..., 1 (on at 0: its onset colour).
double brute_force(const GamutModes& c, const Rgb& want, int n) {
  double best = HUGE_VAL;
  // Grid index -1 is off; 0 is on at the threshold (kLeastOn).
  auto level = [n](int i) { return i < 0 ? 0.0 : i == 0 ? kLeastOn : double(i) / n; };
  for (int i = -1; i <= n; ++i)
    for (int j = -1; j <= n; ++j)
      for (int k = -1; k <= n; ++k)
        best = std::fmin(best, distance(predicted_colour(c, {level(i), level(j), level(k)}), want));
  return best;
}

// Modes' colours like the fibre model's (docs/fibres.md, "Designed for selectivity"): the
// SAI mode pure, RA's and PC's recruiting all of SAI first; linear (no onset colour).
const GamutModes kModel = {{}, {{{0.5, 1.0, 0.43}, {0.0, 1.0, 0.0}, {0.37, 1.0, 0.5}}}};
// The same with each mode recruiting something at its threshold, as the plan drives it.
const GamutModes kOnset = {{{{0.2, 0.5, 0.0}, {0.0, 0.3, 0.0}, {0.0, 0.6, 0.1}}},
                           {{{0.5, 1.0, 0.43}, {0.0, 1.0, 0.0}, {0.37, 1.0, 0.5}}}};

void check_intensities(const GamutAnswer& a) {
  for (double v : a.intensity) CHECK((v == 0 || (v >= kLeastOn && v <= 1)));
}
}  // namespace

TEST_CASE("the gamut: a colour inside it comes back to itself", "[render][gamut]") {
  Stream r;
  for (int t = 0; t < 400; ++t) {
    GamutModes c;
    for (std::size_t m = 0; m < 3; ++m)
      for (std::size_t k = 0; k < 3; ++k) {
        c.full[m][k] = r.next();
        c.onset[m][k] = t % 2 ? c.full[m][k] * r.next() : 0.0;  // every other: linear
      }
    // Each mode off (a quarter of the time) or on at an intensity.
    std::array<double, 3> x{};
    for (double& v : x) v = r.next() < 0.25 ? 0.0 : std::fmax(kLeastOn, r.next());
    const Rgb want = predicted_colour(c, x);
    const GamutAnswer a = nearest_in_gamut(c, want);
    CHECK(a.error < 1e-6);
    CHECK(distance(a.predicted, want) < 1e-6);
    CHECK(distance(predicted_colour(c, a.intensity), a.predicted) < 1e-15);
    check_intensities(a);
  }
  // The pure SAI mode at half intensity is SAI at half.
  const GamutAnswer a = nearest_in_gamut(kModel, {0, 0.5, 0});
  CHECK(a.error < 1e-12);
  CHECK(a.intensity[1] == Approx(0.5).margin(1e-12));
  CHECK(a.intensity[0] == 0);
  CHECK(a.intensity[2] == 0);
  // With onsets: SAI at 0.3 is the SAI mode at its threshold, on but at the least intensity;
  // below it, nothing comes nearer than off or that.
  const GamutAnswer at = nearest_in_gamut(kOnset, {0, 0.3, 0});
  CHECK(at.error < 1e-6);
  CHECK(at.intensity[1] == kLeastOn);
  CHECK(nearest_in_gamut(kOnset, {0, 0.1, 0}).intensity == std::array<double, 3>{0, 0, 0});
  CHECK(nearest_in_gamut(kOnset, {0, 0.2, 0}).intensity[1] == kLeastOn);
  CHECK(nearest_in_gamut(kOnset, {0, 0, 0}).intensity == std::array<double, 3>{0, 0, 0});
}

// [numerics]: the plain build's (its grids take seconds under the sanitizers; the case above
// runs the same solver there).
TEST_CASE("the gamut: a colour outside it is answered no worse than a fine grid",
          "[render][gamut][numerics]") {
  const Rgb asks[] = {{1, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0.2, 0.1, 0.9}, {0, 0, 0},
                      {0.1, 0.2, 0.05}, {0.6, 0.4, 0.2}};
  for (const GamutModes& modes : {kModel, kOnset})
    for (const Rgb& want : asks) {
      const GamutAnswer a = nearest_in_gamut(modes, want);
      CHECK(a.error <= brute_force(modes, want, 100) + 1e-9);
      check_intensities(a);
    }
  // Pure RA is outside: RA's mode brings SAI with it.
  CHECK(nearest_in_gamut(kModel, {1, 0, 0}).error > 0.5);
  // Dependent colours (two modes alike) and a mode that recruits nothing.
  const GamutModes dependent = {{{{0.1, 0.3, 0}, {0.1, 0.3, 0}, {0, 0, 0}}},
                                {{{0.5, 1.0, 0.4}, {0.5, 1.0, 0.4}, {0, 0, 0}}}};
  for (const GamutModes& modes : {GamutModes{{}, dependent.full}, dependent})
    for (const Rgb& want : asks)
      CHECK(nearest_in_gamut(modes, want).error <= brute_force(modes, want, 100) + 1e-9);
  // Brighter than full intensity: held at 1.
  const GamutAnswer over = nearest_in_gamut(kModel, {0, 3, 0});
  CHECK(over.intensity[1] == Approx(1));
}
