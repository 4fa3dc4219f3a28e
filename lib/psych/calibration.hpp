#pragma once
// Calibration (issue 23; docs/calibration.md): for the person wearing the array, each
// primary's detection threshold and comfort limit, at one pixel (the array's centre by
// default) or at every pixel, each by the adaptive procedure of psych/staircase.hpp.
//
// For each pixel, for each primary in turn: the detection threshold ("did you feel it?",
// `threshold`'s rule, 2-down-1-up by default: the 70.7 % point), then, from that
// threshold, the comfort limit ("is it too strong?", 1-down-1-up: the level called too
// strong half the time).  A threshold not found leaves the primary out, and `notes` says
// what ended its staircase (StaircaseEnd).  A comfort limit never reached (never too
// strong up to the ceiling) is the ceiling; one whose staircase ended otherwise unfound
// (too strong at the floor, out of trials) leaves the primary out; one found below its
// threshold is the threshold.  No trial is ever above the ceiling, none steps up by more
// than max_step_up.
//
// The class only decides: a program delivers each trial's stimulus and asks the question.

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/bank.hpp"
#include "psych/profile.hpp"
#include "psych/staircase.hpp"
#include "pulse/mix.hpp"

namespace tp {

struct CalibrationOptions {
  StaircaseOptions staircase;                            // the threshold's; comfort: 1-down
  std::array<double, 3> rate_hz = {30.0, 200.0, 250.0};  // each primary's trials
  double trial_s = 0.5;                                  // a trial's stimulus, 0.05 to 10 s
  double width_us = 200.0, balance_width_us = 200.0;
  std::vector<int> primaries;  // kPrimaries' indices, in order; empty: every one
  std::vector<long> pads;      // the pixels measured, in order
};
// Bad input naming the first option out of range (docs/calibration.md).
void check_calibration_options(const CalibrationOptions& o, const PixelBank& bank);

struct CalibrationTrial {
  int n = 0;  // 1, 2, ... over the whole calibration
  int primary = 0;
  long pad = 0;
  bool comfort = false;  // the question: too strong? (else: felt?)
  double level_mA = 0;
  bool ascending = true, yes = false, reversal = false;
};

// The trial log (calibrate --log, CSV): its header, and one trial's row with the pulses
// the device delivered and their peak current.
std::string calibration_log_header();
std::string calibration_log_row(const CalibrationTrial& t, int columns, std::uint32_t pulses,
                                double peak_mA);

// How long a session is, from the procedure itself: `typical` trials against observers
// whose threshold lies halfway (in log level) from the start to the ceiling and whose
// comfort limit halfway from there to the ceiling (psych/staircase.hpp, typical_trials);
// `most` is every staircase at its max_trials.
struct CalibrationLength {
  int staircases = 0, typical = 0, most = 0;
};

class Calibration {
 public:
  Calibration(const PixelBank& bank, const CalibrationOptions& o);  // checks o
  bool done() const { return unit_ >= units_.size(); }
  // The next trial (while !done()).
  int primary() const { return units_[unit_].primary; }
  long pad() const { return units_[unit_].pad; }
  bool comfort() const { return comfort_; }
  double level_mA() const { return stair_.level_mA(); }
  // Its stimulus: the pixel's pattern of that primary at the level, at the primary's rate,
  // for trial_s; checked as any stimulus is.
  Mix stimulus() const;
  void respond(bool yes);
  // A device that measures: each pad's impedance (kOhm, 0: none) at the trial about to be
  // answered; the threshold's trials' mean goes into the range (PrimaryRange::impedance_kohm).
  void measured(const std::vector<double>& impedance_kohm);
  const std::vector<CalibrationTrial>& trials() const { return trials_; }
  // After done(): the profile (tactile-primaries/profile/1): per pixel when several were
  // measured (the primaries' ranges then their medians), with the array's size.
  Profile profile() const;
  const std::vector<std::string>& notes() const { return notes_; }

  // Every trial the session could deliver, checked by `check` before the first is sent:
  // each unit's stimulus at the ceiling (every limit grows with the level).  `check`
  // throws bad input for a stimulus the device cannot deliver (host::plan_session against
  // its capabilities).  A unit refused there is bad input naming the ceiling, the unit,
  // the reason, and the highest ceiling that `check` passes, or that no level does.
  void check_trials(const std::function<void(const Mix&)>& check) const;

  // What the person is told: the session's length up front ("3 primaries at 1 pixel: 6
  // staircases, about 105 trials of 0.5 s, at most 480"); when the next trial starts a
  // staircase, which (the primary, k of n; the pixel, k of n; the question), else empty;
  // after done(), one line of what was found (each primary's threshold and comfort limit,
  // or not found).
  CalibrationLength length() const;
  std::string length_text() const;
  std::string stage_text() const;
  std::string summary() const;

 private:
  struct Unit {
    long pad;
    int primary;
    bool found = false;
    PrimaryRange range;
  };
  void start_threshold();
  void finish_threshold();
  void finish_comfort();
  void finish_unit();
  std::string where(const Unit& u) const;                       // "SAI at pixel (3, 2)"
  std::string end_text() const;                                 // what ended stair_, unfound
  Mix trial_stimulus(std::size_t unit, double level_mA) const;  // checked
  const PixelBank& bank_;
  CalibrationOptions o_;
  std::vector<int> primaries_;  // in order
  std::vector<Unit> units_;
  std::size_t unit_ = 0;
  bool comfort_ = false;
  Staircase stair_;
  int unit_trials_ = 0;
  std::vector<double> z_sum_;  // the threshold's trials' impedances, summed per pad
  std::vector<int> z_count_;
  std::vector<CalibrationTrial> trials_;
  std::vector<std::string> notes_;
};

}  // namespace tp
