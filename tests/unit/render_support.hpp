#pragma once
// The render tests' fixtures and oracle: a 6 x 6 bank made once, a profile, a dark image,
// random images, and crosstalk computed directly from each pattern's own field (the
// library computes it from one field per pad, by superposition: render/plan.hpp).

#include <cmath>
#include <memory>
#include <random>

#include "requests/optimize_reports.hpp"
#include "model/field.hpp"
#include "opt/bank.hpp"
#include "render/render.hpp"

namespace tp::render_test {

inline Json profile_json(double t = 0.3, double c = 0.9) {
  return {{"format", "tactile-primaries/profile/1"},
          {"primaries",
           {{"RA", {{"threshold_mA", 0.4}, {"comfort_mA", 1.0}}},
            {"SAI", {{"threshold_mA", t}, {"comfort_mA", c}}},
            {"PC", {{"threshold_mA", 0.5}, {"comfort_mA", 1.2}}}}}};
}

// A 6 x 6 grid of 1 x 1 mm pads at 2 mm under rect3d, every pixel's pattern of each mode in
// a 3 x 3 neighbourhood: computed once.
inline const PixelBank& bank6() {
  static const PixelBank b = [] {
    Document doc;
    doc.setup.array = ElectrodeArray::grid_of(6, 6, 2.0, 2.0, 1.0, 1.0);
    doc.setup.conductor.model = "rect3d";
    doc.setup.lateral_margin_mm = 2.0;
    BankOptions o;
    o.neighbourhood = 3;
    o.threads = 2;
    const Bank bank = optimize_bank(doc.setup, o);
    return pixel_bank_from_json(parse_json_strict(dump_json(bank_to_json(doc, bank, o)), "bank"));
  }();
  return b;
}

// A bank of two pixels in a row, each primary's pattern +1 at its own pad and -1 at the
// other's (as make-pulse checks it: balanced, within every limit at 1 mA): calibration's.
inline PixelBank two_pads() {
  PixelBank b;
  b.columns = 2;
  b.rows = 1;
  b.pad_area_mm2 = 1;
  b.entry.resize(2);
  for (std::size_t pad = 0; pad < 2; ++pad)
    for (auto& e : b.entry[pad]) {
      e.present = e.feasible = true;
      e.weights = pad == 0 ? std::vector<double>{1, -1} : std::vector<double>{-1, 1};
    }
  return b;
}

// A 6 x 6 image, all dark.
inline PadIntensities dark6() {
  PadIntensities im;
  im.columns = im.rows = 6;
  im.value.assign(36, {0, 0, 0});
  return im;
}

// Each feasible (pixel, primary) lit with probability lit_share, at a whole level of 255.
inline PadIntensities random_image(const PixelBank& b, std::mt19937& rng, double lit_share) {
  PadIntensities im;
  im.columns = b.columns;
  im.rows = b.rows;
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t pad = 0; pad < b.pads(); ++pad) {
    std::array<double, 3> v{};
    for (std::size_t p = 0; p < 3; ++p)
      if (b.entry[pad][p].feasible && u(rng) < lit_share) v[p] = std::round(u(rng) * 255) / 255;
    im.value.push_back(v);
  }
  return im;
}

// Crosstalk of pixel a's pattern onto pixel b's (both of `primary`) at their currents, as
// render/render.hpp defines it, from each pattern's own field evaluated anew.
inline double crosstalk_oracle(const PixelBank& bank, int primary, long a, double current_a_mA,
                               long b, double current_b_mA) {
  const auto p = static_cast<std::size_t>(primary);
  const BankEntry& ea = bank.entry[static_cast<std::size_t>(a)][p];
  const BankEntry& eb = bank.entry[static_cast<std::size_t>(b)][p];
  const Setup& setup = bank.doc.setup;
  const Receptor& r = setup.receptors[receptor_index(setup, kPrimaries[p])];
  const Field fa(setup, ea.weights), fb(setup, eb.weights);
  const double own = fb.af_3d(r.fibre, fibre_axis(r), eb.peak_x_mm, eb.peak_y_mm, eb.peak_z_mm);
  if (!(own > 0)) return HUGE_VAL;
  const double onto = fa.af_3d(r.fibre, fibre_axis(r), eb.peak_x_mm, eb.peak_y_mm, eb.peak_z_mm);
  return std::abs(current_a_mA * onto) / (current_b_mA * own);
}

}  // namespace tp::render_test
