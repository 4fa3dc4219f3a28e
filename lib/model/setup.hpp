#pragma once
// A model ready to evaluate (Setup: the array, the conductor and the receptor table) and the
// checks of a setup, of a grid or plane of it, and of where a receptor's fibres lie, made
// before any work.  The field over a setup is model/field.hpp.

#include <functional>
#include <string>
#include <vector>

#include "core/number.hpp"
#include "model/array.hpp"
#include "model/conductor.hpp"
#include "model/receptors.hpp"

namespace tp {

// A model ready to evaluate: array geometry, conductor and receptor table.
struct Setup {
  ElectrodeArray array = ElectrodeArray::paper();
  ConductorParams conductor;
  std::vector<Receptor> receptors = default_receptors();
  // Fibres run laterally over [first electrode - margin, last electrode + margin].
  double lateral_margin_mm = 5.0;
};

// Checks that the conductor model exists and is valid for the receptors (point3d: a buried
// source may come no nearer to any receptor's fibres than a surface source can, the
// smallest depth ranges::depth_mm.lo, 0.01 mm, so that the documented bound on the AF holds
// there).  Throws tp::Error (bad input) naming the field.
void validate_setup(const Setup& setup);
// The layered model stands for the finger only down to its skin's valid_to_mm: a deeper
// depth is bad input, "WHAT DEPTH mm is below the skin model's validity (...)".
void check_model_depth(const Setup& setup, double depth_mm, const std::string& what);

// Every check of a grid x by y (af-field's rows) before its first row is written, so that
// none is half-written and none holds a non-finite value.  Bad input, naming the point,
// when a point lies nearer than the smallest depth (ranges::depth_mm.lo, 0.01 mm) to a
// point source (point3d with a buried source), where the field is singular or beyond its
// documented bound; or when the conductor cannot evaluate a row that far from the
// electrodes (Conductor::check_reach: the layered model's Hankel rule).
void check_grid(const Setup& setup, const Conductor& conductor, const Axis& x, const Axis& y);

// The same for af-field's plane at depth y_mm, over x by z.
void check_plane(const Setup& setup, const Conductor& conductor, const Axis& x, const Axis& z,
                 double y_mm);

// The same for points anywhere (Python's af_points): `box` the ranges they fill (x, y, and
// z when given, else the fibres' plane), `each` calls back with every point (z: the
// plane's when the points have none).  The messages name "a point".
struct PointBox {
  double x0_mm, x1_mm, y0_mm, y1_mm, z0_mm, z1_mm;
  bool has_z;
};
using PointVisitor = std::function<void(double x_mm, double y_mm, double z_mm)>;
void check_points(const Setup& setup, const Conductor& conductor, const PointBox& box,
                  const std::function<void(const PointVisitor&)>& each);

// Where the fibres of one receptor lie: the rectangle [x0, x1] x [y0, y1] (y0 == y1 for a
// single depth line) in the plane z = plane_z_mm of a 1-D array; under a 2-D array the box
// [x0, x1] x [y0, y1] x [z0, z1]: horizontal fibres over the pads' centres plus the margin
// in x and z, vertical ones over the pads' area.
struct Region {
  double x0_mm, x1_mm, y0_mm, y1_mm;
  double z0_mm = 0.0, z1_mm = 0.0;
};
Region fibre_region(const Setup& setup, const Receptor& r);

// Bad input, before any work, when the conductor cannot evaluate some receptor's fibre
// region (Conductor::check_reach over the region's depths and its farthest point from an
// electrode): summarize() and the optimisation problem (make_mode_problem) call it.
void check_fibre_reach(const Setup& setup, const Conductor& conductor);

}  // namespace tp
