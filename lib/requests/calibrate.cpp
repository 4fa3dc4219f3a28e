#include "requests/calibrate.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "render/options.hpp"

namespace tp {

void check_calibrate(const CalibrateRequest& r) {
  if (!r.responses.empty() && r.responses != "-")
    bad_input("--responses: '" + r.responses + "' (only - , stdin, is supported)");
  if (r.port != "emu" && !r.record_path.empty())
    bad_input("--record: only with --port emu (stim-emu has its own)");
  if (r.port != "emu" && !r.emu_skin_path.empty())
    bad_input("--emu-skin: only with --port emu (a device's electrodes touch real skin)");
  if (r.emu_compliance_V && r.emu_skin_path.empty())
    bad_input("--emu-compliance-v: applies with --emu-skin (an ideal load needs no voltage)");
  if (r.bank_path == "-" && !r.responses.empty()) bad_input("--bank -: stdin carries the responses");
}

PixelBank calibration_bank(const CalibrateRequest& r) {
  check_calibrate(r);
  return pixel_bank_from_json(read_json(r.bank_path, "bank"));
}

CalibrationOptions calibration_options(const CalibrationSpec& s) {
  CalibrationOptions o;
  o.staircase.ceiling_mA = parse_finite(s.ceiling_mA, "--ceiling");
  o.staircase.start_mA = parse_finite(s.start_mA, "--start");
  o.staircase.ascend_factor = o.staircase.step_factor = parse_finite(s.step, "--step");
  o.staircase.max_step_up = parse_finite(s.max_step, "--max-step");
  o.staircase.down = s.down;
  o.staircase.reversals = s.reversals;
  o.staircase.max_trials = s.max_trials;
  o.trial_s = parse_finite(s.trial_s, "--trial-duration");
  o.width_us = o.balance_width_us = parse_finite(s.width_us, "--width");
  if (!s.rates.empty()) parse_rates(s.rates, o.rate_hz);
  if (!s.primaries.empty()) o.primaries = parse_primaries(s.primaries, "--primaries");
  return o;
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
  CalibrationOptions o = calibration_options(r.spec);
  o.pads = calibration_pads(bank, r);
  Calibration cal(bank, o);
  check_writable(r.log_path, "--log");
  return cal;
}

}  // namespace tp
