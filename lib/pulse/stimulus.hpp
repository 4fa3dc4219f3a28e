#pragma once
// A stimulus: charge-balanced pulses on N channels, the paper's Fig. 11-12 design.
// One pulse shape is multiplied by each channel's current; a positive current is cathodic.
// The shape is the biphasic shorthand (a main phase, an optional gap, a balancing phase of
// opposite sign whose current is the main current times width / balance_width, so that it
// carries exactly the main phase's charge), or up to 16 phases (pulse/shape.hpp) whose
// levels sum to zero charge.

#include <optional>
#include <string>
#include <vector>

#include "device/protocol.hpp"
#include "core/json.hpp"
#include "pulse/shape.hpp"

namespace tp {

struct PulseShape {
  double width_us = 200.0;          // main phase (paper: 200 us)
  double interphase_us = 0.0;       // gap between the phases
  double balance_width_us = 200.0;  // balancing phase; longer and lower keeps the charge
  double frequency_hz = 200.0;      // pulse rate
  // A shaped pulse's phases (level x the channel's current); empty: the shorthand above,
  // whose widths are then the only ones that count.
  std::vector<Phase> phases;
  bool shaped() const { return !phases.empty(); }
  // The phases delivered: `phases`, or the shorthand's.
  std::vector<Phase> delivered() const;
  double period_us() const { return 1e6 / frequency_hz; }
  // The shorthand's |balance I| / |main I| (not for a shaped pulse).
  double balance_scale() const { return width_us / balance_width_us; }
  double length_us() const;
};

// Limits every stimulus is checked against before it is printed or sent.
struct StimulusLimits {
  double max_current_mA = 2.0;  // per electrode (paper, Sec. 6)
  double min_width_us = 10.0;
  double max_width_us = 1000.0;
  double max_balance_width_us = 8000.0;
  double max_frequency_hz = 1000.0;
  // The protocol's longest period is 10 s (docs/protocol.md): slower rates are refused
  // here, before anything reaches a device.
  double min_frequency_hz = 0.1;
  double max_duration_s = 3600.0;
  double sum_tolerance_mA = 1e-6;  // |Sum of channel currents| at any instant
  // Per electrode, over time (the device's bounds, docs/safety.md): the RMS current and the
  // mean absolute current (charge per second, both phases), summed over a mix's patterns.
  double max_rms_current_mA = device_bound_mA(device::hard::max_rms_uA);
  double max_mean_current_mA = device_bound_mA(device::hard::max_mean_uA);
  // A mix's scheduling (docs/protocol.md, "Scheduling"): the least gap between pulses of
  // different patterns and the longest a pulse may be deferred; a device may report
  // tighter ones.
  double min_gap_us = device::hard::min_gap_us;
  double max_slip_us = device::hard::max_slip_us;
  // Shannon's criterion for the charge per phase Q (uC) and its density D = Q / electrode
  // area (uC/cm2): log10 D + log10 Q <= k (R. V. Shannon, IEEE Trans. Biomed. Eng. 39(4):
  // 424-426, 1992: k = 1.85, the usual limit).
  double shannon_k = 1.85;
  static double device_bound_mA(std::uint16_t uA) { return uA * 1e-3; }
};

struct Stimulus {
  std::vector<double> currents_mA;  // main-phase current per channel, + = cathodic
  PulseShape shape;
  long count = 0;                   // number of pulses
  double electrode_area_mm2 = 5.0;  // for the charge density (paper: 0.5 x 10 mm)
  double max_current_mA = 2.0;      // the limit the stimulus was made for
  double amplitude_mA = 0.0;        // make-pulse's --amplitude (|weight| 1); 0: not known
  double phase_us = 0.0;            // in a mix: its first pulse after the start
  // Each channel's impedance (kOhm) when the person's threshold was measured (calibrate's
  // profile, through make-pulse --profile; 0: not known): stimctl --hold-sensation holds
  // the pulse's energy against it (docs/skin.md, "Sensation held").  Empty: none.
  std::vector<double> reference_impedance_kohm;
  Json carried = Json::object();    // e.g. mode, from the weights document
  double duration_s() const { return static_cast<double>(count) / shape.frequency_hz; }
};

// Throws tp::Error (bad input) naming the first violated limit.
void check_stimulus(const Stimulus& s, const StimulusLimits& limits);

// The figures a safety review asks for.
struct SafetyFigures {
  double peak_current_mA = 0;
  double max_charge_per_phase_nC = 0;
  double max_charge_density_uC_per_cm2 = 0;
  double max_rms_current_mA = 0;
  double max_net_charge_nC = 0;    // per pulse per channel, must be 0
  double max_instant_sum_mA = 0;   // |Sum over channels| at any instant
  double max_mean_current_mA = 0;  // the charge both phases carry per second
  double shannon_k = 0;            // log10 D + log10 Q of the largest charge per phase
  std::vector<double> charge_per_phase_nC;
  std::vector<double> rms_current_mA;
  std::vector<double> mean_current_mA;  // per channel
  double shortest_phase_us = 0;         // a shaped pulse's (gaps included)
  int level_unit = 0;                   // a shaped pulse's U (pulse/shape.hpp); 0: shorthand
};
SafetyFigures safety_figures(const Stimulus& s);

Json stimulus_to_json(const Stimulus& s);
Stimulus stimulus_from_json(const Json& j);  // checks structure; call check_stimulus after

// Corner points of the waveform, for plotting: t_us then one current per channel (mA).
std::vector<std::vector<double>> waveform_points(const Stimulus& s, long max_pulses);

}  // namespace tp
