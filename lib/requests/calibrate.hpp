#pragma once
// calibrate's request (docs/calibration.md): the options checked with the program's
// messages before the port is opened, the pixels measured, and the calibration they make.
// The trials themselves, a stimulator and the person's answers, are the program's.

#include <string>
#include <vector>

#include "io/bank.hpp"
#include "psych/calibration.hpp"

namespace tp {

struct CalibrateRequest {
  std::string bank_path;      // the bank's file, - for stdin
  std::string port = "emu";   // a serial port, or emu
  std::string record_path;    // emulator only
  std::string responses;      // - : the answers on stdin; empty: the terminal's keys
  bool per_pixel = false;     // every pixel
  std::string pixel;          // COLUMN,ROW as typed [the array's centre]
  CalibrationOptions options;  // the staircase, rates, primaries, trial and width (no pads)
};

// The options' combinations, before the bank is read: bad input naming --responses,
// --record or --bank.
void check_calibrate(const CalibrateRequest& r);

// The pixels measured, as pads of the bank: every one (per_pixel), the one at COLUMN,ROW,
// or the array's centre; bad input naming --pixel.
std::vector<long> calibration_pads(const PixelBank& bank, const CalibrateRequest& r);

// The calibration of those pixels, every option checked (check_calibration_options).
Calibration make_calibration(const PixelBank& bank, const CalibrateRequest& r);

}  // namespace tp
