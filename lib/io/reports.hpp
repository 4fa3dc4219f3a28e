#pragma once
// Output of the model: the AF on a grid (CSV) and the per-receptor summary (JSON).

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "io/csv.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "model/field.hpp"

namespace tp {

// Columns x_mm,y_mm,af_h,af_v: the AF of horizontal and vertical myelinated fibres of the
// reference diameter, one row per grid point, y outer, x inner.  Rejects y <= 0.  The rows
// go to `out` about 1 MB at a time (a program's tp::cli::write_stdout).
void validate_grid(const Axis& x, const Axis& y);
void write_af_grid(const ByteSink& out, const Field& field, const Axis& x, const Axis& y);

// Columns x_mm,z_mm,af_h,af_v: the AF over the plane at depth y_mm (3-D models), af_h of
// horizontal fibres along x, af_v of vertical ones, z outer, x inner.
void validate_plane(const Axis& x, const Axis& z, double y_mm);
void write_af_plane(const ByteSink& out, const Field& field, const Axis& x, const Axis& z,
                    double y_mm);

// Bad input when a grid of `points` over `pads` electrodes would take more than 6.4e9 pad
// evaluations (1e8 points of a 64-electrode array): hours of output.
void check_grid_work(double points, std::size_t pads);

// Default grid: the array +-5 mm at 0.1 mm, depths 0.2 to 3 mm at 0.05 mm; along z, the
// pads' centres +-5 mm at 0.1 mm.
Axis default_x_axis(const ElectrodeArray& a);
Axis default_y_axis();
Axis default_z_axis(const ElectrodeArray& a);

// {"af_unit", "currents_mA", "receptors": {NAME: {max_af, x_mm, y_mm, ...}}, "ratios": {...}}
Json summary_to_json(const Setup& setup, const std::vector<double>& currents_mA, const Summary& s);

}  // namespace tp
