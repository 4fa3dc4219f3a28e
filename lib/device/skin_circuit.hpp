#pragma once
// The electrode-skin interface of one pad (issue 41; docs/skin.md, "The electrode-skin
// interface"): a series resistance Rs (the spreading resistance into the tissue beneath,
// and the electrode's own) and the skin's interface, a resistance Rp in parallel with a
// capacitance Cp.  Rp falls with the current density through the touching area; a contact
// fraction c in [0, 1] scales the interface with that area (Rp / c, Cp x c) and the
// spreading resistance as a disc's, with the square root of the area (Rs / sqrt(c)).
//
// Each phase of a pulse is a constant current, so within it Rp is constant and the
// interface's voltage moves exponentially towards I Rp with the time constant Rp Cp:
//     Vc(t) = I Rp + (Vc(0) - I Rp) exp(-t / (Rp Cp)),   V(t) = I Rs + Vc(t),
// exact for any piecewise-constant pulse (the interface carries its charge from phase to
// phase, and between pulses discharges through Rp at zero current).  Units: kOhm x mA = V,
// kOhm x nF = us.  Positive current cathodic, as everywhere; the voltage has its sign.
//
// Portable (no heap, no exceptions, no I/O): the library, the emulator and the firmware's
// simulated board share it.

#include <cstddef>

namespace tp::device {

// One pad's interface at full contact.  Ranges (docs/skin.md): rs 0.01 to 1000 kOhm, rp
// 0.1 to 10000 kOhm, cp 0.01 to 10000 nF, j_half 0 (no fall) or 0.001 to 1000 mA/mm^2,
// area 0.01 to 10000 mm^2, contact 0 to 1.
struct SkinInterface {
  double rs_kohm = 1.0;     // series: spreading and electrode
  double rp_kohm = 50.0;    // the interface's resistance at low current density
  double cp_nf = 30.0;      // the interface's capacitance
  double j_half_mA_mm2 = 0; // the current density at which Rp halves (0: Rp is constant)
  double area_mm2 = 1.0;    // the pad's area
  double contact = 1.0;     // the fraction of the pad touching the skin
};

// A contact below this is none: the pad is lifted (a touching area of a millionth of the
// pad would put the interface's values beyond a double's range).
inline constexpr double kLeastContact = 1e-6;

// The interface's resistance at a current (either sign) through the touching area:
// Rp / c / (1 + |I| / (c A j_half)).  Infinite without contact.
double interface_rp_kohm(const SkinInterface& s, double current_mA);
double interface_cp_nf(const SkinInterface& s);     // Cp x c
double series_rs_kohm(const SkinInterface& s);      // Rs / sqrt(c); infinite without contact

// The interface's charge state, carried from phase to phase and pulse to pulse.
struct SkinState {
  double vc_V = 0;  // the voltage across Rp || Cp
};

// One phase of constant current: the state moved on by duration_us, and the pad's voltage
// at the phase's end (I Rs + Vc).  Without contact (below kLeastContact) any current needs
// an infinite voltage of its sign (returned as such); zero current leaves Vc to discharge
// through Rp at low density.
double phase_voltage_V(const SkinInterface& s, SkinState& state, double current_mA,
                       double duration_us);

// A whole pulse, phase by phase (currents in mA, cathodic positive, and durations in us; the
// device's phases, or a biphasic pulse's main phase, interphase and balance): each phase's
// end voltage into end_V[k] (may be null), the state carried on.  Returns the largest |V|
// anywhere in the pulse, which a current source must reach to deliver it as asked (within a
// phase |V| is monotone, so it is at a phase's start or end).
double pulse_peak_voltage_V(const SkinInterface& s, SkinState& state, const double* current_mA,
                            const double* duration_us, std::size_t phases, double* end_V);

// What a current source with a compliance of compliance_V makes of a needed voltage v at a
// current i: v itself when within the compliance, else the rail of v's sign (of i's when v
// is not finite: a lifted pad).
double rail_voltage_V(double v, double current_mA, double compliance_V);

// The pad's impedance as a device derives it at a phase's end: |V / I| (kOhm); 0 for no
// current.
double measured_impedance_kohm(double voltage_V, double current_mA);

}  // namespace tp::device
