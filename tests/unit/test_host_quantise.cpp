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
