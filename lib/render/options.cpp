#include "render/options.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"
#include "psych/profile.hpp"
#include "psych/pulse_train.hpp"

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
  check_pulse_train(o.rate_hz, o.width_us, o.interphase_us, o.balance_width_us, l);
  check_whole_us(o.gap_us, l.min_gap_us, l.max_slip_us, "--gap");
  if (!(o.crosstalk >= 0 && o.crosstalk <= 1))
    bad_input("--crosstalk: " + number_beside(o.crosstalk, 0, 1) + " outside [0, 1]");
  if (!(o.duration_s > 0 && o.duration_s <= l.max_duration_s))
    bad_input("--duration: " + number_beside(o.duration_s, 0, l.max_duration_s) +
              " s outside (0, " + number_text(l.max_duration_s) + "] s");
}

}  // namespace tp
