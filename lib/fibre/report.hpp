#pragma once
// Thresholds of every receptor for one weight pattern, their selectivity ratios, and the
// JSON they are reported in (docs/document-format.md, "Thresholds").

#include <optional>
#include <string>
#include <vector>

#include "fibre/threshold.hpp"
#include "core/json.hpp"
#include "model/field.hpp"
#include "pulse/stimulus.hpp"

namespace tp::fibre {

// The pulse a threshold is for (lib/pulse's shape, or monophasic).
struct PulseSpec {
  double width_us = 200.0;
  double interphase_us = 0.0;
  double balance_width_us = 200.0;
  bool monophasic = false;
  Waveform waveform(double delay_ms = 0.1) const {
    return pulse_waveform(width_us, interphase_us, balance_width_us, monophasic, delay_ms);
  }
  bool operator==(const PulseSpec& o) const;
  std::string describe() const;  // "200 us biphasic (200 us balance)"
};
// The pulse of a stimulus's shape (always biphasic: what is delivered is balanced).
PulseSpec pulse_of(const PulseShape& shape);

// Checks the pulse's ranges (bad input names the flag): widths 1 to 10000 us, gap 0 to
// 10000 us.
void check_pulse(const PulseSpec& p);

struct ThresholdReport {
  std::string model;         // fibre model
  double peak_weight = 1.0;  // max |w|: the stimulus's peak current is peak_weight x amplitude
  PulseSpec pulse;
  ThresholdSettings settings;
  double dt_ms = 0.0;
  std::vector<ReceptorThreshold> receptors;
  // threshold(M) / min over the other receptors' thresholds; empty where M has no
  // threshold or no other receptor has one.
  std::vector<std::optional<double>> ratios;
};

// The smallest time step a pulse gets: 5 us, or a tenth of its shortest phase (at least
// 0.1 us), used from that phase's start to 0.1 ms after its end (cable.hpp); gaps do not count.
double time_step_ms(const PulseSpec& p);

// The estimated work of compute_thresholds() (threshold_work() summed over the receptors),
// in compartment-steps; bad input when a receptor's fibre is (fibre_nodes()).
double thresholds_work(const Setup& setup, const FibreModel& model, const PulseSpec& pulse,
                       ThresholdSettings settings);

// Every receptor of the setup, for weights (|w| = 1 carries the amplitude).  Bad input,
// before any work, when a fibre is (fibre_nodes()) or the estimated work exceeds
// kMaxThresholdWork.
// cache (optional) keeps the unit potentials between calls with the same setup.
ThresholdReport compute_thresholds(const Setup& setup, const std::vector<double>& weights,
                                   const FibreModel& model, const PulseSpec& pulse,
                                   ThresholdSettings settings, PotentialCache* cache = nullptr);

// {"fibre_model", "pulse", "settings", "receptors": {NAME: {...}}} and the ratios.
Json thresholds_to_json(const Setup& setup, const ThresholdReport& r);
Json ratios_to_json(const Setup& setup, const ThresholdReport& r);

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

}  // namespace tp::fibre
