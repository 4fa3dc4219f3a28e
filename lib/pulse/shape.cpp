// Shaped pulses: phases, their sums, their integer units and their ranges.

#include "pulse/shape.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp {
namespace {

std::string phase_name(std::size_t k) { return "phase " + std::to_string(k + 1); }

// 1 to 16 phases, finite, |level| <= 16, not all 0.
void check_count_and_levels(const std::vector<Phase>& p) {
  if (p.empty()) bad_input("pulse.phases: no phases");
  if (p.size() > kMaxPhases)
    bad_input("pulse.phases: " + std::to_string(p.size()) + " phases, more than " +
              std::to_string(kMaxPhases));
  bool any = false;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (!std::isfinite(p[k].level) || std::fabs(p[k].level) > kMaxLevel)
      bad_input(phase_name(k) + ": level " + number_beside(p[k].level, -kMaxLevel, kMaxLevel) +
                " outside [-16, 16] (x the channel's current)");
    any = any || p[k].level != 0.0;
  }
  if (!any) bad_input("pulse.phases: every level is 0: no current");
}

}  // namespace

std::vector<Phase> shorthand_phases(double width_us, double interphase_us,
                                    double balance_width_us) {
  std::vector<Phase> p{{width_us, 1.0}};
  if (interphase_us > 0) p.push_back({interphase_us, 0.0});
  p.push_back({balance_width_us, -width_us / balance_width_us});
  return p;
}

double ShapeSums::max_run_charge_us() const {
  double m = 0;
  for (double q : run_charge_us) m = std::max(m, q);
  return m;
}

ShapeSums shape_sums(const std::vector<Phase>& phases) {
  ShapeSums s;
  s.shortest_us = phases.empty() ? 0.0 : HUGE_VAL;
  int sign = 0;  // of the run under way
  for (const Phase& ph : phases) {
    const double a = std::fabs(ph.level);
    s.length_us += ph.duration_us;
    s.net_us += ph.level * ph.duration_us;
    s.abs_us += a * ph.duration_us;
    s.square_us += ph.level * ph.level * ph.duration_us;
    s.peak_level = std::max(s.peak_level, a);
    s.shortest_us = std::min(s.shortest_us, ph.duration_us);
    if (ph.level == 0.0) continue;  // a gap does not end a run
    const int sg = ph.level > 0 ? 1 : -1;
    if (sg != sign) s.run_charge_us.push_back(0.0);
    sign = sg;
    s.run_charge_us.back() += a * ph.duration_us;
  }
  return s;
}

int level_unit(const std::vector<Phase>& phases) {
  for (int unit = 1; unit <= kMaxLevelUnit; ++unit) {
    bool whole = true;
    for (const Phase& ph : phases) {
      const double v = ph.level * unit;
      whole = whole && std::fabs(v - std::round(v)) <= 1e-9 * std::max(1.0, std::fabs(v));
    }
    if (whole) return unit;
  }
  return 0;
}

ShapeUnits shape_units(const std::vector<Phase>& phases) {
  const ShapeSums sums = shape_sums(phases);
  if (std::fabs(sums.net_us) > 1e-9 * sums.abs_us)
    bad_input("pulse.phases: not charge balanced: the sum of level x duration is " +
              number_text(sums.net_us) + " us, not 0");
  ShapeUnits u;
  u.unit = level_unit(phases);
  if (u.unit == 0)
    bad_input("pulse.phases: levels must be multiples of 1/U for some U up to 64 (a device "
              "balances the charge in whole units); give levels like 0.25 or 0.1");
  std::int64_t net = 0;  // exact: durations are whole microseconds (check_phases)
  for (const Phase& ph : phases) {
    u.units.push_back(static_cast<int>(std::lround(ph.level * u.unit)));
    net += static_cast<std::int64_t>(u.units.back()) * std::llround(ph.duration_us);
  }
  if (net != 0)
    bad_input("pulse.phases: not charge balanced in whole units: the sum of level x "
              "duration is " + number_text(static_cast<double>(net) / u.unit) + " us, not 0");
  return u;
}

