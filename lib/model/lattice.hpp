#pragma once
// A uniform grid's plane of fibres sampled on a lattice its pads' centres lie on.
//
// A grid's pads are translates of one pad, and the conductors that take a 2-D array are
// laterally uniform: pad (c, r)'s response at (x, y, z) is the lone pad's at (x - x_c, y,
// z - z_r).  On the lattice x = x_00 + a hx, z = z_00 + b hz with pitch = m hx and row
// pitch = mz hz, every point-pad pair is one of few offsets ((a - c m) hx, (b - r mz) hz):
// the lone pad's response is tabulated once per plane (PadTable) and looked up, instead of
// evaluating every pad at every point.  The field searches (Field::plane_af) and the focus
// problem's samples (opt/focus_samples.cpp) use it.

#include <memory>
#include <optional>
#include <vector>

#include "model/conductor.hpp"

namespace tp {

// The lattice points within [x0, x1] x [z0, z1]: a in [a0, a1], b in [b0, b1]; the
// region's edges that fall between lattice points are flagged (the caller samples them
// apart).
struct GridLattice {
  int m = 1, mz = 1;  // lattice steps per pitch, per row pitch
  double hx = 0.0, hz = 0.0, x00 = 0.0, z00 = 0.0;
  int a0 = 0, a1 = 0, b0 = 0, b1 = 0;
  bool x0_off = false, x1_off = false, z0_off = false, z1_off = false;
  double x(int a) const { return x00 + a * hx; }
  double z(int b) const { return z00 + b * hz; }
  // The lattice's lines within [x0, x1] (or [z0, z1]), with the region's edges that fall
  // between them: increasing.
  std::vector<double> x_axis(double x0_mm, double x1_mm) const;
  std::vector<double> z_axis(double z0_mm, double z1_mm) const;
};

// The lattice at a step of at most step_mm, or none when the array is not a grid or the
// table would hold more entries than the points x pads (a coarse grid under shallow
// fibres: then every pad is evaluated at every point).
std::optional<GridLattice> grid_lattice(const ElectrodeArray& a, double x0_mm, double x1_mm,
                                        double z0_mm, double z1_mm, double step_mm);

// The lone pad's second derivative of Psi along a fibre axis (V/mm^2 per mA) at every
// offset a point of the lattice has from a pad, in the plane y_mm.
struct PadTable {
  int oa = 0, ob = 0, na = 0, nb = 0;  // the first offsets, the table's width and height
  std::vector<double> k;
  double at(int a, int b) const {
    return k[static_cast<std::size_t>(b - ob) * static_cast<std::size_t>(na) +
             static_cast<std::size_t>(a - oa)];
  }
  // The responses of every pad (row-major, as the array's index) at lattice point (a, b).
  void pads_at(const ElectrodeArray& arr, const GridLattice& g, int a, int b, double* out) const {
    for (int r = 0; r < arr.rows; ++r)
      for (int c = 0; c < arr.columns; ++c)
        out[r * arr.columns + c] = at(a - c * g.m, b - r * g.mz);
  }
};
// The lone pad's response on a wall of a fibre box: the plane z = fixed (along x) or
// x = fixed (along z), at the lattice's lines across the wall and at depths ys.  Pad (c, r)
// sees a point at lattice index i along the wall at the offset (i - c m) hx along x (or
// (i - r mz) hz along z) and fixed - z_r (or fixed - x_c) across: one line per pad row
// (or column).
struct WallTable {
  bool along_x = true;
  int o = 0, n = 0, lines = 0;  // the first offset along the wall, how many; pad rows or columns
  std::vector<double> k;        // [(iy * lines + line) * n + offset - o]
  // The responses of every pad (row-major, as the array's index) at lattice index i along
  // the wall, at depth ys[iy].
  void pads_at(const ElectrodeArray& arr, const GridLattice& g, int i, std::size_t iy,
               double* out) const {
    const auto at = [&](int line, int offset) {
      return k[(iy * static_cast<std::size_t>(lines) + static_cast<std::size_t>(line)) *
                   static_cast<std::size_t>(n) +
               static_cast<std::size_t>(offset - o)];
    };
    for (int r = 0; r < arr.rows; ++r)
      for (int c = 0; c < arr.columns; ++c)
        out[r * arr.columns + c] = along_x ? at(r, i - c * g.m) : at(c, i - r * g.mz);
  }
};

// Tables are kept for the process (the last ones built, up to 2e7 entries of each kind,
// plane and wall: 320 MB at most),
// shared between threads: a pixel's rounds and a bank's patterns evaluate the same planes
// over and over.  A table depends only on its arguments, so keeping it changes no value.
std::shared_ptr<const PadTable> pad_table(const ConductorParams& params, const ElectrodeArray& arr,
                                          const GridLattice& g, double y_mm, const FibreAxis& axis);
// A wall's table (kept as the plane tables are), or none when it would hold more than
// kMaxSamples entries.
std::shared_ptr<const WallTable> wall_table(const ConductorParams& params,
                                            const ElectrodeArray& arr, const GridLattice& g,
                                            bool along_x, double fixed_mm,
                                            const std::vector<double>& ys, const FibreAxis& axis);

}  // namespace tp
