#pragma once
// Strict number parsing (whole string, finite) and fast, locale-free formatting.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace tp {

// Parses a finite double; `what` names the value in the error message.
// Throws tp::Error (bad input) on anything else: empty, trailing junk, nan, inf.
double parse_finite(std::string_view text, const std::string& what);

// Parses a whole-number (e.g. an electrode count); rejects fractions and junk.
long parse_integer(std::string_view text, const std::string& what);

// Parses a comma-separated list of finite doubles ("1,-0.5,2").
std::vector<double> parse_list(std::string_view text, const std::string& what);

// An inclusive grid axis "MIN:MAX:STEP" (both ends included when MAX-MIN is a multiple of STEP,
// to a relative 1e-9 of STEP).  No point lies beyond MAX: min + i*step is rounded in floating
// point (0.01 + 1999 * 0.01 is 20.000000000000004), so the last point is clamped to MAX.
struct Axis {
  double min = 0.0;
  double max = 0.0;
  double step = 1.0;
  std::size_t count() const;
  double at(std::size_t i) const {
    const double v = min + static_cast<double>(i) * step;
    return v < max ? v : max;
  }
};
Axis parse_axis(std::string_view text, const std::string& what);

// Writes the shortest of %.10g-like output into buf (needs 32 bytes); returns chars written.
// Locale-independent; -0 is written as 0.
std::size_t format_number(char* buf, double value);

// format_number as a string (for messages).
std::string number_text(double value);

// A value refused beside its bound: number_text(value), or, where that reads the same as
// number_text(bound) (or on the wrong side of it), as many more significant digits (up to
// the 17 that tell any two doubles apart) as it takes to read differently and on the right
// side: 0.80000000001 beside 0.8, where number_text writes both as 0.8.  Every message that
// sets a value against the limit it breaks writes the value this way.
std::string number_beside(double value, double bound);
// The same beside the bound of [lo, hi] that it breaks (lo when below it, else hi).
std::string number_beside(double value, double lo, double hi);

// Parses a whole number within [lo, hi]; the message names the text as given, never a
// value it was clamped or wrapped to: "WHAT: TEXT outside [LO, HI]".  Fractions and junk
// are refused as parse_integer refuses them.
long long parse_integer(std::string_view text, const std::string& what, long long lo, long long hi);

// Parses an unsigned 64-bit whole number in decimal digits (a seed: every value from 0 to
// 2^64 - 1 is a different one), exactly; a sign, a fraction or a value beyond
// 18446744073709551615 is refused naming the text and the range.
unsigned long long parse_unsigned(std::string_view text, const std::string& what);

}  // namespace tp
