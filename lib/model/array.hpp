#pragma once
// An electrode array on the skin surface (y = 0).
//
// A 1-D array: N parallel electrodes, each width_mm along x and length_mm along z, centred
// on z = 0 at x = positions_mm[i] (the paper's line electrodes).
// A 2-D array: N rectangular pads, each width_mm along x and length_mm along z, centred at
// (positions_mm[i], z_mm[i]); a grid (columns along x, rows along z, centred on (0, 0)) is
// indexed row-major, index = row x columns + column.  Only the 3-D conductor models
// (point3d, rect3d, layered) take a 2-D array.

#include <optional>
#include <string>
#include <vector>

namespace tp {

struct ElectrodeArray {
  std::vector<double> positions_mm;  // pad centres along x
  std::vector<double> z_mm;          // 2-D arrays: pad centres along z; empty for a 1-D array
  double width_mm = 0.5;             // extent along x (paper: 0.5 mm)
  double length_mm = 10.0;           // extent along z (paper: 10 mm)
  std::optional<double> pitch_mm;    // set when the array is uniform (a grid: along x)
  // A grid: columns along x at pitch_mm, rows along z at row_pitch_mm (0 when not a grid).
  int columns = 0, rows = 0;
  double row_pitch_mm = 0.0;

  std::size_t size() const { return positions_mm.size(); }
  bool two_d() const { return !z_mm.empty(); }
  bool grid() const { return columns > 0; }
  // "8 electrodes", "an 8 x 8 grid of pads", "12 pads".
  std::string describe() const;

  // N electrodes at a uniform pitch, centred on x = 0 (paper: 8 at 1 mm).
  static ElectrodeArray uniform(int count, double pitch_mm, double width_mm = 0.5,
                                double length_mm = 10.0);
  // The paper's array (Sec. 6): 8 electrodes, 1 mm pitch, 0.5 mm x 10 mm.
  static ElectrodeArray paper() { return uniform(8, 1.0); }
  // A columns x rows grid of width_mm x length_mm pads, centred on (0, 0).
  static ElectrodeArray grid_of(int columns, int rows, double pitch_mm, double row_pitch_mm,
                                double width_mm, double length_mm);
  // Free pads at (x_mm[i], z_mm[i]).
  static ElectrodeArray pads(std::vector<double> x_mm, std::vector<double> z_mm, double width_mm,
                             double length_mm);

  // Checks the geometry (ranges, at most ranges::max_electrodes, no two electrodes or pads
  // overlapping); throws tp::Error (bad input) naming the problem.
  void validate() const;

  double x_min_mm() const;
  double x_max_mm() const;
  // Pad centres along z: 0 for a 1-D array.
  double z_min_mm() const;
  double z_max_mm() const;
  double z_of(std::size_t i) const { return z_mm.empty() ? 0.0 : z_mm[i]; }
  // The electrode nearest the array's centre: (N - 1) / 2 of a 1-D array; of a 2-D array
  // the pad nearest the middle of the pads' extent, the lowest index of a tie.
  std::size_t centre_index() const;
};

}  // namespace tp
