// stimctl: deliver a stimulus document through a stimulator (serial port or emulator).
//
//   optimize-weights --mode SAI | make-pulse --amplitude 1 --frequency 200 | stimctl --port emu
//   --duration 1 stimctl --port /dev/ttyACM0 < stimulus.json producer | stimctl --port /dev/ttyACM0
//   --live --stimulus stimulus.json   # weight frames as JSON lines

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <optional>
#include <string>

#include <unistd.h>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "pulse/thresholds.hpp"
#include "host/live.hpp"
#include "host/session.hpp"
#include "host/signals.hpp"
#include "core/number.hpp"
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
  std::string port = "emu", stimulus_path = "-", duration, record, latency_log, backend = "auto";
  int baud = 115200, emu_channels = 8;
  bool list = false, live = false;
  app.add_option("--port", port, "Serial port path, or emu for the in-process emulator [emu]")
      ->type_name("PORT");
  app.add_option("--baud", baud, "Baud rate [115200]")->check(CLI::Range(300, 4000000));
  app.add_option("--backend", backend,
                 "Serial backend: auto (libserialport; POSIX termios for pseudo-terminals), "
                 "libserialport or posix [auto]")
      ->check(CLI::IsMember({"auto", "libserialport", "posix"}));
  app.add_flag("--list", list, "List serial ports (CSV: port,description) and exit");
  app.add_option("--stimulus", stimulus_path, "Stimulus document, - for stdin [-]")
      ->type_name("FILE");
  app.add_option("--duration", duration,
                 "Stop after this long, s, at most 3600 [the stimulus' own duration; live mode: "
                 "until the input ends, at most 3600 s]")
      ->type_name("S");
  app.add_flag(
      "--live", live,
      "After starting, read weight frames from stdin as JSON lines {\"currents_mA\": [...]}, "
      "or amplitude frames {\"amplitudes\": [mA, ...]} (one per pattern, each 0 to its "
      "configured amplitude), applied at each pattern's next pulse; needs --stimulus FILE");
  app.add_option("--record", record, "Emulator only: write each delivered pulse as a JSON line")
      ->type_name("FILE");
  app.add_option("--emu-channels", emu_channels, "Emulator only: channel count, 1 to 64 [8]")
      ->check(CLI::Range(1, 64));
  app.add_option("--latency-log", latency_log,
                 "Live mode: write 'n t_ns' per weight frame sent (benchmarks)")
      ->type_name("FILE");

  return tp::cli::run(app, argc, argv, [&] {
    if (list) {
      std::string out = "port,description\n";
      for (const std::string& p : tp::host::list_serial_ports()) {
        const auto tab = p.find('\t');
        out += p.substr(0, tab) + "," + p.substr(tab + 1) + "\n";
      }
      tp::cli::write_stdout(out);
      return;
    }
    if (live && stimulus_path == "-")
      tp::bad_input("--live: give the stimulus with --stimulus FILE (stdin carries the frames)");
    if (port != "emu" && !record.empty())
      tp::bad_input("--record: only with --port emu (stim-emu has its own)");
    if (port != "emu" && app.count("--emu-channels") > 0)
      tp::bad_input("--emu-channels: only with --port emu (a device reports its own channels)");
    if (!latency_log.empty() && !live)
      tp::bad_input("--latency-log: only with --live (it logs live frames)");
    // A stimulus (make-pulse's) or a mix of patterns (mix-stimuli's).
    const tp::Mix mix = tp::mix_from_json(tp::read_json(stimulus_path, "stimulus"));
    tp::check_mix(mix, tp::StimulusLimits{});
    const tp::Stimulus& s = mix.patterns[0];
    // The amplitude against the thresholds the document carries (fiber-threshold's, through
    // make-pulse): said before anything is sent.
    std::optional<std::string> against;
    for (std::size_t p = 0; p < mix.patterns.size(); ++p) {
      const auto one = tp::stimulus_against_thresholds(mix.patterns[p]);
      if (one)
        against = (against ? *against + "; " : std::string()) +
                  (mix.single() ? "" : "pattern " + std::to_string(p) + ": ") + *one;
    }
    tp::host::SessionOptions opt;
    opt.live = live;
    opt.latency_log = latency_log;
    if (app.count("--duration") > 0) {
      opt.duration_s = tp::parse_finite(duration, "--duration");
      if (!(opt.duration_s > 0 && opt.duration_s <= opt.limits.max_duration_s))
        tp::bad_input("--duration: " + duration + " s outside (0, " +
                      tp::number_text(opt.limits.max_duration_s) + "] s");
    }
    // On a terminal, a progress line while the output runs (stderr, overwritten).
    const bool tty = isatty(STDERR_FILENO) == 1;
    bool progress_shown = false;
    if (tty)
      opt.progress = [&](const tp::host::SessionProgress& p) {
        std::fprintf(stderr, "\rstimctl: %.1f of %.1f s, %u of %s pulses%s\033[K", p.seconds,
                     p.expected_s, p.pulses, tp::number_text(p.scheduled).c_str(),
                     live ? (", " + std::to_string(p.frames) + " live frames").c_str() : "");
        progress_shown = true;
      };
    // Before the port is opened: from here on every terminating signal is a flag the
    // session honours (nothing starts after it; a running output is stopped first).
    opt.stop = tp::host::StopToken().with_signals(tp::host::install_stop_handlers());
    tp::host::LineSource lines(STDIN_FILENO);  // live mode's frames: JSON lines on stdin
    if (live) opt.frames = &lines;
    tp::host::EmulatorOptions emu;
    emu.caps.channels = static_cast<std::uint8_t>(emu_channels);
    emu.record_path = record;
    const auto transport = tp::host::open_transport(port, baud, emu, backend);
    tp::host::arm_emergency_stop(transport->native_handle());
    if (against) std::fprintf(stderr, "stimctl: %s\n", against->c_str());
    struct ClearProgress {  // however the run ends, the next message starts a clean line
      const bool& shown;
      ~ClearProgress() {
        if (shown) std::fprintf(stderr, "\r\033[K");
      }
    } clear_progress{progress_shown};
    const tp::host::SessionReport r = tp::host::run_session(*transport, mix, opt);
    tp::host::arm_emergency_stop(-1);
    if (progress_shown) std::fprintf(stderr, "\r\033[K");
    progress_shown = false;
    if (r.preempted)
      std::fprintf(stderr,
                   "stimctl: %s was running another session's output (its host is gone): "
                   "stopped it first\n",
                   r.port.c_str());
    if (!r.started) {
      std::fprintf(stderr, "stimctl: %s: %s before the output started; nothing delivered\n",
                   r.port.c_str(), r.end.c_str());
      throw tp::Error(static_cast<tp::ExitCode>(r.exit_code), "stopped: " + r.end);
    }
    // What the device's receiver has lost since it started, when it lost anything
    // (docs/protocol.md, status).
    std::string line;
    if (r.rx_errors || r.line_errors || r.overruns)
      line = " (the device's receiver so far: " + std::to_string(r.rx_errors) +
             " damaged frames, " + std::to_string(r.line_errors) + " bytes with line errors, " +
             std::to_string(r.overruns) + " overruns)";
    const std::string rate = mix.single()
                                 ? "at " + tp::number_text(s.shape.frequency_hz) + " Hz"
                                 : "of " + std::to_string(mix.patterns.size()) + " patterns";
    std::fprintf(stderr,
                 "stimctl: %s: %u of %s pulses on %zu channels %s, peak %s mA, %s s%s, %d "
                 "retransmissions%s; %s; "
                 "output stopped\n",
                 r.port.c_str(), r.pulses, tp::number_text(r.scheduled).c_str(),
                 s.currents_mA.size(), rate.c_str(), tp::number_text(r.peak_mA).c_str(),
                 tp::number_text(std::round(r.seconds * 100) / 100).c_str(),
                 live ? (", " + std::to_string(r.weight_frames) + " live frames").c_str() : "",
                 r.retransmissions, line.c_str(), r.end.c_str());
    if (r.exit_code != 0)
      throw tp::Error(static_cast<tp::ExitCode>(r.exit_code), "stopped: " + r.end);
  });
}
