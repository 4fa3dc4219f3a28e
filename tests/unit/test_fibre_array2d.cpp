// Fibres under 2-D arrays (ThresholdSettings::through_mm): a grid of one row is the 1-D
// array of the same pads, mirrored patterns through mirrored points give the same
// threshold, amplitudes scale exactly, and a 2-D array without a point is refused.
#include <catch2/catch.hpp>

#include <array>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fibre/report.hpp"
#include "fibre/threshold.hpp"
#include "model/field.hpp"

using namespace tp;
using namespace tp::fibre;

namespace {
// One receptor's threshold (mA) for weights w; RA (0) is vertical, SAI (1) horizontal.
ReceptorThreshold threshold(const Setup& setup, const std::vector<double>& w, std::size_t receptor,
                            std::optional<std::array<double, 2>> through) {
  const auto conductor = make_conductor(setup.conductor, setup.array);
  const auto model = make_fibre_model("mrg");
  ThresholdSettings s;
  s.offsets = 4;
  s.through_mm = through;
  return receptor_threshold(*model, setup, *conductor, w, setup.receptors[receptor],
                            pulse_waveform(200, 0, 200, false), s);
}
Setup rect3d(const ElectrodeArray& a) {
  Setup s;
  s.array = a;
  s.conductor.model = "rect3d";
  return s;
}
}  // namespace

TEST_CASE("a grid of one row gives the 1-D array's fibre thresholds", "[fibre][array2d]") {
  // The paper's array (8 pads 0.5 x 10 mm at 1 mm) as a line and as a grid of one row.
  const Setup line = rect3d(ElectrodeArray::uniform(8, 1.0, 0.5, 10.0));
  const Setup grid = rect3d(ElectrodeArray::grid_of(8, 1, 1.0, 1.0, 0.5, 10.0));
  const std::vector<double> w{0, 0, -0.5, 1, -0.5, 0, 0, 0};
  // Horizontal (SAI): the same fibres, the same placements: the same lattice point.
  const auto h1 = threshold(line, w, 1, std::nullopt);
  const auto h2 = threshold(grid, w, 1, std::array<double, 2>{0.0, 0.0});
  REQUIRE(h1.threshold_mA);
  REQUIRE(h2.threshold_mA);
  CHECK(*h2.threshold_mA == Approx(*h1.threshold_mA).epsilon(1e-12));
  CHECK(h2.x_mm == Approx(h1.x_mm).margin(1e-9));
  // Vertical (RA): the 2-D search, centred where the 1-D one found its minimum, tries that
  // fibre first, so it finds no more; its neighbours within half a pitch differ little.
  const auto v1 = threshold(line, w, 0, std::nullopt);
  REQUIRE(v1.threshold_mA);
  const auto v2 = threshold(grid, w, 0, std::array<double, 2>{v1.x_mm, 0.0});
  REQUIRE(v2.threshold_mA);
  CHECK(*v2.threshold_mA <= *v1.threshold_mA);
  CHECK(*v2.threshold_mA >= 0.97 * *v1.threshold_mA);
  CHECK(v2.placements == 75);
}

TEST_CASE("mirrored patterns through mirrored points have the same thresholds",
          "[fibre][array2d]") {
  // A 3 x 3 grid, row-major from z's lowest row: pattern w and its mirror in z.
  const Setup grid = rect3d(ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.0, 1.0));
  const std::vector<double> w{0.1, -0.3, 0.2, -0.4, 1.0, -0.2, 0.0, -0.3, -0.1};
  std::vector<double> m(9);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[r * 3 + c] = w[(2 - r) * 3 + c];
  for (std::size_t receptor : {0u, 1u, 2u}) {
    CAPTURE(receptor);
    const auto a = threshold(grid, w, receptor, std::array<double, 2>{0.3, 0.7});
    const auto b = threshold(grid, m, receptor, std::array<double, 2>{0.3, -0.7});
    REQUIRE(a.threshold_mA);
    REQUIRE(b.threshold_mA);
    CHECK(*b.threshold_mA == Approx(*a.threshold_mA).epsilon(1e-12));
    CHECK(b.z_mm == Approx(-a.z_mm).margin(1e-9));
    // Doubling every weight halves the threshold exactly (the amplitude lattice).
    std::vector<double> w2;
    for (double x : w) w2.push_back(2 * x);
    const auto d = threshold(grid, w2, receptor, std::array<double, 2>{0.3, 0.7});
    REQUIRE(d.threshold_mA);
    CHECK(*d.threshold_mA == *a.threshold_mA / 2);
  }
}

TEST_CASE("a 2-D array's fibres need a point inside the pads and margin", "[fibre][array2d]") {
  const Setup grid = rect3d(ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.0, 1.0));
  const std::vector<double> w{0, 0, 0, -1, 1, 0, 0, 0, 0};
  CHECK_THROWS_WITH(threshold(grid, w, 1, std::nullopt),
                    Catch::Contains("is 2-D: give the point the fibres pass through"));
  CHECK_THROWS_WITH(threshold(grid, w, 1, std::array<double, 2>{0.0, 9.5}),
                    Catch::Contains("outside the pads plus the lateral margin"));
}
