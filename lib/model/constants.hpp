#pragma once
// Physical constants of the model, with their sources.
//
// The paper (Kajimoto et al., sections 3 and 4) works with proportionalities only; to
// give the activating function (AF) a unit we take standard values from the
// extracellular-stimulation literature.  Selectivity ratios (the quantity every mode is
// designed by) do not depend on any of these constants except through the *relative*
// fibre factors of the receptors, which follow the paper's scaling laws (Sec. 4.1).
//
// Units used throughout the library: x, y, lengths in mm; currents in mA; potentials in
// V; the AF in V/ms (= mV/us), i.e. the initial rate of change of membrane voltage.

namespace tp::constants {

// Extracellular (tissue) resistivity, ohm*m.  Rattay, "Analysis of models for external
// stimulation of axons", IEEE TBME 33 (1986): rho_e = 300 ohm*cm for homogeneous tissue.
inline constexpr double tissue_resistivity_ohm_m = 3.0;

// Axoplasm resistivity, ohm*m.  McNeal, "Analysis of a model for excitation of myelinated
// nerve", IEEE TBME 23 (1976): rho_i = 110 ohm*cm.
inline constexpr double axoplasm_resistivity_ohm_m = 1.1;

// Nodal membrane capacitance of myelinated fibres, F/m^2 (McNeal 1976: 2 uF/cm^2).
inline constexpr double node_capacitance_F_per_m2 = 0.02;

// Node of Ranvier gap length, m (McNeal 1976: 2.5 um), constant with diameter (Sec. 4.1).
inline constexpr double node_length_m = 2.5e-6;

// Internode length over fibre diameter (McNeal 1976: L = 100 d).
inline constexpr double internode_per_diameter = 100.0;

// Membrane capacitance of unmyelinated fibres, F/m^2 (1 uF/cm^2, Hodgkin-Huxley).
inline constexpr double membrane_capacitance_F_per_m2 = 0.01;

// Reference fibre diameter, um.  af_h/af_v in af-field's CSV are for a myelinated fibre of
// this diameter (the SAI/PC afferents of Table 1).
inline constexpr double reference_diameter_um = 10.0;

}  // namespace tp::constants