void check_phases(const std::vector<Phase>& p, const PhaseLimits& lim) {
  check_count_and_levels(p);
  const ShapeSums sums = shape_sums(p);
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double d = p[k].duration_us;
    if (!std::isfinite(d) || d < lim.min_width_us || d > lim.max_balance_width_us)
      bad_input(phase_name(k) + ": duration " +
                number_beside(d, lim.min_width_us, lim.max_balance_width_us) +
                " us outside [" + number_text(lim.min_width_us) + ", " +
                number_text(lim.max_balance_width_us) + "] us");
    if (std::fabs(d - std::round(d)) > 1e-9)
      bad_input(phase_name(k) + ": duration " + number_text(d) +
                " us: a device takes whole microseconds");
    if (std::fabs(p[k].level) == sums.peak_level && d > lim.max_width_us)
      bad_input(phase_name(k) + ": " + number_beside(d, lim.max_width_us) +
                " us at the largest level, longer than the main phase's limit of " +
                number_text(lim.max_width_us) + " us");
  }
  (void)shape_units(p);
}

void check_simulated_phases(const std::vector<Phase>& p) {
  check_count_and_levels(p);
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double d = p[k].duration_us;
    if (!(d >= 1.0 && d <= 10000.0))
      bad_input(phase_name(k) + ": duration " + number_beside(d, 1.0, 10000.0) +
                " us outside [1, 10000] us");
  }
}

Json phases_to_json(const std::vector<Phase>& phases) {
  Json a = Json::array();
  for (const Phase& p : phases) a.push_back(Json{{"duration_us", p.duration_us}, {"level", p.level}});
  return a;
}

std::vector<Phase> phases_from_json(const Json& j, const std::string& where) {
  if (!j.is_array()) bad_input(where + ": expected an array of {\"duration_us\", \"level\"}");
  if (j.size() > kMaxPhases)
    bad_input(where + ": " + std::to_string(j.size()) + " phases, more than " +
              std::to_string(kMaxPhases));
  std::vector<Phase> p;
  for (std::size_t k = 0; k < j.size(); ++k) {
    const std::string at = where + "[" + std::to_string(k) + "]";
    const Json& e = j[k];
    if (!e.is_object() || !e.contains("duration_us") || !e.contains("level") || e.size() != 2)
      bad_input(at + ": expected {\"duration_us\": D, \"level\": L}");
    p.push_back({json_finite(e["duration_us"], at + ".duration_us"),
                 json_finite(e["level"], at + ".level")});
  }
  return p;
}

std::vector<Phase> phases_from_text(const std::string& text, const std::string& flag) {
  std::vector<Phase> p;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos)
      bad_input(flag + ": expected DURATION_US:LEVEL,... (like 200:1,200:-1), got '" + item + "'");
    if (p.size() == kMaxPhases)
      bad_input(flag + ": more than " + std::to_string(kMaxPhases) + " phases");
    p.push_back({parse_finite(item.substr(0, colon), flag + " duration"),
                 parse_finite(item.substr(colon + 1), flag + " level")});
    start = comma + 1;
  }
  return p;
}

std::string describe_phases(const std::vector<Phase>& phases) {
  std::string s;
  for (const Phase& p : phases)
    s += (s.empty() ? "" : ", ") + number_text(p.duration_us) + " us at " + number_text(p.level);
  return s;
}

bool same_phases(const std::vector<Phase>& a, const std::vector<Phase>& b) {
  auto same = [](double x, double y) {
    return std::fabs(x - y) <= 1e-9 * std::max(1.0, std::fabs(x));
  };
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!same(a[k].duration_us, b[k].duration_us) || !same(a[k].level, b[k].level)) return false;
  return true;
}

}  // namespace tp
