#pragma once
// The bank render-tactile and calibrate read (optimize-weights --bank without --at): every
// pad's pixel, and per primary its pattern (weights and peak) or why the optimiser found
// none.

#include <array>
#include <string>
#include <vector>

#include "io/document.hpp"

namespace tp {

// One (pixel, primary) of a bank.
struct BankEntry {
  bool present = false;  // the bank has this primary's mode
  bool feasible = false;
  std::string reason;           // why not feasible
  std::vector<double> weights;  // one per pad, max |w| = 1
  double peak_x_mm = 0, peak_y_mm = 0, peak_z_mm = 0;
};

// A bank of every pad's pixel on a grid (optimize-weights --bank without --at).
struct PixelBank {
  Document doc;  // the array, model and receptors
  int columns = 0, rows = 0;
  double pad_area_mm2 = 0;
  std::vector<std::array<BankEntry, 3>> entry;  // by pad, by primary
  std::size_t pads() const { return entry.size(); }
};
// Bad input naming the problem: not a bank, not a grid, a pixel that is not its pad's
// centre, weights that are not one per pad or not finite.
PixelBank pixel_bank_from_json(const Json& j);

// "pixel (c, r)": pad r x columns + c as the image's column and row.
std::string pixel_text(long pad, int columns);

}  // namespace tp
