// The electrode-skin interface's circuit (skin_circuit.hpp).

#include "device/skin_circuit.hpp"

#include <cmath>
#include <limits>

namespace tp::device {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}

double interface_rp_kohm(const SkinInterface& s, double current_mA) {
  if (!(s.contact >= kLeastContact)) return kInfinity;
  const double rp = s.rp_kohm / s.contact;
  if (!(s.j_half_mA_mm2 > 0)) return rp;
  const double density = std::fabs(current_mA) / (s.contact * s.area_mm2);
  return rp / (1.0 + density / s.j_half_mA_mm2);
}

double interface_cp_nf(const SkinInterface& s) {
  return s.contact >= kLeastContact ? s.cp_nf * s.contact : 0.0;
}

double series_rs_kohm(const SkinInterface& s) {
  return s.contact >= kLeastContact ? s.rs_kohm / std::sqrt(s.contact) : kInfinity;
}

double phase_voltage_V(const SkinInterface& s, SkinState& state, double current_mA,
                       double duration_us) {
  if (!(s.contact >= kLeastContact)) {  // lifted: nothing flows, nothing is held
    state.vc_V = 0;
    return current_mA == 0 ? 0.0 : std::copysign(kInfinity, current_mA);
  }
  const double rp = interface_rp_kohm(s, current_mA);
  const double tau_us = rp * interface_cp_nf(s);  // = Rp(J) Cp: the contact cancels
  const double target_V = current_mA * rp;
  state.vc_V = target_V + (state.vc_V - target_V) * std::exp(-duration_us / tau_us);
  if (!std::isfinite(state.vc_V)) state.vc_V = 0;  // never carried on
  return current_mA * series_rs_kohm(s) + state.vc_V;
}

double pulse_peak_voltage_V(const SkinInterface& s, SkinState& state, const double* current_mA,
                            const double* duration_us, std::size_t phases, double* end_V) {
  double peak = 0;
  for (std::size_t k = 0; k < phases; ++k) {
    const double i = current_mA[k];
    // At the phase's first instant the interface still holds its charge; Rs takes the step.
    const double start = i == 0 ? state.vc_V : i * series_rs_kohm(s) + state.vc_V;
    const double end = phase_voltage_V(s, state, i, duration_us[k]);
    if (end_V) end_V[k] = end;
    peak = std::fmax(peak, std::fmax(std::fabs(start), std::fabs(end)));
  }
  return peak;
}

double rail_voltage_V(double v, double current_mA, double compliance_V) {
  if (std::fabs(v) <= compliance_V) return v;
  if (std::isfinite(v)) return std::copysign(compliance_V, v);
  return current_mA < 0 ? -compliance_V : compliance_V;
}

double measured_impedance_kohm(double voltage_V, double current_mA) {
  return current_mA == 0 ? 0.0 : std::fabs(voltage_V / current_mA);
}

}  // namespace tp::device
