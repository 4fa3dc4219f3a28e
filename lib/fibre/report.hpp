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
#include "pulse/thresholds.hpp"

namespace tp::fibre {

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

// The waveform of a pulse: its phases (pulse_waveform() for the shorthand).
Waveform waveform_of(const PulseSpec& p, double delay_ms = 0.1);

}  // namespace tp::fibre
