#pragma once
// An array of N parallel line electrodes on the skin surface (y = 0), lying along z.

#include <optional>
#include <vector>

namespace tp {

struct ElectrodeArray {
  std::vector<double> positions_mm;  // electrode centres along x
  double width_mm = 0.5;             // extent along x (paper: 0.5 mm)
  double length_mm = 10.0;           // extent along z (paper: 10 mm)
  std::optional<double> pitch_mm;    // set when the array is uniform

  std::size_t size() const { return positions_mm.size(); }

  // N electrodes at a uniform pitch, centred on x = 0 (paper: 8 at 1 mm).
  static ElectrodeArray uniform(int count, double pitch_mm, double width_mm = 0.5,
                                double length_mm = 10.0);
  // The paper's array (Sec. 6): 8 electrodes, 1 mm pitch, 0.5 mm x 10 mm.
  static ElectrodeArray paper() { return uniform(8, 1.0); }

  // Checks the geometry; throws tp::Error (bad input) naming the problem.
  void validate() const;

  double x_min_mm() const;
  double x_max_mm() const;
};

}  // namespace tp
