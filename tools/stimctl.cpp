// stimctl: deliver a stimulus document through a stimulator (serial port or emulator).
//
//   optimize-weights --mode SAI | make-pulse --amplitude 1 --frequency 200 | stimctl --port emu
//   --duration 1 stimctl --port /dev/ttyACM0 < stimulus.json producer | stimctl --port /dev/ttyACM0
//   --live --stimulus stimulus.json   # weight frames as JSON lines

#include <csignal>
#include <cstdio>
#include <optional>
#include <string>

#include <unistd.h>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "host/delivery.hpp"
#include "host/live.hpp"
#include "host/session.hpp"
#include "host/signals.hpp"
#include "core/number.hpp"
#include "host/impedance_check.hpp"
#include "pulse/mix.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Delivers a stimulus document (make-pulse's JSON, on stdin) through a stimulator: "
      "identifies the device, checks the stimulus against its capabilities and the host's "
      "limits, configures it, starts, feeds its watchdog, and stops the output on completion, "
      "--duration, end of input, any terminating signal or any error.  The port is opened "
      "exclusively; a device still running another (dead) host's output is stopped first.  "
      "--port emu runs the device emulator in-process.  Exit status: 0 done, 1 device or I/O "
      "failure (also: port in use), 2 bad input (nothing started), 128+N after signal N.",
      "stimctl"};
  tp::host::DeliveryRequest r;
  std::string duration;
  int emu_channels = 8;
  bool list = false;
  app.add_option("--port", r.port, "Serial port path, or emu for the in-process emulator [emu]")
      ->type_name("PORT");
  app.add_option("--baud", r.baud, "Baud rate [115200]")->check(CLI::Range(300, 4000000));
  app.add_option("--backend", r.backend,
                 "Serial backend: auto (libserialport; POSIX termios for pseudo-terminals), "
                 "libserialport or posix [auto]")
      ->check(CLI::IsMember({"auto", "libserialport", "posix"}));
  app.add_flag("--list", list, "List serial ports (CSV: port,description) and exit");
  app.add_option("--stimulus", r.stimulus_path, "Stimulus document, - for stdin [-]")
      ->type_name("FILE");
  app.add_option("--duration", duration,
                 "Stop after this long, s, at most 3600 [the stimulus' own duration; live mode: "
                 "until the input ends, at most 3600 s]")
      ->type_name("S");
  app.add_flag(
      "--live", r.live,
      "After starting, read weight frames from stdin as JSON lines {\"currents_mA\": [...]}, "
      "or amplitude frames {\"amplitudes\": [mA, ...]} (one per pattern, each 0 to its "
      "configured amplitude), applied at each pattern's next pulse; needs --stimulus FILE");
  app.add_option("--record", r.record_path,
                 "Emulator only: write each delivered pulse as a JSON line")
      ->type_name("FILE");
  app.add_option("--emu-channels", emu_channels, "Emulator only: channel count, 1 to 64 [8]")
      ->check(CLI::Range(1, 64));
  std::string emu_compliance;
  tp::cli::add_skin_flags(app, "--emu-skin", "--emu-compliance-v", r.emu_skin_path,
                          emu_compliance, "--record", "Emulator only: ");
  app.add_flag("--check-impedance", r.check_impedance,
               "Before starting, probe every electrode the stimulus uses below sensation "
               "(--probe-current) on a device that measures; refuse to start (exit 2, naming "
               "the pad) when a used pad has no contact or the stimulus's peak would need more "
               "than the device's compliance, else print each pad's impedance and contact "
               "(stderr) and start");
  app.add_option("--contact-loss", r.contact_loss,
                 "On a device that measures, what a pad's lost contact does: stop the whole "
                 "output, or suspend only the patterns that drive it (their pulses at the probe's "
                 "current, --probe-current) until a probe finds the contact again, for a finger "
                 "moving over a display [stop]")
      ->type_name("stop|suspend");
  app.add_flag("--hold-sensation", r.hold_sensation,
               "On a device that measures, hold each pattern's pulse energy (sum of Z I^2 T over "
               "its pads) at what it was when the person's threshold was measured, as the skin's "
               "impedance changes: the device scales each pulse's current, up to twice the "
               "amplitude within every limit (docs/skin.md); needs the stimulus's "
               "reference_impedance_kohm (make-pulse --profile); not with --live");
  std::string probe;
  app.add_option("--probe-current", probe,
                 "With --check-impedance or --contact-loss suspend: the probe's current per "
                 "electrode, mA, 0.01 to 0.5 [0.05]")
      ->type_name("MA");
  app.add_option("--latency-log", r.latency_log,
                 "Live mode: write 'n t_ns' per weight frame sent (benchmarks)")
      ->type_name("FILE");

  return tp::cli::run(app, argc, argv, [&] {
    if (list) {
      tp::cli::write_stdout(tp::host::serial_ports_csv());
      return;
    }
    if (app.count("--emu-channels") > 0) r.emu_channels = emu_channels;
    if (!emu_compliance.empty())
      r.emu_compliance_V = tp::parse_finite(emu_compliance, "--emu-compliance-v");
    if (!probe.empty()) r.probe_mA = tp::parse_finite(probe, "--probe-current");
    tp::host::check_delivery(r);
    // A stimulus (make-pulse's) or a mix of patterns (mix-stimuli's).
    const tp::Mix mix = tp::mix_from_json(tp::read_json(r.stimulus_path, "stimulus"));
    tp::check_mix(mix, tp::StimulusLimits{});
    const std::optional<std::string> against = tp::host::thresholds_note(mix);
    if (app.count("--duration") > 0) {
      r.duration_s = tp::parse_finite(duration, "--duration");
      r.duration_given = duration;
    }
    tp::host::SessionOptions opt = tp::host::delivery_session(r);
    // On a terminal, a progress line while the output runs (stderr, overwritten).
    const bool tty = isatty(STDERR_FILENO) == 1;
    bool progress_shown = false;
    if (tty)
      opt.progress = [&](const tp::host::SessionProgress& p) {
        std::fprintf(stderr, "\rstimctl: %s\033[K", tp::host::progress_text(p, r).c_str());
        progress_shown = true;
      };
    // Before the port is opened: from here on every terminating signal is a flag the
    // session honours (nothing starts after it; a running output is stopped first).
    opt.stop = tp::host::StopToken().with_signals(tp::host::install_stop_handlers());
    tp::host::LineSource lines(STDIN_FILENO);  // live mode's frames: JSON lines on stdin
    if (r.live) opt.frames = &lines;
    const auto transport = tp::host::open_delivery(r);
    const tp::host::EmergencyStopArmed armed(transport->native_handle());
    if (against) std::fprintf(stderr, "stimctl: %s\n", against->c_str());
    struct ClearProgress {  // however the run ends, the next message starts a clean line
      const bool& shown;
      ~ClearProgress() {
        if (shown) std::fprintf(stderr, "\r\033[K");
      }
    } clear_progress{progress_shown};
    if (r.check_impedance) {
      const tp::host::ImpedanceCheck check = tp::host::check_impedance(
          *transport, mix, opt, r.probe_mA.value_or(tp::host::kDefaultProbe_mA));
      if (!check.refusal.empty()) tp::bad_input(check.refusal);  // one line, as bad input
      std::fprintf(stderr, "%s", tp::host::impedance_table(check).c_str());
    }
    const tp::host::SessionReport report = tp::host::run_session(*transport, mix, opt);
    if (progress_shown) std::fprintf(stderr, "\r\033[K");
    progress_shown = false;
    if (const auto note = tp::host::preempted_note(report))
      std::fprintf(stderr, "stimctl: %s\n", note->c_str());
    if (const auto note = tp::host::not_started_note(report)) {
      std::fprintf(stderr, "stimctl: %s\n", note->c_str());
      throw tp::Told(static_cast<tp::ExitCode>(report.exit_code), "stopped: " + report.end);
    }
    std::fprintf(stderr, "stimctl: %s\n", tp::host::session_summary(report, mix, r).c_str());
    if (report.exit_code != 0)
      throw tp::Told(static_cast<tp::ExitCode>(report.exit_code), "stopped: " + report.end);
  });
}
