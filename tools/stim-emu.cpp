// stim-emu: the stimulator emulator on a pseudo-terminal.  Prints the pty's path on the
// first line of stdout and behaves as the device (docs/protocol.md) until killed.
//
//   stim-emu --record pulses.jsonl > port.txt &
//   stimctl --port "$(head -1 port.txt)" < stimulus.json

#include <cstdio>
#include <string>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "device/protocol.hpp"
#include "host/emulator_request.hpp"
#include "core/number.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Emulates an N-channel stimulator on a pseudo-terminal, running the portable device "
      "core.  Fault injection options exercise the host's error handling.",
      "stim-emu"};
  tp::host::EmulatorRequest r;
  std::string max_current = "2", drop = "0", corrupt = "0", stall_after, stall_ms = "0",
              disconnect_after, reply_delay_ms = "0";
  namespace hard = tp::device::hard;
  tp::cli::add_integer(app, "--channels", r.channels, "Channels, 1 to 64 [8]", 1,
                       static_cast<int>(tp::device::kMaxChannels));
  app.add_option("--max-current", max_current,
                 "Current limit per channel, mA; at most the device's compile-time bound of 2 "
                 "mA [2]")
      ->type_name("MA");
  tp::cli::add_integer(app, "--dac-bits", r.dac_bits, "DAC resolution, signed bits, 4 to 16 [12]",
                       4, 16);
  tp::cli::add_integer(app, "--watchdog-ms", r.watchdog_ms,
                       "Output stops this long after the session's last frame, 10 to 1000 ms [300]",
                       int{hard::min_watchdog_ms}, int{hard::max_watchdog_ms})
      ->type_name("MS");
  tp::cli::add_integer(app, "--max-pulse-rate", r.max_pulse_rate_hz,
                       "Pulses a second, over every pattern, the device reports it delivers on "
                       "time (its throughput), 1 to 10000 [10000]",
                       1, int{tp::device::hard::max_pulse_rate_hz});
  std::string compliance;
  tp::cli::add_skin_flags(app, "--skin", "--compliance-v", r.skin_path, compliance,
                          "the record", "");
  std::string skin_block;
  auto* block = app.add_option("--skin-block", skin_block,
                               "Write the skin (--skin, --compliance-v) as the firmware's "
                               "simulated board reads it (scripts/firmware-emu --skin), then exit")
                    ->type_name("FILE");
  app.add_option("--record", r.record_path, "Write each delivered pulse as a JSON line")
      ->type_name("FILE");
  app.add_option("--apply-log", r.apply_log_path, "Write 'n t_ns' per applied weight frame")
      ->type_name("FILE");
  app.add_option("--event-log", r.event_log_path,
                 "Write 'start t_ns wall_ns' and 'stop t_ns wall_ns' (CLOCK_MONOTONIC, "
                 "CLOCK_REALTIME) as a host's frames start and stop the output")
      ->type_name("FILE");
  app.add_option("--drop", drop, "Fraction of bytes to drop, each direction [0]")->type_name("P");
  app.add_option("--corrupt", corrupt, "Fraction of bytes to corrupt, each direction [0]")
      ->type_name("P");
  app.add_option("--stall-after", stall_after, "Stop reading and answering after S seconds...")
      ->type_name("S");
  app.add_option("--stall-ms", stall_ms, "... for this many milliseconds [0]")->type_name("MS");
  app.add_option("--disconnect-after", disconnect_after, "Close the line after S seconds")
      ->type_name("S");
  app.add_option("--reply-delay-ms", reply_delay_ms,
                 "Answer every request this much later, 0 to 1000 ms (a slow device) [0]")
      ->type_name("MS");
  tp::cli::add_seed(app, "--seed", r.seed,
                    "Seed of the fault injection, 0 to 18446744073709551615 (2^64 - 1) [1]");
  auto* forward =
      app.add_option("--forward", r.forward_socket,
                     "No built-in device: forward the line, with the same fault "
                     "injection, to the device on this Unix socket (the firmware "
                     "in QEMU: scripts/firmware-emu); the path is printed once it answers")
          ->type_name("SOCKET");
  for (const char* device_option : {"--channels", "--max-current", "--dac-bits", "--watchdog-ms",
                                    "--max-pulse-rate", "--record", "--apply-log", "--event-log",
                                    "--skin", "--compliance-v"})
    forward->excludes(app.get_option(device_option));
  forward->excludes(block);

  return tp::cli::run(app, argc, argv, [&] {
    r.given = {max_current, stall_after, stall_ms, disconnect_after, reply_delay_ms};
    r.max_current_mA = tp::parse_finite(max_current, "--max-current");
    r.drop = tp::parse_finite(drop, "--drop");
    r.corrupt = tp::parse_finite(corrupt, "--corrupt");
    if (!stall_after.empty()) r.stall_after_s = tp::parse_finite(stall_after, "--stall-after");
    r.stall_ms = tp::parse_finite(stall_ms, "--stall-ms");
    if (!disconnect_after.empty())
      r.disconnect_after_s = tp::parse_finite(disconnect_after, "--disconnect-after");
    r.reply_delay_ms = tp::parse_finite(reply_delay_ms, "--reply-delay-ms");
    if (!compliance.empty()) r.compliance_V = tp::parse_finite(compliance, "--compliance-v");
    if (!skin_block.empty()) {
      const std::size_t n = tp::host::write_skin_block(r, skin_block);
      std::fprintf(stderr, "stim-emu: wrote the skin block (%zu bytes) to %s\n", n,
                   skin_block.c_str());
      return;
    }
    const int rc = tp::host::run_pty_emulator(tp::host::pty_emulator_options(r));
    if (rc != 0) tp::failure("emulator stopped");
  });
}
