#pragma once
// The fibre factor lambda^2/tau = G/C_m of Eq. 14-16: the AF is this factor times the
// second derivative of the extracellular potential along the fibre.

namespace tp {

enum class Orientation { horizontal, vertical };

struct Fibre {
  Orientation orientation = Orientation::horizontal;
  double diameter_um = 10.0;
  bool myelinated = true;
};

// Fibre factor in mm^2/ms for a fibre of the reference diameter (constants.hpp).
//   myelinated:   G/C = d * L_int / (4 rho_i c_node l_node), with L_int = 100 d
//                 (axial conductance of one internode over one node's capacitance)
//   unmyelinated: G/C = d / (4 rho_i c_m)
double reference_fibre_factor_mm2_per_ms(bool myelinated);

// Fibre factor in mm^2/ms.  Sec. 4.1: it grows as diameter^2 for myelinated fibres
// (G ~ d^2, node capacitance fixed) and as diameter for unmyelinated ones (G ~ d^2,
// C_m ~ d), relative to the reference diameter.
double fibre_factor_mm2_per_ms(const Fibre& fibre);

}  // namespace tp
