#pragma once
// The pulse a threshold is for, and the thresholds a weights document carries
// (fiber-threshold --stimulus, docs/document-format.md "Thresholds") read back against a
// stimulus: what make-pulse and stimctl print.  No model: a stimulator-only program uses it.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/json.hpp"
#include "pulse/stimulus.hpp"

namespace tp {

// The pulse a threshold is for (lib/pulse's shape, or monophasic, or phases).
struct PulseSpec {
  double width_us = 200.0;
  double interphase_us = 0.0;
  double balance_width_us = 200.0;
  bool monophasic = false;
  // A shaped pulse (pulse/shape.hpp): when not empty, the only thing that counts.
  std::vector<Phase> phases;
  // The phases simulated: `phases`, the monophasic main phase, or the shorthand's.
  std::vector<Phase> delivered() const;
  // The same phases (within 1e-9): a shorthand equals its phases.
  bool operator==(const PulseSpec& o) const;
  // "200 us biphasic, 800 us balance", "shaped: 500 us at 0.1, 200 us at 1, ..."
  std::string describe() const;
};
// The pulse of a stimulus's shape (its phases, or its biphasic shorthand).
PulseSpec pulse_of(const PulseShape& shape);

// Checks the pulse's ranges (bad input names the flag): widths 1 to 10000 us, gap 0 to
// 10000 us; phases by check_simulated_phases (--phases).
void check_pulse(const PulseSpec& p);

// A pulse as JSON: {"phases": [...]}, {"width_us", "monophasic": true} or the shorthand's
// widths; and back (bad input naming `where`).
Json pulse_spec_to_json(const PulseSpec& p);
PulseSpec pulse_spec_from_json(const Json& j, const std::string& where);

// Reads back the pulse and the per-receptor thresholds a document carries ("thresholds");
// empty when it carries none.  Bad input when they are malformed.
struct CarriedThresholds {
  PulseSpec pulse;
  double peak_weight = 1.0;
  std::string model;
  std::vector<std::pair<std::string, std::optional<double>>> threshold_mA;
};
std::optional<CarriedThresholds> carried_thresholds(const Json& document);
// "1.5 mA = 2.13 x SAI threshold, 0.71 x RA, 0.49 x PC": the amplitude over each threshold,
// smallest threshold first.
std::string threshold_multiples(const CarriedThresholds& t, double amplitude_mA);
// What make-pulse and stimctl print for a stimulus whose document carries thresholds: the
// multiples for the stimulus's peak current (peak_weight x the amplitude), or why there are
// none (thresholds for another pulse).  Empty when the document carries none; bad input when
// they are malformed.
std::optional<std::string> stimulus_against_thresholds(const Json& document, const PulseSpec& pulse,
                                                       double peak_current_mA);
// The same for a stimulus and the thresholds it carries.
std::optional<std::string> stimulus_against_thresholds(const Stimulus& s);

}  // namespace tp
