// The tactile gamut (render/gamut.hpp, issue 40 item 4): a colour some intensities make
// comes back to itself; one outside the gamut is answered no worse than a brute-force
// search over a fine grid of intensities, for independent and dependent mode colours.
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

// The least error over intensities on a grid of step 1 / n in each mode.
double brute_force(const GamutColours& c, const Rgb& want, int n) {
  double best = HUGE_VAL;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k) {
        const double x[3] = {double(i) / n, double(j) / n, double(k) / n};
        double sq = 0;
        for (std::size_t q = 0; q < 3; ++q) {
          const double p = x[0] * c[0][q] + x[1] * c[1][q] + x[2] * c[2][q];
          sq += (p - want[q]) * (p - want[q]);
        }
        best = std::fmin(best, std::sqrt(sq));
      }
  return best;
}

// Modes' colours like the fibre model's (docs/fibres.md, "Designed for selectivity"): the
// SAI mode pure, RA's and PC's recruiting all of SAI first.
const GamutColours kModel = {{{0.5, 1.0, 0.43}, {0.0, 1.0, 0.0}, {0.37, 1.0, 0.5}}};
}  // namespace

TEST_CASE("the gamut: a colour inside it comes back to itself", "[render][gamut]") {
  Stream r;
  for (int t = 0; t < 200; ++t) {
    GamutColours c;
    for (auto& m : c)
      for (double& v : m) v = r.next();
    const std::array<double, 3> x{r.next(), r.next(), r.next()};
    Rgb want{};
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t m = 0; m < 3; ++m) want[k] += x[m] * c[m][k];
    const GamutAnswer a = nearest_in_gamut(c, want);
    CHECK(a.error < 1e-9);
    for (std::size_t k = 0; k < 3; ++k) CHECK(std::fabs(a.predicted[k] - want[k]) < 1e-6);
    for (double v : a.intensity) CHECK((v >= 0 && v <= 1));
  }
  // The pure SAI mode at half intensity is SAI at half.
  const GamutAnswer a = nearest_in_gamut(kModel, {0, 0.5, 0});
  CHECK(a.error < 1e-12);
  CHECK(a.intensity[1] == Approx(0.5).margin(1e-12));
  CHECK(a.intensity[0] == Approx(0).margin(1e-12));
  CHECK(a.intensity[2] == Approx(0).margin(1e-12));
}

// [numerics]: the plain build's (its grids take 6 s under the sanitizers; the case above
// runs the same solver there).
TEST_CASE("the gamut: a colour outside it is answered no worse than a fine grid",
          "[render][gamut][numerics]") {
  const Rgb asks[] = {{1, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0.2, 0.1, 0.9}, {0, 0, 0}};
  for (const Rgb& want : asks) {
    const GamutAnswer a = nearest_in_gamut(kModel, want);
    CHECK(a.error <= brute_force(kModel, want, 100) + 1e-12);
    for (double v : a.intensity) CHECK((v >= 0 && v <= 1));
  }
  // Pure RA is outside: RA's mode brings SAI with it.
  CHECK(nearest_in_gamut(kModel, {1, 0, 0}).error > 0.5);
  // Dependent colours (two modes alike) and a mode that recruits nothing.
  const GamutColours dependent = {{{0.5, 1.0, 0.4}, {0.5, 1.0, 0.4}, {0, 0, 0}}};
  for (const Rgb& want : asks)
    CHECK(nearest_in_gamut(dependent, want).error <= brute_force(dependent, want, 100) + 1e-12);
  // Brighter than full intensity: held at 1.
  const GamutAnswer over = nearest_in_gamut(kModel, {0, 3, 0});
  CHECK(over.intensity[1] == Approx(1));
}
