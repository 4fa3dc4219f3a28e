#include "requests/calibrate.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp {

void check_calibrate(const CalibrateRequest& r) {
  if (!r.responses.empty() && r.responses != "-")
    bad_input("--responses: '" + r.responses + "' (only - , stdin, is supported)");
  if (r.port != "emu" && !r.record_path.empty())
    bad_input("--record: only with --port emu (stim-emu has its own)");
  if (r.bank_path == "-" && !r.responses.empty()) bad_input("--bank -: stdin carries the responses");
}

std::vector<long> calibration_pads(const PixelBank& bank, const CalibrateRequest& r) {
  std::vector<long> pads;
  if (r.per_pixel && !r.pixel.empty()) bad_input("--pixel and --per-pixel: give one");
  if (r.per_pixel) {
    for (long pad = 0; pad < static_cast<long>(bank.pads()); ++pad) pads.push_back(pad);
  } else if (!r.pixel.empty()) {
    const std::vector<double> cr = parse_list(r.pixel, "--pixel");
    if (cr.size() != 2 || cr[0] != std::floor(cr[0]) || cr[1] != std::floor(cr[1]) || cr[0] < 0 ||
        cr[0] >= bank.columns || cr[1] < 0 || cr[1] >= bank.rows)
      bad_input("--pixel: '" + r.pixel + "' is not a column,row of the " +
                std::to_string(bank.columns) + " x " + std::to_string(bank.rows) + " array");
    pads.push_back(static_cast<long>(cr[1]) * bank.columns + static_cast<long>(cr[0]));
  } else {
    pads.push_back(static_cast<long>(bank.rows / 2) * bank.columns + bank.columns / 2);
  }
  return pads;
}

Calibration make_calibration(const PixelBank& bank, const CalibrateRequest& r) {
  CalibrationOptions o = r.options;
  o.pads = calibration_pads(bank, r);
  return Calibration(bank, o);
}

}  // namespace tp
