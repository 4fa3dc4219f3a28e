// Numbers (core/number): parsing, grids, formatting and the messages of refused values.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "error_support.hpp"

using namespace tp;

using tp::test::code_of;
using tp::test::message_of;

TEST_CASE("parse_finite accepts numbers and refuses everything else", "[io][number]") {
  CHECK(parse_finite("1.5", "v") == 1.5);
  CHECK(parse_finite("-2e-3", "v") == -2e-3);
  CHECK(parse_finite("+3", "v") == 3.0);
  CHECK(parse_finite(" 4 ", "v") == 4.0);
  for (const char* bad : {"", "abc", "1x", "nan", "inf", "-inf", "1e999", "1,2", "--1"})
    CHECK(code_of([&] { parse_finite(bad, "v"); }) == ExitCode::bad_input);
  CHECK(parse_integer("8", "n") == 8);
  CHECK(code_of([] { parse_integer("8.5", "n"); }) == ExitCode::bad_input);
  CHECK(parse_list("1,-1, 0.5", "w") == std::vector<double>{1, -1, 0.5});
  CHECK(code_of([] { parse_list("1,,2", "w"); }) == ExitCode::bad_input);
}

TEST_CASE("grid axes include both ends", "[io][number]") {
  CHECK(parse_axis("-3:3:0.25", "x").count() == 25);
  CHECK(parse_axis("0.5:2.5:0.5", "y").count() == 5);
  CHECK(parse_axis("0:1:0.1", "x").count() == 11);
  CHECK(parse_axis("1:1:0.1", "x").count() == 1);
  CHECK(parse_axis("0:1:0.3", "x").count() == 4);  // 0, 0.3, 0.6, 0.9
  // No point beyond MAX, though min + i * step rounds above it (0.01 + 1999 * 0.01 is
  // 20.000000000000004 in doubles): a grid ending at a model's limit stays within it.
  for (const char* text : {"0.01:20:0.01", "0.1:3:0.1", "-5:5:0.1", "0:0.3:0.1"}) {
    const Axis a = parse_axis(text, "y");
    CHECK(a.at(a.count() - 1) == a.max);
    for (std::size_t i = 0; i < a.count(); ++i) CHECK(a.at(i) <= a.max);
  }
  CHECK(parse_axis("0:1:0.3", "x").at(3) == Approx(0.9));  // not clamped where MAX is not a point
  for (const char* bad : {"1:0:0.1", "0:1:0", "0:1:-1", "0:1", "0:1:0.1:2", "a:1:1", "0:nan:1"})
    CHECK(code_of([&] { parse_axis(bad, "x"); }) == ExitCode::bad_input);
}

TEST_CASE("format_number is short, locale-free and never prints -0", "[io][number]") {
  char buf[32];
  auto fmt = [&](double v) { return std::string(buf, format_number(buf, v)); };
  CHECK(fmt(0.25) == "0.25");
  CHECK(fmt(-0.0) == "0");
  CHECK(fmt(1.0 / 3.0) == "0.3333333333");
  CHECK(fmt(-1.5e-7) == "-1.5e-07");
  CHECK(fmt(12345678.0) == "12345678");
}

TEST_CASE("format_number writes what printf(\"%.10g\") writes", "[io][number]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> ex(-14, 14);
  char buf[32], ref[64];
  int mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    double v = mant(rng) * std::pow(10.0, ex(rng));
    if (i % 10 == 0 && std::fabs(v) < 1e6) v = std::round(v * 1000) / 1000;  // short decimals
    const std::string got(buf, format_number(buf, v));
    std::snprintf(ref, sizeof ref, "%.10g", v == 0.0 ? 0.0 : v);
    if (got != ref) {
      ++mismatches;  // only possible at an exact rounding tie; must still round-trip
      INFO(got << " vs " << ref);
      CHECK(std::strtod(got.c_str(), nullptr) == Approx(v).epsilon(1e-9));
    }
  }
  CHECK(mismatches <= 2);
  for (double v :
       {1.0, 10.0, 9.9999999999, 0.00012345, 1e-5, 123456789012.0, 99999.999995, 1e-13, 5e13})
    CHECK(std::string(buf, format_number(buf, v)) == [&] {
      std::snprintf(ref, sizeof ref, "%.10g", v);
      return std::string(ref);
    }());
}

