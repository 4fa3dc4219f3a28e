#include "psych/staircase.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp {
namespace {

// "--flag: V unit outside [lo, hi] unit" (the flag calibrate sets it with).
void in_range(double v, double lo, double hi, bool lo_open, const std::string& flag,
              const std::string& unit = "") {
  const bool ok = (lo_open ? v > lo : v >= lo) && v <= hi;
  const std::string u = unit.empty() ? "" : " " + unit;
  if (!ok)
    bad_input(flag + ": " + number_beside(v, lo, hi) + u + " outside " + (lo_open ? "(" : "[") +
              number_text(lo) + ", " + number_text(hi) + "]" + u);
}

}  // namespace

void check_staircase_options(const StaircaseOptions& o) {
  in_range(o.ceiling_mA, 0, 2, true, "--ceiling", "mA");
  in_range(o.start_mA, kMinLevel_mA, o.ceiling_mA, false, "--start", "mA");
  in_range(o.max_step_up, 1, 2, true, "--max-step");
  in_range(o.ascend_factor, 1, o.max_step_up, true, "--step");
  in_range(o.step_factor, 1, o.max_step_up, true, "--step");
  in_range(o.down, 1, 3, false, "--down");
  in_range(o.reversals, 4, 30, false, "--reversals");
  in_range(o.max_trials, 10, 1000, false, "--max-trials");
}

Staircase::Staircase(const StaircaseOptions& o) : o_(o) {
  check_staircase_options(o);
  level_ = o.start_mA;
  step_ = o.step_factor;
}

void Staircase::respond(bool yes) {
  if (done_) return;
  StaircaseTrial t;
  t.n = static_cast<int>(trials_.size()) + 1;
  t.level_mA = level_;
  t.ascending = ascending_;
  t.yes = yes;
  trials_.push_back(t);
  if (ascending_ && !yes) {
    if (level_ >= o_.ceiling_mA) {  // nothing felt up to the ceiling
      finish(StaircaseEnd::ceiling);
      return;
    }
    level_ = std::min(level_ * o_.ascend_factor, o_.ceiling_mA);
  } else {
    // The staircase (the ascending series' first "yes" is its first answer).
    ascending_ = false;
    no_at_ceiling_ = !yes && level_ >= o_.ceiling_mA ? no_at_ceiling_ + 1 : 0;
    if (no_at_ceiling_ >= kNoAtCeiling) {
      finish(StaircaseEnd::no_at_ceiling);
      return;
    }
    yes_at_floor_ = yes && level_ <= kMinLevel_mA ? yes_at_floor_ + 1 : 0;
    if (yes_at_floor_ >= kYesAtFloor) {
      finish(StaircaseEnd::yes_at_floor);
      return;
    }
    int move = 0;
    if (yes) {
      if (++yes_run_ >= o_.down) move = -1;
    } else {
      move = +1;
    }
    if (move != 0) {
      yes_run_ = 0;
      if (direction_ != 0 && move != direction_) {
        trials_.back().reversal = true;
        reversal_levels_.push_back(level_);
        if (reversal_levels_.size() == 2) step_ = std::sqrt(o_.step_factor);
        if (static_cast<int>(reversal_levels_.size()) >= o_.reversals) {
          finish(StaircaseEnd::reversals);
          return;
        }
      }
      direction_ = move;
      level_ = move > 0 ? std::min(level_ * step_, o_.ceiling_mA)
                        : std::max(level_ / step_, kMinLevel_mA);
    }
  }
  if (static_cast<int>(trials_.size()) >= o_.max_trials) finish(StaircaseEnd::trials);
}

int typical_trials(const StaircaseOptions& o, double level_mA) {
  Staircase s(o);
  while (!s.done()) s.respond(s.level_mA() > level_mA);
  return static_cast<int>(s.trials().size());
}

void Staircase::finish(StaircaseEnd end) {
  done_ = true;
  end_ = end;
  if (end != StaircaseEnd::reversals) return;
  // The reversals at the smaller step: all but the first two.
  double log_sum = 0, sum = 0, sum_sq = 0;
  const std::size_t n = reversal_levels_.size() - 2;
  for (std::size_t k = 2; k < reversal_levels_.size(); ++k) {
    const double v = reversal_levels_[k];
    log_sum += std::log(v);
    sum += v;
    sum_sq += v * v;
  }
  const double nd = static_cast<double>(n);
  estimate_ = std::exp(log_sum / nd);
  spread_ = n > 1 ? std::sqrt(std::max(0.0, (sum_sq - sum * sum / nd) / (nd - 1))) : 0.0;
}

}  // namespace tp
