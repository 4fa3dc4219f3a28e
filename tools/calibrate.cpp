// calibrate: finds, for the person wearing the array, each primary's detection threshold
// and comfort limit (docs/calibration.md), delivering every trial through a stimulator and
// asking in the terminal.  Prints the profile render-tactile takes.
//
//   calibrate --bank bank.json --port emu --log trials.csv > profile.json

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "host/line_reader.hpp"
#include "host/session.hpp"
#include "host/signals.hpp"
#include "host/terminal.hpp"
#include "io/json.hpp"
#include "io/number.hpp"
#include "psych/calibration.hpp"

namespace {

constexpr int kEsc = 27;

std::string pixel_text(long pad, int columns) {
  return "(" + std::to_string(pad % columns) + ", " + std::to_string(pad / columns) + ")";
}

// Where the answers come from: the terminal's keys, or lines on stdin (--responses -).
class Answers {
 public:
  explicit Answers(bool from_stdin) {
    if (from_stdin)
      lines_ = std::make_unique<tp::host::LineReader>(0, 4096);
    else
      tty_ = std::make_unique<tp::host::Terminal>();
  }
  void say(const std::string& text) {
    if (tty_)
      tty_->say(text);
    else
      std::fprintf(stderr, "%s", text.c_str());
  }
  // During a trial: whether q or Esc was pressed (the terminal only).
  bool stop_key(int timeout_ms) {
    if (!tty_) {
      timespec ts{0, static_cast<long>(timeout_ms) * 1000000};
      nanosleep(&ts, nullptr);
      return false;
    }
    const int k = tty_->key(timeout_ms);
    if (k == tp::host::Terminal::kGone) gone_ = true;
    return gone_ || k == 'q' || k == 'Q' || k == kEsc;
  }
  bool gone() const { return gone_; }
  // The answer: 'y', 'n' or 'q' (q, Q or Esc); empty when a signal interrupted the wait.
  std::optional<char> answer(const volatile std::sig_atomic_t* flag) {
    while (!*flag) {
      if (tty_) {
        const int k = tty_->key(100);
        if (k == tp::host::Terminal::kGone)
          throw tp::Error(tp::ExitCode::failure, "the terminal is gone; nothing running");
        if (k == 'y' || k == 'Y') return 'y';
        if (k == 'n' || k == 'N') return 'n';
        if (k == 'q' || k == 'Q' || k == kEsc) return 'q';
        continue;
      }
      std::string line;
      if (lines_->next(line)) {
        const auto b = line.find_first_not_of(" \t\r");
        const auto e = line.find_last_not_of(" \t\r");
        const std::string word = b == std::string::npos ? "" : line.substr(b, e - b + 1);
        if (word == "y" || word == "yes") return 'y';
        if (word == "n" || word == "no") return 'n';
        if (word == "q" || word == "quit") return 'q';
        tp::bad_input("--responses: line " + std::to_string(lines_->lines()) + ": '" + word +
                      "' is not y, n or q");
      }
      if (lines_->at_end())
        throw tp::Error(tp::ExitCode::failure,
                        "--responses: the answers ended before the "
                        "calibration did");
      lines_->fill(100);
    }
    return std::nullopt;
  }

