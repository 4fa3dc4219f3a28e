#include "core/number.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <system_error>

#include "core/error.hpp"
#include "core/text.hpp"

namespace tp {

namespace {

std::string_view trimmed(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

}  // namespace

double parse_finite(std::string_view text, const std::string& what) {
  text = trimmed(text);  // surrounding blanks, so that "1, 2" works in lists
  if (text.empty()) bad_input(what + ": empty number");
  std::string_view body = text;
  if (body.front() == '+') body.remove_prefix(1);  // from_chars refuses a leading '+'
  double value = 0.0;
  const char* end = body.data() + body.size();
  auto [ptr, ec] = std::from_chars(body.data(), end, value);
  if (ec == std::errc::result_out_of_range)
    bad_input(what + ": number out of range " + quoted_text(text));
  if (ec != std::errc() || ptr != end) bad_input(what + ": not a number " + quoted_text(text));
  if (!std::isfinite(value)) bad_input(what + ": non-finite number " + quoted_text(text));
  return value;
}

long parse_integer(std::string_view text, const std::string& what) {
  const double v = parse_finite(text, what);
  if (v != std::floor(v)) bad_input(what + ": not a whole number " + quoted_text(trimmed(text)));
  if (std::fabs(v) > 1e9) bad_input(what + ": out of range " + quoted_text(trimmed(text)));
  return static_cast<long>(v);
}

long long parse_integer(std::string_view text, const std::string& what, long long lo,
                        long long hi) {
  // The bounds are within 2^53, where doubles hold every whole number: the comparison is
  // exact, and a text far beyond them (99999999999999999999) is named as it was given.
  const double v = parse_finite(text, what);
  if (v != std::floor(v)) bad_input(what + ": not a whole number " + quoted_text(trimmed(text)));
  if (v < static_cast<double>(lo) || v > static_cast<double>(hi))
    bad_input(what + ": " + printable(trimmed(text)) + " outside [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "]");
  return static_cast<long long>(v);
}

unsigned long long parse_unsigned(std::string_view text, const std::string& what) {
  static const std::string range = " outside [0, 18446744073709551615]";
  const std::string_view t = trimmed(text);
  if (t.empty()) bad_input(what + ": empty number");
  const std::string_view body = t.front() == '+' ? t.substr(1) : t;
  const bool digits = !body.empty() && body.find_first_not_of("0123456789") == body.npos;
  if (digits) {
    unsigned long long v = 0;
    const auto [ptr, ec] = std::from_chars(body.data(), body.data() + body.size(), v);
    if (ec == std::errc::result_out_of_range) bad_input(what + ": " + printable(t) + range);
    if (ec == std::errc() && ptr == body.data() + body.size()) return v;
  }
  const double v = parse_finite(t, what);  // junk: "not a number"
  if (v < 0 || v >= 18446744073709551616.0) bad_input(what + ": " + printable(t) + range);
  bad_input(what + ": not a whole number in decimal digits " + quoted_text(t));
}

std::vector<double> parse_list(std::string_view text, const std::string& what) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string_view item = text.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
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
    bad_input(what + ": expected MIN:MAX:STEP, got " + quoted_text(text));
  Axis axis;
  axis.min = parse_finite(text.substr(0, a), what + " MIN");
  axis.max = parse_finite(text.substr(a + 1, b - a - 1), what + " MAX");
  axis.step = parse_finite(text.substr(b + 1), what + " STEP");
  if (!(axis.step > 0.0)) bad_input(what + ": STEP must be > 0");
  if (axis.max < axis.min) bad_input(what + ": empty grid (MAX < MIN)");
  if (!((axis.max - axis.min) / axis.step <= 1e8)) bad_input(what + ": more than 1e8 points");
  return axis;
}

std::size_t format_number(char* buf, double value) {
  // The text of printf("%.10g"), made with integer arithmetic: round |value| to a 10-digit
  // integer mantissa m (10^9 <= m < 10^10) and a decimal exponent e, then lay out the
  // digits.  std::to_chars and {fmt} with a precision take ~70 ns a number here, which
  // dominated af-field's run time; this takes a few.  Values outside [1e-12, 1e12) and
  // non-finite ones go to std::to_chars.
  static const double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                  1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                  1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  static const double kPow10Neg[] = {1e0,  1e-1, 1e-2, 1e-3,  1e-4,  1e-5,  1e-6,
                                     1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13};
  static const char kPairs[] =
      "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
      "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
      "8081828384858687888990919293949596979899";
  if (value == 0.0) {
    buf[0] = '0';
    return 1;
  }
  const double a = std::fabs(value);
  if (!(a >= 1e-12 && a < 1e12)) {
    auto result = std::to_chars(buf, buf + 32, value, std::chars_format::general, 10);
    return static_cast<std::size_t>(result.ptr - buf);
  }
  auto pow10 = [](int k) { return k >= 0 ? kPow10[k] : kPow10Neg[-k]; };
  // Decimal exponent from the binary one: floor(e2 * log10(2)), corrected by one step.
  int e = (std::ilogb(a) * 78913) >> 18;
  if (a < pow10(e))
    --e;
  else if (a >= pow10(e + 1))
    ++e;
  const int k = 9 - e;  // -2 <= k <= 21
  long long m = std::llrint(k >= 0 ? a * kPow10[k] : a / kPow10[-k]);
  if (m >= 10000000000LL) {
    m /= 10;
    ++e;
  }
  char d[10];
  for (int i = 8; i >= 0; i -= 2, m /= 100) std::memcpy(d + i, kPairs + 2 * (m % 100), 2);
  int nd = 10;
  while (nd > 1 && d[nd - 1] == '0') --nd;

  char* p = buf;
  if (value < 0) *p++ = '-';
  if (e < -4 || e >= 10) {  // scientific, as %g: d.ddde-05
    *p++ = d[0];
    if (nd > 1) {
      *p++ = '.';
      for (int i = 1; i < nd; ++i) *p++ = d[i];
    }
    *p++ = 'e';
    *p++ = e < 0 ? '-' : '+';
    const int ae = e < 0 ? -e : e;
    *p++ = static_cast<char>('0' + ae / 10);
    *p++ = static_cast<char>('0' + ae % 10);
  } else if (e >= 0) {
    for (int i = 0; i <= e; ++i) *p++ = d[i];
    if (nd > e + 1) {
      *p++ = '.';
      for (int i = e + 1; i < nd; ++i) *p++ = d[i];
    }
  } else {
    *p++ = '0';
    *p++ = '.';
    for (int i = 0; i < -e - 1; ++i) *p++ = '0';
    for (int i = 0; i < nd; ++i) *p++ = d[i];
  }
  return static_cast<std::size_t>(p - buf);
}

std::string number_text(double value) {
  char buf[32];
  return std::string(buf, format_number(buf, value));
}

std::string number_beside(double value, double bound) {
  std::string text = number_text(value);
  const std::string bound_text = number_text(bound);
  if (value == bound || !std::isfinite(value) || !std::isfinite(bound)) return text;
  // As many digits as it takes for the value to read differently from the bound as it is
  // printed, and on the same side of it (0.80000000001 above 0.8, not equal to it; never
  // 1.4282874546 beside a bound printed 1.428287455 that it exceeds).
  const double printed_bound = std::strtod(bound_text.c_str(), nullptr);
  auto reads_right = [&](const std::string& t) {
    const double v = std::strtod(t.c_str(), nullptr);
    return t != bound_text && (value > bound ? v > printed_bound : v < printed_bound);
  };
  char buf[64];
  for (int digits = 11; digits <= 17 && !reads_right(text); ++digits) {
    const auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, digits);
    text.assign(buf, r.ptr);
  }
  return text;
}

std::string number_beside(double value, double lo, double hi) {
  return number_beside(value, value < lo ? lo : hi);
}

}  // namespace tp
