// stim-emu: the stimulator emulator on a pseudo-terminal.  Prints the pty's path on the
// first line of stdout and behaves as the device (docs/protocol.md) until killed.
//
//   stim-emu --record pulses.jsonl > port.txt &
//   stimctl --port "$(head -1 port.txt)" < stimulus.json

#include <cmath>
#include <string>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "device/protocol.hpp"
#include "host/emulator.hpp"
#include "core/number.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Emulates an N-channel stimulator on a pseudo-terminal, running the portable device "
      "core.  Fault injection options exercise the host's error handling.",
      "stim-emu"};
  tp::host::PtyEmulatorOptions o;
  int channels = 8, dac_bits = 12, watchdog_ms = 300,
      max_pulse_rate = tp::device::hard::max_pulse_rate_hz;
  std::string max_current = "2", drop = "0", corrupt = "0", stall_after, stall_ms = "0",
              disconnect_after, reply_delay_ms = "0";
  namespace hard = tp::device::hard;
  tp::cli::add_integer(app, "--channels", channels, "Channels, 1 to 64 [8]", 1,
                       static_cast<int>(tp::device::kMaxChannels));
  app.add_option("--max-current", max_current,
                 "Current limit per channel, mA; at most the device's compile-time bound of 2 "
                 "mA [2]")
      ->type_name("MA");
  tp::cli::add_integer(app, "--dac-bits", dac_bits, "DAC resolution, signed bits, 4 to 16 [12]", 4,
                       16);
  tp::cli::add_integer(app, "--watchdog-ms", watchdog_ms,
                       "Output stops this long after the session's last frame, 10 to 1000 ms [300]",
                       int{hard::min_watchdog_ms}, int{hard::max_watchdog_ms})
      ->type_name("MS");
  tp::cli::add_integer(app, "--max-pulse-rate", max_pulse_rate,
                       "Pulses a second, over every pattern, the device reports it delivers on "
                       "time (its throughput), 1 to 10000 [10000]",
                       1, int{tp::device::hard::max_pulse_rate_hz});
  app.add_option("--record", o.record_path, "Write each delivered pulse as a JSON line")
      ->type_name("FILE");
  app.add_option("--apply-log", o.apply_log_path, "Write 'n t_ns' per applied weight frame")
      ->type_name("FILE");
  app.add_option("--event-log", o.event_log_path,
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
  tp::cli::add_seed(app, "--seed", o.faults.seed,
                    "Seed of the fault injection, 0 to 18446744073709551615 (2^64 - 1) [1]");
  auto* forward =
      app.add_option("--forward", o.forward_socket,
                     "No built-in device: forward the line, with the same fault "
                     "injection, to the device on this Unix socket (the firmware "
                     "in QEMU: scripts/firmware-emu); the path is printed once it answers")
          ->type_name("SOCKET");
  for (const char* device_option : {"--channels", "--max-current", "--dac-bits", "--watchdog-ms",
                                    "--max-pulse-rate", "--record", "--apply-log", "--event-log"})
    forward->excludes(app.get_option(device_option));

  return tp::cli::run(app, argc, argv, [&] {
    const double imax = tp::parse_finite(max_current, "--max-current");
    const double hard_mA = hard::max_current_uA * 1e-3;
    if (!(imax >= 0.001 && imax <= hard_mA))
      tp::bad_input("--max-current: " + max_current + " mA outside [0.001, " +
                    tp::number_text(hard_mA) + "] mA (the device's compile-time bound)");
    auto fraction = [](const std::string& t, const char* what) {
      const double v = tp::parse_finite(t, what);
      if (v < 0 || v > 1)
        tp::bad_input(std::string(what) + ": " + tp::number_beside(v, 0, 1) + " outside [0, 1]");
      return v;
    };
    o.faults.drop = fraction(drop, "--drop");
    o.faults.corrupt = fraction(corrupt, "--corrupt");
    auto seconds = [](const std::string& t, const char* what) {
      const double v = tp::parse_finite(t, what);
      if (v < 0 || v > 1e6) tp::bad_input(std::string(what) + ": " + t + " outside [0, 1e6]");
      return v;
    };
    if (!stall_after.empty()) o.faults.stall_after_s = seconds(stall_after, "--stall-after");
    o.faults.stall_s = seconds(stall_ms, "--stall-ms") * 1e-3;
    if (!disconnect_after.empty())
      o.faults.disconnect_after_s = seconds(disconnect_after, "--disconnect-after");
    o.faults.reply_delay_s = tp::parse_finite(reply_delay_ms, "--reply-delay-ms") * 1e-3;
    if (!(o.faults.reply_delay_s >= 0 && o.faults.reply_delay_s <= 1))
      tp::bad_input("--reply-delay-ms: " + reply_delay_ms + " outside [0, 1000] ms");
    o.caps.channels = static_cast<std::uint8_t>(channels);
    // Whole microamperes, rounded down: the limit is never raised by rounding.
    o.caps.max_current_uA = static_cast<std::uint16_t>(std::floor(imax * 1000 + 1e-9));
    // One code of a signed DAC of dac_bits spanning +-max_current (the device core's rule,
    // which the firmware applies to its own DAC).
    const std::uint32_t step = tp::device::dac_step_nA(o.caps.max_current_uA, dac_bits);
    if (step == 0)  // the protocol's dac_step_nA is 16 bits
      tp::bad_input("--dac-bits " + std::to_string(dac_bits) + " at " + max_current +
                    " mA needs a DAC step over 65535 nA, more than the protocol carries "
                    "(use more bits)");
    o.caps.dac_step_nA = static_cast<std::uint16_t>(step);
    o.caps.watchdog_ms = static_cast<std::uint16_t>(watchdog_ms);
    o.caps.max_pulse_rate_hz = static_cast<std::uint16_t>(max_pulse_rate);
    const int rc = tp::host::run_pty_emulator(o);
    if (rc != 0) tp::failure("emulator stopped");
  });
}