 private:
  std::unique_ptr<tp::host::Terminal> tty_;
  std::unique_ptr<tp::host::LineReader> lines_;
  bool gone_ = false;
};

[[noreturn]] void stopped_by_signal(int sig) {
  throw tp::Error(static_cast<tp::ExitCode>(128 + sig),
                  "stopped by " + tp::host::signal_name(sig) + "; output stopped");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Finds, for the person wearing the array, each primary's detection threshold and "
      "comfort limit at a pixel (or at every pixel), by an ascending method of limits and "
      "then a transformed up-down staircase (Levitt 1971: 2-down-1-up, the 70.7 % point, "
      "for the threshold; 1-down-1-up from the threshold for the comfort limit).  Each "
      "trial is delivered through the stimulator, then the terminal asks y or n; q, Esc or "
      "Ctrl-C stops the output at once and exits.  No trial exceeds --ceiling.  Prints the "
      "profile (tactile-primaries/profile/1) on stdout; writes every trial to --log.  "
      "docs/calibration.md.",
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
  app.add_option("--responses", responses,
                 "- : the answers as lines on stdin (y, n or q) instead of the terminal's keys")
      ->type_name("-");

  return tp::cli::run(app, argc, argv, [&] {
    // Everything checked before the port is opened.
    if (!responses.empty() && responses != "-")
      tp::bad_input("--responses: '" + responses + "' (only - , stdin, is supported)");
    if (port != "emu" && !record.empty())
      tp::bad_input("--record: only with --port emu (stim-emu has its own)");
    if (bank_path == "-" && !responses.empty())
      tp::bad_input("--bank -: stdin carries the responses");
    const tp::PixelBank bank = tp::pixel_bank_from_json(tp::read_json(bank_path, "bank"));
    tp::CalibrationOptions o;
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
    if (per_pixel && !pixel.empty()) tp::bad_input("--pixel and --per-pixel: give one");
    if (per_pixel) {
      for (long pad = 0; pad < static_cast<long>(bank.pads()); ++pad) o.pads.push_back(pad);
    } else if (!pixel.empty()) {
      const std::vector<double> cr = tp::parse_list(pixel, "--pixel");
      if (cr.size() != 2 || cr[0] != std::floor(cr[0]) || cr[1] != std::floor(cr[1]) || cr[0] < 0 ||
          cr[0] >= bank.columns || cr[1] < 0 || cr[1] >= bank.rows)
        tp::bad_input("--pixel: '" + pixel + "' is not a column,row of the " +
                      std::to_string(bank.columns) + " x " + std::to_string(bank.rows) + " array");
      o.pads.push_back(static_cast<long>(cr[1]) * bank.columns + static_cast<long>(cr[0]));
    } else {
      o.pads.push_back(static_cast<long>(bank.rows / 2) * bank.columns + bank.columns / 2);
    }
    tp::Calibration cal(bank, o);  // checks every option
    std::FILE* log = std::fopen(log_path.c_str(), "w");
    if (!log) tp::bad_input("--log: cannot open '" + log_path + "': " + std::strerror(errno));
    struct CloseLog {
      std::FILE* f;
      ~CloseLog() { std::fclose(f); }
    } close_log{log};
    std::fprintf(log,
                 "trial,primary,pad,column,row,question,level_mA,phase,response,reversal,"
                 "pulses,peak_mA\n");
    std::fflush(log);

    const volatile std::sig_atomic_t* flag = tp::host::install_stop_handlers();
    Answers answers(!responses.empty());
    tp::host::EmulatorOptions emu;
    emu.caps.channels =
        static_cast<std::uint8_t>(emu_channels > 0 ? emu_channels : static_cast<int>(bank.pads()));
    emu.record_path = record;
    const auto transport = tp::host::open_transport(port, baud, emu);
    tp::host::arm_emergency_stop(transport->native_handle());
    tp::host::SessionOptions session;
    while (!cal.done()) {
      if (*flag) stopped_by_signal(*flag);
      const tp::Mix m = cal.stimulus();
      const int n = static_cast<int>(cal.trials().size()) + 1;
      const std::string what =
          std::string(tp::kPrimaries[static_cast<std::size_t>(cal.primary())]) + " at " +
          pixel_text(cal.pad(), bank.columns) + ", " +
          tp::number_text(std::round(cal.level_mA() * 1e4) / 1e4) + " mA";
      answers.say("trial " + std::to_string(n) + ": " + what + " ... ");
      bool by_key = false;
      const tp::host::SessionReport r = tp::host::run_watched(
          *transport, m, session, flag, [&](int ms) { return answers.stop_key(ms); }, by_key);
      if (*flag) stopped_by_signal(*flag);
      if (by_key && answers.gone())
        throw tp::Error(tp::ExitCode::failure, "the terminal is gone during trial " +
                                                   std::to_string(n) + "; output stopped");
      if (by_key) {
        answers.say("stopped\n");
        throw tp::Error(tp::ExitCode::failure, "stopped by the user (q) during trial " +
                                                   std::to_string(n) + "; output stopped");
      }
      if (r.exit_code != 0) stopped_by_signal(r.exit_code - 128);
      answers.say(cal.comfort() ? "too strong? [y/n] " : "felt it? [y/n] ");
      const std::optional<char> a = answers.answer(flag);
      if (!a) stopped_by_signal(*flag);
      if (*a == 'q') {
        answers.say("q\n");
        throw tp::Error(tp::ExitCode::failure, "stopped by the user (q) after trial " +
                                                   std::to_string(n) + "; nothing running");
      }
      answers.say(std::string(1, *a) + "\n");
      const double level = cal.level_mA();
      const bool comfort = cal.comfort();
      const long pad = cal.pad();
      const int primary = cal.primary();
      cal.respond(*a == 'y');
      const tp::CalibrationTrial& t = cal.trials().back();
      std::fprintf(log, "%d,%s,%ld,%ld,%ld,%s,%s,%s,%s,%d,%u,%s\n", n,
                   tp::kPrimaries[static_cast<std::size_t>(primary)], pad, pad % bank.columns,
                   pad / bank.columns, comfort ? "too strong" : "felt",
                   tp::number_text(level).c_str(), t.ascending ? "ascending" : "staircase",
                   *a == 'y' ? "yes" : "no", t.reversal ? 1 : 0, r.pulses,
                   tp::number_text(r.peak_mA).c_str());
      std::fflush(log);
    }
    tp::host::arm_emergency_stop(-1);
    for (const std::string& note : cal.notes())
      std::fprintf(stderr, "calibrate: %s\n", note.c_str());
    const tp::Profile p = cal.profile();
    bool any = false;
    for (const auto& r : p.primary) any = any || r.has_value();
    if (!any)
      throw tp::Error(tp::ExitCode::failure,
                      "nothing was felt up to the ceiling: no profile (the log has every trial)");
    std::fprintf(stderr, "calibrate: %zu trials\n", cal.trials().size());
    tp::cli::write_stdout(tp::dump_json(tp::profile_to_json(p)));
  });
}
