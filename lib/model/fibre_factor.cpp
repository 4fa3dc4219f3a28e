#include "model/fibre_factor.hpp"

#include "model/constants.hpp"

namespace tp {

double reference_fibre_factor_mm2_per_ms(bool myelinated) {
  using namespace constants;
  const double d_m = reference_diameter_um * 1e-6;
  double m2_per_s = 0.0;
  if (myelinated) {
    m2_per_s = d_m * (internode_per_diameter * d_m) /
               (4.0 * axoplasm_resistivity_ohm_m * node_capacitance_F_per_m2 * node_length_m);
  } else {
    m2_per_s = d_m / (4.0 * axoplasm_resistivity_ohm_m * membrane_capacitance_F_per_m2);
  }
  return m2_per_s * 1e6 / 1e3;  // m^2/s -> mm^2/ms
}

double fibre_factor_mm2_per_ms(const Fibre& fibre) {
  const double n = fibre.diameter_um / constants::reference_diameter_um;
  const double scale = fibre.myelinated ? n * n : n;
  return reference_fibre_factor_mm2_per_ms(fibre.myelinated) * scale;
}

}  // namespace tp
