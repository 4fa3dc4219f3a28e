#pragma once
// A shaped pulse: up to 16 piecewise-constant phases, each a duration and a level relative
// to the amplitude (+1: the main cathodic phase on an electrode of weight 1), as a weights
// or stimulus document's `pulse.phases` gives them (docs/document-format.md, "Shaped
// pulses").  The biphasic shorthand (width, gap, balance) is the same thing in three phases.
// A delivered shape is charge balanced exactly: its levels are whole multiples of 1/U for a
// small U (the level unit), so that a device sums them in integers (docs/protocol.md).

#include <cstddef>
#include <string>
#include <vector>

#include "core/json.hpp"

namespace tp {

struct Phase {
  double duration_us = 0;
  double level = 0;  // x the channel's current; + = cathodic
};

inline constexpr std::size_t kMaxPhases = 16;
inline constexpr int kMaxLevelUnit = 64;  // the largest U: levels are multiples of 1/64 at least
inline constexpr double kMaxLevel = 16;   // |level| at most 16 x the channel's current

// The phases of the biphasic shorthand: the main phase at +1, the gap (if any) at 0, the
// balancing phase at -width / balance_width.
std::vector<Phase> shorthand_phases(double width_us, double interphase_us,
                                    double balance_width_us);

// Sums over a shape, per mA of the channel's current (so x |I| gives nC, mA^2 us, ...).
struct ShapeSums {
  double length_us = 0;              // Sum d
  double net_us = 0;                 // Sum L d (0: balanced)
  double abs_us = 0;                 // Sum |L| d (both signs' charge)
  double square_us = 0;              // Sum L^2 d (for the RMS)
  double peak_level = 0;             // max |L|
  double shortest_us = 0;            // the shortest phase (gaps included)
  std::vector<double> run_charge_us;  // Sum |L| d over each run of one sign (gaps inside a
                                      // run do not end it): the charge "per phase"
  double max_run_charge_us() const;
};
ShapeSums shape_sums(const std::vector<Phase>& phases);

// The shape in integer units: level_k = units[k] / unit, the least unit (1 to 64) that makes
// every level whole; Sum units_k d_k == 0 exactly.  Bad input when no unit up to 64 does,
// or the shape is not balanced.
struct ShapeUnits {
  int unit = 1;
  std::vector<int> units;
};
ShapeUnits shape_units(const std::vector<Phase>& phases);
// The least U (1 to 64) that makes every level a whole multiple of 1/U; 0 when none does.
int level_unit(const std::vector<Phase>& phases);

// The ranges of a shape that is delivered (bad input naming the phase): 1 to 16 phases,
// whole microseconds from min_width_us to max_balance_width_us, the phases at the largest
// |level| at most max_width_us, |level| at most 16 and not all 0, charge balanced in units.
struct PhaseLimits {
  double min_width_us = 10.0;
  double max_width_us = 1000.0;
  double max_balance_width_us = 8000.0;
};
void check_phases(const std::vector<Phase>& phases, const PhaseLimits& limits);

// The ranges of a shape that is only simulated (fiber-threshold --phases): 1 to 16 phases,
// durations 1 to 10000 us, |level| at most 16, not all 0; balance not required.
void check_simulated_phases(const std::vector<Phase>& phases);

// [{"duration_us": D, "level": L}, ...].  Reading checks structure and finiteness and
// reads at most 16 phases (more is bad input naming `where`).
Json phases_to_json(const std::vector<Phase>& phases);
std::vector<Phase> phases_from_json(const Json& j, const std::string& where);

// "200:1,100:0,800:-0.25" (make-pulse --phases, fiber-threshold --phases); bad input
// naming `flag`.
std::vector<Phase> phases_from_text(const std::string& text, const std::string& flag);

// "200 us at 1, 100 us at 0, 800 us at -0.25".
std::string describe_phases(const std::vector<Phase>& phases);

// Same durations and levels within 1e-9 (relative).
bool same_phases(const std::vector<Phase>& a, const std::vector<Phase>& b);

}  // namespace tp
