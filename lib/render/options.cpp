#include "render/options.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "io/number.hpp"
#include "render/profile.hpp"

namespace tp {

namespace {

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    const std::size_t end = std::min(text.find(',', at), text.size());
    out.push_back(text.substr(at, end - at));
    if (end == text.size()) return out;
    at = end + 1;
  }
}

}  // namespace

void parse_rates(const std::string& text, std::array<double, 3>& rate) {
  std::array<bool, 3> given{};
  for (const std::string& item : split_commas(text)) {
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos)
      bad_input("--rates: '" + item + "' is not PRIMARY:HZ (e.g. SAI:200)");
    const std::string name = item.substr(0, colon);
    const auto p = static_cast<std::size_t>(primary_index(name, "--rates"));
    if (given[p]) bad_input("--rates: " + name + " given twice (" + text + "): give each once");
    given[p] = true;
    rate[p] = parse_finite(item.substr(colon + 1), "--rates");
  }
}

std::vector<int> parse_primaries(const std::string& text, const std::string& what) {
  std::vector<int> out;
  for (const std::string& item : split_commas(text)) {
    const int p = primary_index(item, what);
    if (std::find(out.begin(), out.end(), p) != out.end())
      bad_input(what + ": " + item + " given twice");
    out.push_back(p);
  }
  return out;
}

void check_render_options(const RenderOptions& o) {
  const StimulusLimits& l = o.limits;
  for (std::size_t p = 0; p < 3; ++p)
    if (!(o.rate_hz[p] >= l.min_frequency_hz && o.rate_hz[p] <= l.max_frequency_hz))
      bad_input(std::string("--rates: ") + kPrimaries[p] + " " +
                number_beside(o.rate_hz[p], l.min_frequency_hz, l.max_frequency_hz) +
                " Hz outside [" + number_text(l.min_frequency_hz) + ", " +
                number_text(l.max_frequency_hz) + "] Hz");
  auto whole = [](double v, double lo, double hi, const char* name) {
    if (!(v >= lo && v <= hi && v == std::floor(v)))
      bad_input(std::string(name) + ": " + number_beside(v, lo, hi) +
                " us is not a whole number in [" + number_text(lo) + ", " + number_text(hi) +
                "] us");
  };
  whole(o.width_us, l.min_width_us, l.max_width_us, "--width");
  whole(o.interphase_us, 0, 1000, "--interphase");
  whole(o.balance_width_us, o.width_us, l.max_balance_width_us, "--balance-width");
  whole(o.gap_us, l.min_gap_us, l.max_slip_us, "--gap");
  if (!(o.crosstalk >= 0 && o.crosstalk <= 1))
    bad_input("--crosstalk: " + number_beside(o.crosstalk, 0, 1) + " outside [0, 1]");
  if (!(o.duration_s > 0 && o.duration_s <= l.max_duration_s))
    bad_input("--duration: " + number_beside(o.duration_s, 0, l.max_duration_s) +
              " s outside (0, " + number_text(l.max_duration_s) + "] s");
}

}  // namespace tp
