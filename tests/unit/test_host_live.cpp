// Live frames (lib/host/live): the parser refuses a repeated key, checks a frame as the
// device checks its codes, and under random input (a property test) returns a checked frame
// or refuses it as bad input, never anything else.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "device/frame.hpp"
#include "host/line_reader.hpp"
#include "host/session.hpp"
#include "host/transport.hpp"

using namespace tp;

namespace {

long fuzz_iterations(long fallback) {
  const char* env = std::getenv("TP_FUZZ_ITERATIONS");
  return env ? std::max(1L, std::atol(env) / 100) : fallback;
}

Stimulus test_stimulus() {
  Stimulus s;
  s.currents_mA = {0, 0, -0.5, 1, -0.5, 0, 0, 0};
  s.count = 200;
  return s;
}

}  // namespace

TEST_CASE("a live frame that names currents_mA twice is refused", "[host][live]") {
  const Stimulus s = test_stimulus();
  const device::Capabilities caps;
  const StimulusLimits lim;
  const std::string one = "[0, 0, -0.5, 1, -0.5, 0, 0, 0]";
  const std::string two = "[0, 0, -1, 2, -1, 0, 0, 0]";
  CHECK(host::parse_live_frame("{\"currents_mA\": " + one + "}", 1, s, lim, caps).size() == 8);
  try {
    host::parse_live_frame("{\"currents_mA\": " + one + ", \"currents_mA\": " + two + "}", 3, s,
                           lim, caps);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK(std::string(e.what()) == "input line 3: key \"currents_mA\" appears twice in one object");
  }
}

TEST_CASE("a live frame is checked as the device checks its codes: RMS as the DAC makes it",
          "[host][live]") {
  Stimulus s = test_stimulus();
  s.shape.width_us = s.shape.balance_width_us = 250;
  s.shape.frequency_hz = 1000;
  const device::Capabilities caps;  // 977 nA a code
  const StimulusLimits lim;
  // 1.41421356 mA, 250 + 250 us at 1 kHz: RMS 0.99999999 mA; 1448 codes make 1.0003 mA.
  const std::string over =
      "{\"currents_mA\": [0, 0, 0, 0, -0.70710678, 0, 1.41421356, -0.70710678]}";
  try {
    host::parse_live_frame(over, 4, s, lim, caps);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Matchers::StartsWith("input line 4: electrode 6: RMS 1.0003"));
    CHECK_THAT(e.what(), Catch::Matchers::Contains("as the DAC makes them"));
  }
  const std::string under = "{\"currents_mA\": [0, 0, 0, 0, -0.7066, 0, 1.4132, -0.7066]}";
  CHECK(host::parse_live_frame(under, 5, s, lim, caps)[6] == 1446);
}

TEST_CASE("live frames: random JSON is a checked frame or bad input, nothing else",
          "[host][live][fuzz]") {
  SplitMix64 rng{7};
  const Stimulus s = test_stimulus();
  const device::Capabilities caps;
  const StimulusLimits lim;
  auto number = [&]() -> std::string {
    const double k = rng.unit();
    if (k < 0.1) return "1e999";
    if (k < 0.15) return "-1e999";
    if (k < 0.2) return "1e-999";
    if (k < 0.25) return "-0";
    if (k < 0.3) return "123456789012345678901234567890";
    if (k < 0.35) return std::to_string(static_cast<long>(rng.next() >> 1));
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", (rng.unit() - 0.5) * std::pow(10.0, rng.unit() * 10 - 6));
    return b;
  };
  std::function<std::string(int)> value = [&](int depth) -> std::string {
    const double k = rng.unit();
    if (depth > 6 || k < 0.4) return number();
    if (k < 0.5) return "\"s\"";
    if (k < 0.55) return rng.unit() < 0.5 ? "true" : "null";
    const int n = static_cast<int>(rng.unit() * 10);
    std::string out = k < 0.8 ? "[" : "{";
    for (int i = 0; i < n; ++i) {
      if (i) out += ",";
      if (out[0] == '{')
        out += rng.unit() < 0.5 ? "\"currents_mA\":" : "\"k" + std::to_string(i) + "\":";
      out += value(depth + 1);
    }
    return out + (out[0] == '[' ? "]" : "}");
  };
  const long cases = fuzz_iterations(20000);
  long accepted = 0;
  for (long c = 0; c < cases; ++c) {
    std::string line;
    const double k = rng.unit();
    if (k < 0.4) {  // a frame of 8 currents, some valid
      line = "{\"currents_mA\": [";
      const double a = rng.unit() * 2.2;
      std::vector<double> v = {0, 0, -a / 2, a, -a / 2, 0, 0, 0};
      for (std::size_t i = 0; i < v.size(); ++i) {
        char b[40];
        std::snprintf(b, sizeof b, "%.17g", v[i]);
        line += (i ? "," : "") + (rng.unit() < 0.05 ? number() : std::string(b));
      }
      line += "]}";
    } else if (k < 0.8) {
      line = value(0);
    } else {  // byte mutations of a valid frame, or deep nesting
      line = "{\"currents_mA\": [0, 0, -0.5, 1, -0.5, 0, 0, 0]}";
      for (int m = static_cast<int>(rng.unit() * 4); m >= 0; --m)
        line[static_cast<std::size_t>(rng.unit() * static_cast<double>(line.size()))] =
            static_cast<char>(rng.unit() * 256);
      if (rng.unit() < 0.01) line = std::string(100000, '[');
    }
    try {
      const auto codes = host::parse_live_frame(line, 1, s, lim, caps);
      ++accepted;
      long sum = 0;
      for (std::int16_t x : codes) {
        CHECK(std::abs(int{x}) <= caps.max_code());
        sum += x;
      }
      CHECK(sum == 0);
      CHECK(codes.size() == 8);
      // and what the device's own load check accepts
      device::ChannelLoad load;
      device::add_dense(load, codes, pattern_timing(s, 0));
      CHECK(load.within(caps));
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
    }
  }
  CHECK(accepted > 0);
  WARN("live frames: " << cases << " random lines, " << accepted << " accepted");
}
