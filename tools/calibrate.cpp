// calibrate: finds, for the person wearing the array, each primary's detection threshold
// and comfort limit (docs/calibration.md), delivering every trial through a stimulator and
// asking in the terminal.  Prints the profile render-tactile takes.
//
//   calibrate --bank bank.json --port emu --log trials.csv --output profile.json

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "host/answers.hpp"
#include "host/session.hpp"
#include "host/signals.hpp"
#include "host/stimulator.hpp"
#include "host/terminal.hpp"
#include "core/files.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "psych/calibration.hpp"
#include "render/options.hpp"
#include "requests/calibrate.hpp"

namespace {

[[noreturn]] void stopped_by_signal(int sig) {
  throw tp::Error(static_cast<tp::ExitCode>(128 + sig),
                  "stopped by " + tp::host::signal_name(sig) + "; output stopped");
}

// One trial: its stimulus delivered while the keys are watched for a stop, then the
// question; the answer goes to the calibration and the log.
void run_trial(tp::Calibration& cal, tp::host::Transport& transport, tp::host::Answers& answers,
               tp::LineFile& log, const volatile std::sig_atomic_t* flag, int columns) {
  if (*flag) stopped_by_signal(*flag);
  const std::string stage = cal.stage_text();
  if (!stage.empty()) answers.say("calibrate: " + stage + "\n");
  const int n = static_cast<int>(cal.trials().size()) + 1;
  answers.say("trial " + std::to_string(n) + ": " +
              tp::kPrimaries[static_cast<std::size_t>(cal.primary())] + " at (" +
              std::to_string(cal.pad() % columns) + ", " + std::to_string(cal.pad() / columns) +
              "), " + tp::number_text(std::round(cal.level_mA() * 1e4) / 1e4) + " mA ... ");
  bool by_key = false;
  const tp::host::SessionReport r = tp::host::run_watched(
      transport, cal.stimulus(), tp::host::SessionOptions{}, flag,
      [&](int ms) { return answers.stop_key(ms); }, by_key);
  if (*flag) stopped_by_signal(*flag);
  if (by_key && answers.gone())
    tp::failure("the terminal is gone during trial " + std::to_string(n) + "; output stopped");
  if (by_key) {
    answers.say("stopped\n");
    tp::failure("stopped by the user (" + answers.stop_key_name() + ") during trial " +
                std::to_string(n) + "; output stopped");
  }
  if (r.exit_code != 0) stopped_by_signal(r.exit_code - 128);
  answers.say(cal.comfort() ? "too strong? [y/n] " : "felt it? [y/n] ");
  const auto a = answers.answer(flag);
  if (!a) stopped_by_signal(*flag);
  answers.say(a->given + "\n");
  if (a->kind == tp::host::Answer::stop)
    tp::failure("stopped by the user (" + a->given + ") after trial " + std::to_string(n) +
                "; nothing running");
  cal.respond(a->kind == tp::host::Answer::yes);
  log.line(tp::calibration_log_row(cal.trials().back(), columns, r.pulses, r.peak_mA));
}

}  // namespace

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
  std::string bank_path, port = "emu", record, log_path, pixel, primaries, rates, responses,
                         ceiling = "1", start = "0.05", step = "1.25", max_step = "1.5",
                         trial = "0.5", width = "200";
  int baud = 115200, emu_channels = 0, down = 2, reversals = 8, max_trials = 80;
  bool per_pixel = false;
  app.add_option("--bank", bank_path, "Pattern bank (optimize-weights --bank)")
      ->required()
      ->type_name("FILE");
  app.add_option("--log", log_path, "The trial log (CSV), one row per trial as it is answered")
      ->required()
      ->type_name("FILE");
  app.add_option("--port", port, "Serial port path, or emu for the in-process emulator [emu]")
      ->type_name("PORT");
  app.add_option("--baud", baud, "Baud rate [115200]")->check(CLI::Range(300, 4000000));
  app.add_option("--emu-channels", emu_channels, "Emulator only: channels [the bank's pads]")
      ->check(CLI::Range(1, 64));
  app.add_option("--record", record, "Emulator only: write each delivered pulse as a JSON line")
      ->type_name("FILE");
  app.add_option("--pixel", pixel, "The pixel measured, COLUMN,ROW [the array's centre]")
      ->type_name("C,R");
  app.add_flag("--per-pixel", per_pixel, "Measure every pixel (a long session)");
  app.add_option("--primaries", primaries, "Which, in order, of RA, SAI, PC [all three]")
      ->type_name("P,...");
  app.add_option("--rates", rates, "Each primary's trial rate, Hz [RA:30,SAI:200,PC:250]")
      ->type_name("P:HZ,...");
  app.add_option("--ceiling", ceiling, "Never above this, mA, (0, 2] [1]")->type_name("MA");
  app.add_option("--start", start, "The first trial's level, mA, 0.001 to --ceiling [0.05]")
      ->type_name("MA");
  app.add_option("--step", step, "Each step's factor, (1, --max-step] [1.25]")->type_name("F");
  app.add_option("--max-step", max_step, "The largest step up, a factor, (1, 2] [1.5]")
      ->type_name("F");
  app.add_option("--down", down, "The threshold's n-down-1-up rule, 1 to 3 [2]");
  app.add_option("--reversals", reversals, "Reversals that end a staircase, 4 to 30 [8]");
  app.add_option("--max-trials", max_trials, "Trials per staircase at most, 10 to 1000 [80]");
  app.add_option("--trial-duration", trial, "Each trial's stimulus, s, 0.05 to 10 [0.5]")
      ->type_name("S");
  app.add_option("--width", width, "Main phase, us, whole, 10 to 1000 [200]")->type_name("US");
  tp::cli::add_output_option(app);
  app.add_option("--responses", responses,
                 "- : the answers as lines on stdin (y, n or q) instead of the terminal's keys")
      ->type_name("-");

  return tp::cli::run(app, argc, argv, [&] {
    // Everything checked before the port is opened.
    tp::CalibrateRequest r;
    r.bank_path = bank_path;
    r.port = port;
    r.record_path = record;
    r.responses = responses;
    r.per_pixel = per_pixel;
    r.pixel = pixel;
    tp::check_calibrate(r);
    const tp::PixelBank bank = tp::pixel_bank_from_json(tp::read_json(bank_path, "bank"));
    tp::CalibrationOptions& o = r.options;
    o.staircase.ceiling_mA = tp::parse_finite(ceiling, "--ceiling");
    o.staircase.start_mA = tp::parse_finite(start, "--start");
    o.staircase.ascend_factor = o.staircase.step_factor = tp::parse_finite(step, "--step");
    o.staircase.max_step_up = tp::parse_finite(max_step, "--max-step");
    o.staircase.down = down;
    o.staircase.reversals = reversals;
    o.staircase.max_trials = max_trials;
    o.trial_s = tp::parse_finite(trial, "--trial-duration");
    o.width_us = o.balance_width_us = tp::parse_finite(width, "--width");
    if (!rates.empty()) tp::parse_rates(rates, o.rate_hz);
    if (!primaries.empty()) o.primaries = tp::parse_primaries(primaries, "--primaries");
    tp::Calibration cal = tp::make_calibration(bank, r);  // checks every option
    tp::check_writable(log_path, "--log");  // created once the device has passed its check

    const volatile std::sig_atomic_t* flag = tp::host::install_stop_handlers();
    tp::host::Answers answers(!responses.empty());
    tp::host::EmulatorOptions emu;
    emu.caps.channels =
        static_cast<std::uint8_t>(emu_channels > 0 ? emu_channels : static_cast<int>(bank.pads()));
    emu.record_path = record;
    const auto transport = tp::host::open_transport(port, baud, emu);
    tp::host::arm_emergency_stop(transport->native_handle());
    // Every trial at the ceiling against the device's capabilities, as each trial's session
    // will check it (run_watched's count is the stimulus's own), before the first is sent.
    const tp::device::Capabilities caps = tp::host::StimulatorClient(*transport).identify();
    cal.check_trials(
        [&](const tp::Mix& m) { tp::host::plan_session(caps, m, tp::host::SessionOptions{}); });
    tp::LineFile log(log_path, "--log");
    log.line(tp::calibration_log_header());
    answers.say("calibrate: " + cal.length_text() + "\n");
    while (!cal.done()) run_trial(cal, *transport, answers, log, flag, bank.columns);
    tp::host::arm_emergency_stop(-1);
    log.close();
    for (const std::string& note : cal.notes())
      std::fprintf(stderr, "calibrate: %s\n", note.c_str());
    const tp::Profile p = cal.profile();
    bool any = false;
    for (const auto& range : p.primary) any = any || range.has_value();
    if (!any) tp::failure("no primary found (said above): no profile; the log has every trial");
    std::fprintf(stderr, "calibrate: %s\n", cal.summary().c_str());
    tp::cli::write_stdout(tp::dump_json(tp::profile_to_json(p)));
  });
}
