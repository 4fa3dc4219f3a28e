// calibrate: finds, for the person wearing the array, each primary's detection threshold
// and comfort limit (docs/calibration.md), delivering every trial through a stimulator and
// asking in the terminal.  Prints the profile render-tactile takes.
//
//   calibrate --bank bank.json --port emu --log trials.csv --output profile.json

#include <cstdio>
#include <string>

#include "cli/entry.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "host/answers.hpp"
#include "host/signals.hpp"
#include "psych/profile.hpp"
#include "requests/calibrate.hpp"
#include "runs/calibration_run.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Finds, for the person wearing the array, each primary's detection threshold and "
      "comfort limit at a pixel (or at every pixel), by an ascending method of limits and "
      "then a transformed up-down staircase (Levitt 1971: 2-down-1-up, the 70.7 % point, "
      "for the threshold; 1-down-1-up from the threshold for the comfort limit).  Each "
      "trial is delivered through the stimulator, then the terminal asks y or n; q, Esc or "
      "Ctrl-C stops the output at once and exits.  No trial exceeds --ceiling, and every "
      "trial at the ceiling is checked against the device before the first is sent.  Says "
      "the session's length up front, each staircase as it starts, and what was found at "
      "the end.  Prints the profile (tactile-primaries/profile/1) on stdout, or to --output "
      "FILE (whole, or left as it was when calibrate is stopped); writes every trial to "
      "--log.  docs/calibration.md.",
      "calibrate"};
  tp::CalibrateRequest r;
  tp::CalibrationSpec& spec = r.spec;
  app.add_option("--bank", r.bank_path, "Pattern bank (optimize-weights --bank)")
      ->required()
      ->type_name("FILE");
  app.add_option("--log", r.log_path, "The trial log (CSV), one row per trial as it is answered")
      ->required()
      ->type_name("FILE");
  app.add_option("--port", r.port, "Serial port path, or emu for the in-process emulator [emu]")
      ->type_name("PORT");
  app.add_option("--baud", r.baud, "Baud rate [115200]")->check(CLI::Range(300, 4000000));
  app.add_option("--emu-channels", r.emu_channels, "Emulator only: channels [the bank's pads]")
      ->check(CLI::Range(1, 64));
  app.add_option("--record", r.record_path, "Emulator only: write each delivered pulse as a JSON line")
      ->type_name("FILE");
  std::string emu_compliance;
  tp::cli::add_skin_flags(app, "--emu-skin", "--emu-compliance-v", r.emu_skin_path,
                          emu_compliance, "--record (and the profile's impedance_kohm)",
                          "Emulator only: ");
  app.add_option("--pixel", r.pixel, "The pixel measured, COLUMN,ROW [the array's centre]")
      ->type_name("C,R");
  app.add_flag("--per-pixel", r.per_pixel, "Measure every pixel (a long session)");
  app.add_option("--primaries", spec.primaries, "Which, in order, of RA, SAI, PC [all three]")
      ->type_name("P,...");
  app.add_option("--rates", spec.rates, "Each primary's trial rate, Hz [RA:30,SAI:200,PC:250]")
      ->type_name("P:HZ,...");
  app.add_option("--ceiling", spec.ceiling_mA, "Never above this, mA, (0, 2] [1]")->type_name("MA");
  app.add_option("--start", spec.start_mA, "The first trial's level, mA, 0.001 to --ceiling [0.05]")
      ->type_name("MA");
  app.add_option("--step", spec.step, "Each step's factor, (1, --max-step] [1.25]")->type_name("F");
  app.add_option("--max-step", spec.max_step, "The largest step up, a factor, (1, 2] [1.5]")
      ->type_name("F");
  app.add_option("--down", spec.down, "The threshold's n-down-1-up rule, 1 to 3 [2]");
  app.add_option("--reversals", spec.reversals, "Reversals that end a staircase, 4 to 30 [8]");
  app.add_option("--max-trials", spec.max_trials, "Trials per staircase at most, 10 to 1000 [80]");
  app.add_option("--trial-duration", spec.trial_s, "Each trial's stimulus, s, 0.05 to 10 [0.5]")
      ->type_name("S");
  app.add_option("--width", spec.width_us, "Main phase, us, whole, 10 to 1000 [200]")->type_name("US");
  tp::cli::add_output_option(app);
  app.add_option("--responses", r.responses,
                 "- : the answers as lines on stdin (y, n or q) instead of the terminal's keys")
      ->type_name("-");

  return tp::cli::run(app, argc, argv, [&] {
    // Everything checked before the port is opened.
    if (!emu_compliance.empty())
      r.emu_compliance_V = tp::parse_finite(emu_compliance, "--emu-compliance-v");
    const tp::PixelBank bank = tp::calibration_bank(r);
    tp::Calibration cal = tp::make_calibration(bank, r);
    const volatile std::sig_atomic_t* flag = tp::host::install_stop_handlers();
    tp::host::Answers answers(!r.responses.empty());
    tp::runs::AnswersRespondent person(answers);
    const tp::Profile p = tp::runs::run_calibration(
        r, bank, cal, person, flag,
        [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
    tp::cli::write_stdout(tp::dump_json(tp::profile_to_json(p)));
  });
}
