#pragma once
// Volume-conductor models: the extracellular potential Psi set up by the electrode currents.
//
// A conductor gives, for a unit (1 mA, cathodic) current on each electrode, the second
// derivatives of Psi at a point.  Psi is linear in the currents, so the field of any current
// pattern is the weighted sum (Eq. 25); the optimiser uses the per-electrode responses
// directly.  New models (3-D electrodes, layered skin) implement this interface and are
// registered in make_conductor().

#include <memory>
#include <string>
#include <vector>

#include "model/array.hpp"

namespace tp {

struct ConductorParams {
  std::string model = "line2d";    // "line2d" (the paper's) or "strip2d"
  double resistivity_ohm_m = 0.0;  // 0: constants::tissue_resistivity_ohm_m
};

class Conductor {
 public:
  virtual ~Conductor() = default;
  virtual const char* name() const = 0;
  virtual std::size_t size() const = 0;  // number of electrodes

  // For 1 mA cathodic on electrode i alone: d2Psi/dx2 into xx[i] and d2Psi/dy2 into yy[i],
  // in V/mm^2, at (x_mm, y_mm) with y_mm > 0.  Either pointer may be null.
  virtual void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const = 0;

  // Psi (V) at (x_mm, y_mm) for 1 mA cathodic on each electrode alone, up to a constant
  // (the 2-D models have no zero at infinity).  Used to check the derivatives.
  virtual void unit_potentials(double x_mm, double y_mm, double* psi) const = 0;

  // True when Psi is harmonic in the (x, y) plane, so that the AF of either orientation
  // is harmonic too (Eq. 28-30) and obeys the maximum principle.
  virtual bool planar_harmonic() const = 0;
};

std::unique_ptr<Conductor> make_conductor(const ConductorParams& params,
                                          const ElectrodeArray& array);

const std::vector<std::string>& conductor_models();

}  // namespace tp
