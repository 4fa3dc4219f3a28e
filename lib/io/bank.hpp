#pragma once
// The bank render-tactile and calibrate read (optimize-weights --bank without --at): every
// pad's pixel, and per primary its pattern (weights and peak) or why the optimiser found
// none.

#include <array>
#include <cstdint>
#include <optional>
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

// One mode's recruitment (optimize-weights --bank --population N; render/recruitment.hpp
// computes it, docs/rendering.md "The gamut"): its pattern at the feasible pixel nearest the
// array's centre, the target's model threshold there (the fibre through the pattern's peak,
// as the profile without calibration takes it), and the thresholds of afferents sampled over
// the pitch around that pixel, per class (RA, SAI, PC), ascending; +infinity where one does
// not fire below the search's cap (null in JSON).
struct ModeRecruitment {
  long pad = -1;
  double reference_mA = 0;
  std::array<std::vector<double>, 3> thresholds_mA;
  // Each class's fraction recruited at `current_mA` (threshold <= current).
  std::array<double, 3> fractions(double current_mA) const;
};
struct BankRecruitment {
  long per_class = 0;
  std::uint64_t seed = 1;
  std::string fibre_model;
  Json pulse;                     // the pulse the thresholds are for (pulse_spec_to_json)
  double max_mA = 0;              // the searches' cap
  std::array<std::optional<ModeRecruitment>, 3> mode;  // by primary; none: no such mode
};
Json recruitment_to_json(const BankRecruitment& r);
// Bad input naming the field at fault (under `where`): a count or threshold out of range,
// thresholds not ascending, a pad outside the bank.
BankRecruitment recruitment_from_json(const Json& j, std::size_t pads, const std::string& where);

// A bank of every pad's pixel on a grid (optimize-weights --bank without --at).
struct PixelBank {
  Document doc;  // the array, model and receptors
  int columns = 0, rows = 0;
  double pad_area_mm2 = 0;
  std::vector<std::array<BankEntry, 3>> entry;  // by pad, by primary
  std::optional<BankRecruitment> recruitment;   // the modes' colours' source, when it has one
  std::size_t pads() const { return entry.size(); }
};
// Bad input naming the problem: not a bank, not a grid, a pixel that is not its pad's
// centre, weights that are not one per pad or not finite.
PixelBank pixel_bank_from_json(const Json& j);

// "pixel (c, r)": pad r x columns + c as the image's column and row.
std::string pixel_text(long pad, int columns);

}  // namespace tp
