#pragma once
// calibrate's request (docs/calibration.md): the options checked with the program's
// messages before the port is opened, the pixels measured, and the calibration they make.
// The trials themselves, a stimulator and the person's answers, are runs/calibration_run's.

#include <optional>
#include <string>
#include <vector>

#include "io/bank.hpp"
#include "psych/calibration.hpp"

namespace tp {

// The staircase, rates, primaries, trial and width as typed (calibrate's flags), parsed
// once the bank is read; the defaults are calibrate's.
struct CalibrationSpec {
  std::string ceiling_mA = "1", start_mA = "0.05", step = "1.25", max_step = "1.5",
              trial_s = "0.5", width_us = "200";
  std::string rates;      // P:HZ,... [RA:30,SAI:200,PC:250]
  std::string primaries;  // P,... [all three]
  int down = 2, reversals = 8, max_trials = 80;
};

struct CalibrateRequest {
  std::string bank_path;      // the bank's file, - for stdin
  std::string log_path;       // the trial log (CSV)
  std::string port = "emu";   // a serial port, or emu
  int baud = 115200;          // a serial port's
  int emu_channels = 0;       // emulator only: its channels; 0: the bank's pads
  std::string record_path;    // emulator only
  std::string emu_skin_path;  // emulator only: the electrodes' skin (docs/skin.md)
  std::optional<double> emu_compliance_V;  // with emu_skin_path: 1 to 1000 V [100]
  std::string responses;      // - : the answers on stdin; empty: the terminal's keys
  bool per_pixel = false;     // every pixel
  std::string pixel;          // COLUMN,ROW as typed [the array's centre]
  CalibrationSpec spec;       // the staircase and the trials
};

// The options' combinations, before the bank is read: bad input naming --responses,
// --record or --bank.
void check_calibrate(const CalibrateRequest& r);

// check_calibrate, then the bank (bad input naming --bank when it is not one).
PixelBank calibration_bank(const CalibrateRequest& r);

// The spec's values (no pads): bad input naming the first flag that is not a number, in
// the order --ceiling, --start, --step, --max-step, --trial-duration, --width, --rates,
// --primaries.  The step is the ascent's factor and the staircase's; the width both
// phases'.  Their ranges are check_calibration_options'.
CalibrationOptions calibration_options(const CalibrationSpec& s);

// The pixels measured, as pads of the bank: every one (per_pixel), the one at COLUMN,ROW,
// or the array's centre; bad input naming --pixel.
std::vector<long> calibration_pads(const PixelBank& bank, const CalibrateRequest& r);

// The calibration of those pixels, every option checked (check_calibration_options), and
// the log's place writable (bad input naming --log; the file is created once the device
// has passed its check).  It refers to `bank`, which must outlive it.
Calibration make_calibration(const PixelBank& bank, const CalibrateRequest& r);

}  // namespace tp
