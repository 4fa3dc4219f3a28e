#pragma once
// An adaptive psychophysical procedure for one level (a current, mA): an ascending method
// of limits to bracket, then a transformed up-down staircase (docs/calibration.md).
//
//  1. Ascending: from start_mA, each "no" multiplies the level by ascend_factor, until the
//     first "yes" (or the ceiling, answered "no": not found).
//  2. Staircase, from that level: n-down-1-up (down consecutive "yes" answers step down,
//     one "no" steps up).  H. Levitt, "Transformed up-down methods in psychoacoustics",
//     J. Acoust. Soc. Am. 49(2B):467-477, 1971 (Table I): 1-down-1-up converges on the
//     level answered "yes" half the time, 2-down-1-up on 70.7 %, 3-down-1-up on 79.4 %.
//     Steps are factors (equal in log level), the first step_factor, then its square root
//     after the first two reversals; the run ends after `reversals` reversals or
//     max_trials trials.  The estimate is the geometric mean of the levels of the
//     reversals made at the smaller step (all but the first two).
//
// Safety: no level is ever above ceiling_mA (a step that would pass it stops there), and no
// step up is larger than max_step_up (ascend_factor and step_factor are bounded by it).
// A run that is answered "no" at the ceiling ends there, not found: in the ascending series
// at once, in the staircase after kNoAtCeiling such answers in a row (one "yes" there, then
// nothing: a false alarm, or a comfort limit above the ceiling), so it never dwells at the
// ceiling.  Nor at the floor: kYesAtFloor "yes" answers in a row at kMinLevel_mA end it,
// not found (the level is below what the procedure measures).  end() says which ended it.
//
// "yes" is whatever the question asks: "did you feel it?" for a detection threshold,
// "is it too strong?" for a comfort limit.

#include <cstddef>
#include <vector>

namespace tp {

// "No" answers in a row at the ceiling that end a staircase, not found.
inline constexpr int kNoAtCeiling = 3;

// "Yes" answers in a row at the floor that end a staircase, not found.
inline constexpr int kYesAtFloor = 3;

// The lowest level a run uses: a start below it is bad input, and no step goes under it.
inline constexpr double kMinLevel_mA = 0.001;

struct StaircaseOptions {
  double start_mA = 0.05;       // the ascending series' first level, [kMinLevel_mA, ceiling]
  double ceiling_mA = 1.0;      // never exceeded, (0, 2] mA
  double ascend_factor = 1.25;  // each ascending step, (1, max_step_up]
  double step_factor = 1.25;    // the staircase's first step, (1, max_step_up]
  double max_step_up = 1.5;     // the largest step up, (1, 2]
  int down = 2;                 // n-down-1-up, 1 to 3
  int reversals = 8;            // to end the staircase, 4 to 30
  int max_trials = 80;          // in all, both phases, 10 to 1000
};
// Throws tp::Error (bad input) naming the first value outside its range by calibrate's flag
// ("--ceiling: 2.5 mA outside (0, 2] mA").
void check_staircase_options(const StaircaseOptions& o);

// What ended a run.
enum class StaircaseEnd {
  running,        // not done yet
  reversals,      // its `reversals` reversals: found
  ceiling,        // the ascending series reached the ceiling, answered "no" there
  no_at_ceiling,  // kNoAtCeiling "no" answers in a row at the ceiling, in the staircase
  yes_at_floor,   // kYesAtFloor "yes" answers in a row at the floor
  trials,         // max_trials trials before `reversals` reversals
};

struct StaircaseTrial {
  int n = 0;  // 1, 2, ...
  double level_mA = 0;
  bool ascending = true;  // the method-of-limits phase
  bool yes = false;
  bool reversal = false;  // this answer turned the staircase's direction
};

// The trials a run takes against an observer who answers "yes" exactly above level_mA:
// the procedure's own count for a session's length (calibrate's "about N trials").
int typical_trials(const StaircaseOptions& o, double level_mA);

class Staircase {
 public:
  explicit Staircase(const StaircaseOptions& o);  // checks o
  bool done() const { return done_; }
  double level_mA() const { return level_; }  // the next trial's level (while !done())
  void respond(bool yes);                     // the answer at level_mA()
  // After done(): what ended it; whether the staircase ran to its end (its reversals; any
  // other end is not found), its estimate (geometric mean of the small-step reversals) and
  // their spread (the standard deviation of those levels, mA).
  StaircaseEnd end() const { return end_; }
  bool found() const { return end_ == StaircaseEnd::reversals; }
  int reversals() const { return static_cast<int>(reversal_levels_.size()); }
  double estimate_mA() const { return estimate_; }
  double spread_mA() const { return spread_; }
  const std::vector<StaircaseTrial>& trials() const { return trials_; }

 private:
  void finish(StaircaseEnd end);
  StaircaseOptions o_;
  double level_ = 0;
  bool ascending_ = true;
  bool done_ = false;
  StaircaseEnd end_ = StaircaseEnd::running;
  int yes_run_ = 0;
  int no_at_ceiling_ = 0, yes_at_floor_ = 0;
  int direction_ = 0;  // +1 up, -1 down, 0 none yet
  double step_ = 1;
  std::vector<double> reversal_levels_;
  double estimate_ = 0, spread_ = 0;
  std::vector<StaircaseTrial> trials_;
};

}  // namespace tp
