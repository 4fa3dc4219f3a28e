// The protocol's arithmetic (device/protocol): scaling codes by a live amplitude.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <vector>

#include "device/protocol.hpp"

using namespace tp::device;

TEST_CASE("scale_codes: sums stay zero, no code grows, each within one of the exact value",
          "[device][mix]") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> code(-2047, 2047), n_of(2, 64);
  std::uniform_int_distribution<int> scale(0, kFullScale);
  for (int it = 0; it < 20000; ++it) {
    const int n = n_of(rng);
    std::vector<std::int16_t> in(static_cast<std::size_t>(n));
    int sum = 0;
    for (int i = 0; i + 1 < n; ++i) {
      in[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(code(rng) / 2);
      sum += in[static_cast<std::size_t>(i)];
    }
    in.back() = static_cast<std::int16_t>(-sum);
    const auto s = static_cast<std::uint16_t>(it < 3 ? it * kFullScale / 2 : scale(rng));
    std::vector<std::int16_t> out(in.size());
    scale_codes(in.data(), in.size(), s, out.data());
    int total = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
      const double exact = static_cast<double>(in[i]) * s / kFullScale;
      REQUIRE(std::abs(out[i] - exact) < 1.0);
      REQUIRE(std::abs(out[i]) <= std::abs(in[i]));
      total += out[i];
    }
    REQUIRE(total == 0);
    if (s == kFullScale) REQUIRE(out == in);
    if (s == 0) REQUIRE(std::all_of(out.begin(), out.end(), [](int c) { return c == 0; }));
  }
}
