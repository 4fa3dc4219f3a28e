#include "io/number.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include "core/error.hpp"

namespace tp {

double parse_finite(std::string_view text, const std::string& what) {
  // Trim surrounding blanks so "1, 2" works in lists.
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  if (text.empty()) bad_input(what + ": empty number");
  std::string_view body = text;
  if (body.front() == '+') body.remove_prefix(1);  // from_chars refuses a leading '+'
  double value = 0.0;
  const char* end = body.data() + body.size();
  auto [ptr, ec] = std::from_chars(body.data(), end, value);
  if (ec == std::errc::result_out_of_range)
    bad_input(what + ": number out of range '" + std::string(text) + "'");
  if (ec != std::errc() || ptr != end)
    bad_input(what + ": not a number '" + std::string(text) + "'");
  if (!std::isfinite(value)) bad_input(what + ": non-finite number '" + std::string(text) + "'");
  return value;
}

long parse_integer(std::string_view text, const std::string& what) {
  const double v = parse_finite(text, what);
  if (v != std::floor(v)) bad_input(what + ": not a whole number '" + std::string(text) + "'");
  if (std::fabs(v) > 1e9) bad_input(what + ": out of range '" + std::string(text) + "'");
  return static_cast<long>(v);
}

std::vector<double> parse_list(std::string_view text, const std::string& what) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string_view item =
        text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    out.push_back(parse_finite(item, what + " item " + std::to_string(out.size() + 1)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::size_t Axis::count() const {
  // Tolerate rounding in (max-min)/step so that "0:1:0.1" gives 11 points.
  const double n = std::floor((max - min) / step + 1e-9);
  return static_cast<std::size_t>(n) + 1;
}

Axis parse_axis(std::string_view text, const std::string& what) {
  const std::size_t a = text.find(':');
  const std::size_t b = a == std::string_view::npos ? a : text.find(':', a + 1);
  if (a == std::string_view::npos || b == std::string_view::npos ||
      text.find(':', b + 1) != std::string_view::npos)
    bad_input(what + ": expected MIN:MAX:STEP, got '" + std::string(text) + "'");
  Axis axis;
  axis.min = parse_finite(text.substr(0, a), what + " MIN");
  axis.max = parse_finite(text.substr(a + 1, b - a - 1), what + " MAX");
  axis.step = parse_finite(text.substr(b + 1), what + " STEP");
  if (!(axis.step > 0.0)) bad_input(what + ": STEP must be > 0");
  if (axis.max < axis.min) bad_input(what + ": empty grid (MAX < MIN)");
  if ((axis.max - axis.min) / axis.step > 1e8) bad_input(what + ": more than 1e8 points");
  return axis;
}

std::size_t format_number(char* buf, double value) {
  if (value == 0.0) value = 0.0;  // turn -0 into 0
  auto result = std::to_chars(buf, buf + 32, value, std::chars_format::general, 10);
  return static_cast<std::size_t>(result.ptr - buf);
}

}  // namespace tp
