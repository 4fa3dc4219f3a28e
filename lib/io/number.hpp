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

}  // namespace tp
