// The host's quantisation of currents to DAC codes (host/stimulator): the codes sum to zero,
// stay within the limit in force and within a step or so of the exact currents.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "device/protocol.hpp"
#include "host/stimulator.hpp"
#include "pulse/shape.hpp"

using namespace tp;
using namespace tp::device;

TEST_CASE("host quantisation: codes sum to exactly zero and stay within half a step or so",
          "[device][quantize]") {
  Capabilities caps;
  const double step = caps.dac_step_nA * 1e-6;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<double> c(8);
    for (auto& v : c) v = u(rng);
    const double mean = std::accumulate(c.begin(), c.end(), 0.0) / 8;
    for (auto& v : c) v -= mean;
    const auto codes = host::quantize_currents(c, caps, 2.0);
    CHECK(std::accumulate(codes.begin(), codes.end(), 0L) == 0);
    for (std::size_t i = 0; i < c.size(); ++i)
      CHECK(std::fabs(codes[i] * step - c[i]) <= 1.5 * step);
  }
}

TEST_CASE("host quantisation never crosses the limit in force, and keeps the sum at zero",
          "[device][quantize]") {
  // The case: 0.5 mA on a 977 nA step is 511.77 codes; the nearest, 512, is
  // 0.500224 mA.  Toward zero instead: 511, 0.499247 mA.
  Capabilities caps;
  CHECK(host::limit_code(0.5, caps) == 511);
  CHECK(host::limit_code(512 * 977e-6, caps) == 512);  // an exact multiple is within
  CHECK(host::limit_code(5.0, caps) == caps.max_code());
  const auto sai = host::quantize_currents({0.5, -0.25, -0.25}, caps, 0.5);
  CHECK(sai[0] == 511);
  CHECK(std::accumulate(sai.begin(), sai.end(), 0L) == 0);
  // A 6-bit DAC: 64516 nA a code; 0.49 mA is 7.6 codes, the nearest 8 (0.516 mA).
  Capabilities coarse;
  coarse.dac_step_nA = static_cast<std::uint16_t>(dac_step_nA(2000, 6));
  const auto six = host::quantize_currents({0.49, -0.49}, coarse, 0.5);
  CHECK(six[0] == 7);
  CHECK(six[1] == -7);
  // Randomised: every code within the limit, within one step of the exact current
  // (more where the sum is moved), summing to zero.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0), lim(0.05, 2.0);
  std::uniform_int_distribution<int> nch(2, 64), bits(6, 16);
  for (int trial = 0; trial < 5000; ++trial) {
    Capabilities d;
    d.dac_step_nA = static_cast<std::uint16_t>(dac_step_nA(2000, bits(rng)));
    const double limit = lim(rng);
    const double step = d.dac_step_nA * 1e-6;
    std::vector<double> c(static_cast<std::size_t>(nch(rng)));
    for (auto& v : c) v = u(rng);
    const double mean = std::accumulate(c.begin(), c.end(), 0.0) / static_cast<double>(c.size());
    double peak = 0;
    for (auto& v : c) peak = std::max(peak, std::fabs(v -= mean));
    for (auto& v : c) v *= limit / peak;  // the largest exactly at the limit
    std::vector<std::int16_t> codes;
    try {
      codes = host::quantize_currents(c, d, limit);
    } catch (const Error&) {
      continue;  // no zero sum within the limit: refused, nothing sent
    }
    REQUIRE(std::accumulate(codes.begin(), codes.end(), 0L) == 0);
    for (std::size_t i = 0; i < c.size(); ++i) {
      REQUIRE(std::abs(codes[i]) * step <= limit + 1e-12);
      REQUIRE(std::fabs(codes[i] * step - c[i]) <= 2.0 * step);
    }
  }
  // Above the limit: refused.
  CHECK_THROWS_AS(host::quantize_currents({0.6, -0.6}, caps, 0.5), Error);
}

TEST_CASE("a shape's base codes: each phase within 1.5 x its units of DAC steps, never over the limit",
          "[device][quantize]") {
  Capabilities caps;
  caps.features = kFeatureShapedPulses;
  const double step = caps.dac_step_nA * 1e-6;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Prepulse at 0.1 (U = 10), a 1.5 peak (U = 2, max |units| 3), an asymmetric 1/4 (U = 4).
  const std::vector<std::vector<tp::Phase>> shapes = {
      {{500, 0.1}, {200, 1}, {50, 0}, {500, -0.5}},
      {{100, 1.5}, {150, -1}},
      {{200, 1}, {100, 0}, {800, -0.25}}};
  for (const auto& phases : shapes) {
    const tp::ShapeUnits su = tp::shape_units(phases);
    double peak_level = 0;
    for (const auto& p : phases) peak_level = std::max(peak_level, std::fabs(p.level));
    for (int trial = 0; trial < 300; ++trial) {
      tp::Stimulus s;
      s.shape.phases = phases;
      s.currents_mA.resize(8);
      for (auto& v : s.currents_mA) v = u(rng) * 1.3 / peak_level;
      const double mean = std::accumulate(s.currents_mA.begin(), s.currents_mA.end(), 0.0) / 8;
      for (auto& v : s.currents_mA) v -= mean;
      double worst = 0;
      for (double c : s.currents_mA) worst = std::max(worst, std::fabs(c) * peak_level);
      const double limit = std::max(worst, 1.3);
      const auto base = host::pattern_codes(s, caps, limit);
      CHECK(std::accumulate(base.begin(), base.end(), 0L) == 0);
      const tp::Stimulus d = host::delivered_stimulus(s, base, caps);
      for (std::size_t i = 0; i < base.size(); ++i) {
        for (std::size_t k = 0; k < phases.size(); ++k) {
          const double asked = s.currents_mA[i] * phases[k].level;
          const double given = base[i] * su.units[k] * step;
          // A base code within 1.5 codes of its exact value (half a code rounding, one for
          // the zero sum, as quantize_currents): phase k within 1.5 x |units_k| DAC steps of
          // the current asked; never above the limit at any phase.
          CHECK(std::fabs(given - asked) <= 1.5 * std::fabs(su.units[k]) * step + 1e-12);
          CHECK(std::fabs(given) <= limit + 1e-12);
        }
        CHECK(d.currents_mA[i] == Approx(base[i] * su.unit * step));
      }
    }
  }
}
