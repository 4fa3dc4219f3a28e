#pragma once
// Membrane kinetics of a node of Ranvier: the ionic current and how its gates move.
// Two implementations: MRG's mammalian node (McIntyre, Richardson & Grill 2002; the
// AXNODE mechanism of ModelDB 3810) and the Frankenhaeuser-Huxley node of McNeal's and
// Reilly's SENN model.  Equations and parameters with their sources: docs/fibres.md.
//
// Units: membrane potential v in mV (inside minus outside), time in ms, current density
// in mA/cm^2, conductance density in S/cm^2.

#include <cstddef>
#include <memory>

namespace tp::fibre {

inline constexpr std::size_t kMaxGates = 4;

class NodeKinetics {
 public:
  virtual ~NodeKinetics() = default;
  virtual const char* name() const = 0;
  virtual std::size_t gate_count() const = 0;
  // The resting potential the model starts from (mV).
  virtual double rest_mV() const = 0;
  // The gates' steady state at v.
  virtual void steady_state(double v_mV, double* gates) const = 0;
  // Ionic current density at v with the gates fixed, and its derivative in v.
  virtual double current(double v_mV, const double* gates, double* di_dv) const = 0;
  // Advances the gates over dt at a fixed v: exponential Euler (NEURON's cnexp), exact for
  // a constant v, stable for any dt.
  virtual void advance(double v_mV, double dt_ms, double* gates) const = 0;
};

// MRG's node at celsius (the published model runs at 37 C; the Q10s are AXNODE's).
std::unique_ptr<NodeKinetics> make_mrg_node(double celsius = 37.0);
// Frankenhaeuser-Huxley (1964) as in McNeal (1976) and Reilly's SENN: GHK currents of Na,
// K and the non-specific P current, and a leak; rates at 20 C scaled by
// 3^((rate_celsius-20)/10)
// (fh.mod of ModelDB 239006).  Potentials absolute (mV); the rate functions take v + 70.
struct FhParams {
  double celsius = 20.0;       // the GHK factor F/RT
  double rate_celsius = 20.0;  // the rates' Q10 scaling (20: FH's own rates)
  double p_na_cm_s = 8e-3, p_k_cm_s = 1.2e-3, p_p_cm_s = 0.54e-3;
  double g_l_S_cm2 = 30.3e-3, e_l_mV = -69.74;
  double na_i_mM = 13.74, na_o_mM = 114.5, k_i_mM = 120.0, k_o_mM = 2.5;
  double rest_mV = -70.0;
};
std::unique_ptr<NodeKinetics> make_fh_node(const FhParams& params);

}  // namespace tp::fibre
