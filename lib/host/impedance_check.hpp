#pragma once
// stimctl --check-impedance (issue 41, item 5; docs/skin.md, "Before a session"): before a
// stimulus starts, a short probe well below sensation drives every electrode the stimulus
// uses, on a device that measures (protocol 7).  Its readings give each pad's impedance and
// contact, and the voltage each pad would need at the stimulus's own peak current (the
// probe's voltage scaled by the currents: exact for a linear interface, and an
// overestimate where the interface's resistance falls with current).  A used pad without
// contact, or a peak needing more than the device's compliance, refuses the stimulus
// before any of it is sent.

#include <string>
#include <vector>

#include "host/session.hpp"
#include "pulse/mix.hpp"

namespace tp::host {

// The probe's current on each electrode, mA: 0.01 to 0.5 [0.05] (under a fifth of the
// fibre model's lowest threshold at 200 us: docs/skin.md).
inline constexpr double kDefaultProbe_mA = 0.05;

struct ImpedanceRow {
  std::size_t channel = 0;
  double probe_mA = 0;        // its current in the probe (signed, + cathodic)
  bool contact = false;       // current flowed and no guard tripped on it
  double impedance_kohm = 0;  // inf: no current flowed
  double voltage_V = 0;       // at the probe's main phase's end
  double peak_mA = 0;         // the stimulus's largest |current| on it
  double needed_V = 0;        // its voltage at that peak: |V| x peak / |probe|
};

struct ImpedanceCheck {
  std::vector<ImpedanceRow> rows;  // the electrodes the stimulus uses, by channel
  double compliance_V = 0;
  double probe_mA = 0;  // the probe's current (the largest on any pad)
  std::string port;
  // Empty: the stimulus may start.  Else the one line that refuses it.
  std::string refusal;
};

// The probe for a mix: its used channels (a current in any pattern), alternately cathodic
// and anodic at probe_mA (the cathodes, one more when the count is odd, share the anodes'
// current: they sum to zero and none carries more than probe_mA), five symmetric biphasic
// pulses at 50 Hz as wide as the longest main phase of any pattern (a shaped pulse's
// longest run of one sign; at most 1000 us), on the smallest electrode area.  Bad input when the probe is outside 0.01 to 0.5 mA.
Stimulus probe_stimulus(const Mix& m, double probe_mA);

// Runs the probe (a session of its own, opt's stop and limits) and judges its readings.
// Bad input when the device does not measure.
ImpedanceCheck check_impedance(Transport& transport, const Mix& m, const SessionOptions& opt,
                               double probe_mA);

// The table stimctl prints (stderr) when the check passes: a header, then "channel,
// impedance, voltage at the probe, contact, needed at the peak" per used electrode.  (A
// refusal is one line, as all bad input.)
std::string impedance_table(const ImpedanceCheck& c);

}  // namespace tp::host