TEST_CASE("a refused value reads differently from the bound it breaks", "[io][number]") {
  // Issue 38: "0.80000000001 outside [0, 0.8]" printed the value as 0.8.
  CHECK(number_beside(0.80000000001, 0.8) == "0.80000000001");
  CHECK(number_beside(2.0000000000000004, 2.0) == "2.0000000000000004");
  CHECK(number_beside(-2.00000000001, -2.0) == "-2.00000000001");
  CHECK(number_beside(0.0099999999999, 0.01) == "0.0099999999999");
  CHECK(number_beside(1.00000000001e-7, 1e-7) == "1.00000000001e-07");
  // Otherwise number_text's 10 digits: a value far from its bound, or equal to it (an
  // open bound), reads as number_text writes it.
  CHECK(number_beside(2.5, 2.0) == "2.5");
  CHECK(number_beside(1.0 / 3.0, 2.0) == "0.3333333333");
  CHECK(number_beside(0.0, 0.0) == "0");
  CHECK(number_beside(1e300, 100.0) == "1e+300");
  // Beside the bound of [lo, hi] it breaks.
  CHECK(number_beside(0.80000000001, 0.0, 0.8) == "0.80000000001");
  CHECK(number_beside(-1e-12, 0.0, 0.8) == "-1e-12");
  CHECK(number_beside(0.00999999999999, 0.01, 20.0) == "0.00999999999999");
  // A value a step from a bound of up to 5 digits (every bound the programs print): it
  // reads differently, and on its side of the bound.
  std::mt19937_64 rng(38);
  for (int i = 0; i < 20000; ++i) {
    const double bound = std::strtod((std::to_string(rng() % 100000 + 1) + "e-3").c_str(), nullptr);
    const double value = std::nextafter(bound, i % 2 ? 1e9 : 0.0);
    const std::string text = number_beside(value, bound);
    REQUIRE(text != number_text(bound));
    const double read = std::strtod(text.c_str(), nullptr);
    REQUIRE((i % 2 ? read > bound : read < bound));
  }
  // Beside any bound, printed to 10 digits: on the same side of the printed bound.
  for (int i = 0; i < 20000; ++i) {
    const double bound = std::ldexp(static_cast<double>(rng() >> 11), -53) * 100.0 + 0.001;
    const double printed = std::strtod(number_text(bound).c_str(), nullptr);
    const double value = bound * (i % 2 ? 1 + 1e-12 : 1 - 1e-12);
    if (i % 2 ? value <= printed : value >= printed) continue;  // no digits can: skip
    const double read = std::strtod(number_beside(value, bound).c_str(), nullptr);
    REQUIRE((i % 2 ? read > printed : read < printed));
  }
  // And in a range's message.
  CHECK(message_of([] {
          ranges::check(2.00000000001, ranges::max_current_mA, "max_current_mA");
        }) == "max_current_mA: 2.00000000001 mA outside [0.001, 2] mA");
}

TEST_CASE("whole numbers are refused naming the text as given", "[io][number]") {
  CHECK(parse_integer("10000", "--population", 1, 10000) == 10000);
  CHECK(parse_integer("1e3", "--population", 1, 10000) == 1000);
  CHECK(parse_integer(" 7 ", "n", 1, 10) == 7);
  CHECK(message_of([] { parse_integer("99999999999999999999", "--population", 1, 10000); }) ==
        "--population: 99999999999999999999 outside [1, 10000]");
  CHECK(message_of([] { parse_integer("0", "--population", 1, 10000); }) ==
        "--population: 0 outside [1, 10000]");
  CHECK(message_of([] { parse_integer("2.5", "--threads", 1, 256); }) ==
        "--threads: not a whole number '2.5'");
  CHECK(message_of([] { parse_integer("0x10", "--threads", 1, 256); }) ==
        "--threads: not a number '0x10'");
  CHECK(parse_integer("010", "--threads", 1, 256) == 10);  // decimal, never octal
  // Seeds: every value from 0 to 2^64 - 1, exactly.
  CHECK(parse_unsigned("0", "--seed") == 0);
  CHECK(parse_unsigned("18446744073709551615", "--seed") == 18446744073709551615ULL);
  CHECK(parse_unsigned("9007199254740993", "--seed") == 9007199254740993ULL);  // 2^53 + 1
  CHECK(parse_unsigned("+5", "--seed") == 5);
  CHECK(message_of([] { parse_unsigned("-1", "--seed"); }) ==
        "--seed: -1 outside [0, 18446744073709551615]");
  CHECK(message_of([] { parse_unsigned("18446744073709551616", "--seed"); }) ==
        "--seed: 18446744073709551616 outside [0, 18446744073709551615]");
  CHECK(message_of([] { parse_unsigned("1e30", "--seed"); }) ==
        "--seed: 1e30 outside [0, 18446744073709551615]");
  CHECK(message_of([] { parse_unsigned("1.5", "--seed"); }) ==
        "--seed: not a whole number in decimal digits '1.5'");
  CHECK(message_of([] { parse_unsigned("seven", "--seed"); }) == "--seed: not a number 'seven'");
  CHECK(message_of([] { parse_unsigned("", "--seed"); }) == "--seed: empty number");
}
