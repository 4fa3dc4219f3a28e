// stim-emu: the stimulator emulator on a pseudo-terminal.  Prints the pty's path on the
// first line of stdout and behaves as the device (docs/protocol.md) until killed.
//
//   stim-emu --record pulses.jsonl > port.txt &
//   stimctl --port "$(head -1 port.txt)" < stimulus.json

#include <cmath>
#include <string>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "host/emulator.hpp"
#include "io/number.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Emulates an N-channel stimulator on a pseudo-terminal, running the portable device "
      "core.  Fault injection options exercise the host's error handling.",
      "stim-emu"};
  tp::host::PtyEmulatorOptions o;
  int channels = 8, dac_bits = 12, watchdog_ms = 300;
  std::string max_current = "2", drop = "0", corrupt = "0", stall_after, stall_ms = "0",
              disconnect_after;
  app.add_option("--channels", channels, "Channels [8]")->check(CLI::Range(1, 64));
  app.add_option("--max-current", max_current, "Current limit per channel, mA [2]")
      ->type_name("MA");
  app.add_option("--dac-bits", dac_bits, "DAC resolution, signed bits [12]")
      ->check(CLI::Range(4, 16));
  app.add_option("--watchdog-ms", watchdog_ms,
                 "Output stops this long after the last valid frame [300]")
      ->check(CLI::Range(10, 60000));
  app.add_option("--record", o.record_path, "Write each delivered pulse as a JSON line")
      ->type_name("FILE");
  app.add_option("--apply-log", o.apply_log_path, "Write 'n t_ns' per applied weight frame")
      ->type_name("FILE");
  app.add_option("--drop", drop, "Fraction of bytes to drop, each direction [0]")->type_name("P");
  app.add_option("--corrupt", corrupt, "Fraction of bytes to corrupt, each direction [0]")
      ->type_name("P");
  app.add_option("--stall-after", stall_after, "Stop reading and answering after S seconds...")
      ->type_name("S");
  app.add_option("--stall-ms", stall_ms, "... for this many milliseconds [0]")->type_name("MS");
  app.add_option("--disconnect-after", disconnect_after, "Close the line after S seconds")
      ->type_name("S");
  app.add_option("--seed", o.faults.seed, "Seed of the fault injection [1]");

  return tp::cli::run(app, argc, argv, [&] {
    const double imax = tp::parse_finite(max_current, "--max-current");
    if (!(imax > 0 && imax <= 30)) tp::bad_input("--max-current: must be in (0, 30] mA");
    auto fraction = [](const std::string& t, const char* what) {
      const double v = tp::parse_finite(t, what);
      if (v < 0 || v > 1) tp::bad_input(std::string(what) + ": must be in [0, 1]");
      return v;
    };
    o.faults.drop = fraction(drop, "--drop");
    o.faults.corrupt = fraction(corrupt, "--corrupt");
    if (!stall_after.empty())
      o.faults.stall_after_s = tp::parse_finite(stall_after, "--stall-after");
    o.faults.stall_s = tp::parse_finite(stall_ms, "--stall-ms") * 1e-3;
    if (!disconnect_after.empty())
      o.faults.disconnect_after_s = tp::parse_finite(disconnect_after, "--disconnect-after");
    o.caps.channels = static_cast<std::uint8_t>(channels);
    o.caps.max_current_uA = static_cast<std::uint16_t>(std::lround(imax * 1000));
    // One code of a signed DAC of dac_bits spanning +-max_current.
    o.caps.dac_step_nA = static_cast<std::uint16_t>(
        std::max(1L, std::lround(imax * 1e6 / ((1 << (dac_bits - 1)) - 1))));
    o.caps.watchdog_ms = static_cast<std::uint16_t>(watchdog_ms);
    const int rc = tp::host::run_pty_emulator(o);
    if (rc != 0) tp::failure("emulator stopped");
  });
}
