#pragma once
// A mix: several stimuli (patterns) on the same electrodes, interleaved by the device, each
// with its own weights, pulse shape, rate, amplitude and phase (docs/document-format.md,
// "Mixed stimuli").  A stimulus document of one pattern is a mix of one.  Checked as a
// whole: every pattern as a stimulus, and across patterns what the device checks too
// (docs/safety.md): each electrode's RMS and mean current summed over the patterns, the
// share of time the pulses and gaps take, and how long a pulse may be deferred.

#include <vector>

#include "device/protocol.hpp"
#include "core/json.hpp"
#include "pulse/stimulus.hpp"

namespace tp {

struct Mix {
  std::vector<Stimulus> patterns;            // each its own shape, count, phase_us and amplitude_mA
  double gap_us = device::hard::min_gap_us;  // between pulses of different patterns
  // Each pattern's amplitude at the start (mA, 0 to its amplitude), set before the output
  // starts; empty: each as configured.  A live sequence starts from its first frame.
  std::vector<double> start_amplitudes_mA;
  bool single() const { return patterns.size() == 1; }
  // Goes to a device as a table of patterns (protocol 4): several, or one with a phase or
  // starting amplitudes.
  bool table() const {
    return !single() || patterns[0].phase_us != 0 || !start_amplitudes_mA.empty();
  }
  double duration_s() const;  // the longest pattern's
};

// A pattern's timing as the device takes it: whole microseconds (the period rounded from
// the rate); bad input naming the value when a width or phase is not whole.  A shaped
// pulse's timing has no widths and its phases in integer units (device_shape).
device::PatternTiming pattern_timing(const Stimulus& s, long count);
// A shaped pulse's phases as the device takes them (set_shape): whole microseconds and
// the levels in units of 1/U (shape_units); bad input when they do not fit the protocol.
device::Shape device_shape(const std::vector<Phase>& phases);

struct MixFigures {
  std::vector<double> rms_current_mA;   // per electrode, summed over the patterns
  std::vector<double> mean_current_mA;  // per electrode: the charge both phases carry per s
  double utilisation = 0;               // sum over patterns of (pulse + gap) / period
  double worst_slip_us = 0;             // the scheduler's bound (device::Scheduler)
};
// Throws tp::Error (bad input) when the patterns cannot be timed (see pattern_timing).
// The worst slip is exact up to max_slip_us (the scheduler's exact schedule is tried only
// when its closed bound is above that); beyond, HUGE_VAL when unbounded or too long to check.
MixFigures mix_figures(const Mix& m, double max_slip_us = device::hard::max_slip_us);

// Every pattern by check_stimulus, then the mix: one channel count, at most kMaxPatterns,
// the gap, the summed loads, the utilisation and the slip.  Throws tp::Error (bad input)
// naming the first violated limit.
void check_mix(const Mix& m, const StimulusLimits& limits);

// "tactile-primaries/stimulus/1" (one pattern) or "/2" (patterns); read checks structure.
Mix mix_from_json(const Json& j);
Json mix_to_json(const Mix& m);

// A pattern's amplitude: the current of its weight-1 electrode (amplitude_mA), or its
// largest current when it has none.
double pattern_amplitude_mA(const Stimulus& s);

// Amplitudes in mA, one per pattern, each 0 to its pattern's amplitude: the device's
// scales (device::kFullScale = the pattern as configured), rounded down.  Bad input naming
// `where`.
std::vector<std::uint16_t> amplitude_scales(const std::vector<double>& amplitudes_mA,
                                            const Mix& m, const std::string& where);

// An amplitude frame {"amplitudes": [a1, ...]} (no other key): amplitude_scales.
std::vector<std::uint16_t> parse_amplitudes(const Json& frame, const Mix& m,
                                            const std::string& where);

}  // namespace tp
