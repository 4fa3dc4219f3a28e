#pragma once
// The documented range of every physical parameter (docs/document-format.md, "Ranges").
// Each is wide enough for any fingertip or forearm array and any tissue, and narrow enough
// that every result the models compute is finite and every sample count bounded: with
// depths >= 0.01 mm, resistivity <= 1e7 ohm m, currents <= 100 mA and diameters <= 30 um,
// the largest AF is ~1e22 V/ms, far from overflow.  A value outside is bad input (exit 2),
// named with its range.

#include <string>

namespace tp::ranges {

struct Range {
  double lo, hi;
  const char* unit;
};

// Depth of a receptor's fibres and of af-field's grid rows: from a hundredth of a
// millimetre (inside the epidermis) to 20 mm (well below any fingertip afferent).
inline constexpr Range depth_mm{0.01, 20.0, "mm"};
// Positions along the skin (electrode centres, af-field's grid columns).
inline constexpr Range position_mm{-500.0, 500.0, "mm"};
// Electrode pitch, width (0: the paper's line electrode) and length.
inline constexpr Range pitch_mm{0.01, 100.0, "mm"};
inline constexpr Range width_mm{0.0, 100.0, "mm"};
inline constexpr Range length_mm{0.01, 1000.0, "mm"};
// Tissue resistivity: from saline-soaked tissue (~0.01 ohm m) to dry stratum corneum
// (~1e5 to 1e6 ohm m), with a decade to spare.
inline constexpr Range resistivity_ohm_m{0.01, 1e7, "ohm m"};
// Fibre diameter: the thinnest myelinated afferents (~1 um, A-delta) down to 0.1 um for
// C fibres, up to 30 um (beyond the largest A-beta, ~20 um).
inline constexpr Range diameter_um{0.1, 30.0, "um"};
// 3-D models: the plane of the fibres along the electrodes' length (z = 0 is their middle),
// and point3d's source depth (0: on the surface; buried sources for fibre benchmarks).
inline constexpr Range plane_z_mm{-500.0, 500.0, "mm"};
inline constexpr Range source_depth_mm{0.0, 20.0, "mm"};
// A horizontal fibre's direction in the skin plane under a 2-D array (0: along x).
inline constexpr Range azimuth_deg{-180.0, 180.0, "deg"};
// How far the fibres run beyond the outer electrodes.
inline constexpr Range lateral_margin_mm{0.0, 50.0, "mm"};
// The design document's current limit per electrode (the paper's 2 mA; the stimulus
// limits of lib/pulse cap what is ever delivered).
inline constexpr Range max_current_mA{0.001, 2.0, "mA"};
// stimctl --check-impedance's probe current on each electrode: below the fibre model's
// lowest thresholds at 200 us (0.26 mA; docs/skin.md, "Before and during a session").
inline constexpr Range probe_mA{0.01, 0.5, "mA"};
// An electrode-skin impedance (a stimulus's reference, a profile's): from a wet pad's tens of
// ohms to a dry fingertip's megohms (docs/skin.md).
inline constexpr Range impedance_kohm{0.01, 100000.0, "kOhm"};
// af-field's --amplitude: the current of a unit weight, for field maps (not delivered).
inline constexpr Range amplitude_mA{1e-6, 100.0, "mA"};
// A weight, before it is multiplied by the amplitude.
inline constexpr Range weight{-1000.0, 1000.0, ""};
// Pads of a 2-D array, for design: the field, the optimiser, a bank of pixels.
inline constexpr int max_electrodes = 256;
// Electrodes of a 1-D array (the unconstrained optimiser's work grows fast with them).
inline constexpr int max_line_electrodes = 64;
// Channels a stimulus may drive: what a device can (a set_weights frame carries 64
// channels); make-pulse and stimctl refuse a document with more pads than this.
inline constexpr int max_channels = 64;
// A 2-D grid's columns and rows (columns x rows is at most max_electrodes).
inline constexpr int max_grid_side = 256;
// af-field's grid: at most this many rows.
inline constexpr double max_grid_points = 1e8;

// Throws tp::Error (bad input): "WHAT: VALUE UNIT outside [LO, HI] UNIT".
void check(double value, const Range& r, const std::string& what);

}  // namespace tp::ranges
