#pragma once
// stim-emu's request: the emulated device's capabilities and the fault injection, checked
// with the program's messages (docs/programs.md, stim-emu), become the options of
// run_pty_emulator.

#include <cstdint>
#include <optional>
#include <string>

#include "device/protocol.hpp"
#include "host/emulator.hpp"

namespace tp::host {

struct EmulatorRequest {
  int channels = 8;                                     // 1 to 64
  double max_current_mA = 2.0;                          // 0.001 to the device's hard bound
  int dac_bits = 12;                                    // 4 to 16, signed
  int watchdog_ms = 300;                                // the device's bounds
  int max_pulse_rate_hz = device::hard::max_pulse_rate_hz;  // 1 to the hard bound
  double drop = 0.0, corrupt = 0.0;                     // fractions, [0, 1]
  std::optional<double> stall_after_s;                  // [0, 1e6]
  double stall_ms = 0.0;                                // [0, 1e6]
  std::optional<double> disconnect_after_s;             // [0, 1e6]
  double reply_delay_ms = 0.0;                          // [0, 1000]
  std::uint64_t seed = 1;
  std::string record_path, apply_log_path, event_log_path, forward_socket;
  std::string skin_path;                 // --skin: the electrodes' skin (empty: an ideal load)
  std::optional<double> compliance_V;    // --compliance-v, with --skin: 1 to 1000 V [100]
  // The texts the user typed, quoted by the messages that refuse them (stim-emu's flags);
  // empty: the values' numbers are written instead.
  struct Given {
    std::string max_current, stall_after, stall_ms, disconnect_after, reply_delay_ms;
  } given;
};

// Bad input naming the flag (--max-current, --drop, --corrupt, --stall-after, --stall-ms,
// --disconnect-after, --reply-delay-ms, --dac-bits), in that order; else the options, the
// current limit in whole microamperes rounded down (never raised by rounding) and the DAC
// step the device core derives from it.
PtyEmulatorOptions pty_emulator_options(const EmulatorRequest& r);

// stim-emu --skin-block FILE: the request's skin (--skin, required) and compliance, checked as
// pty_emulator_options checks them, written to path as the firmware's simulated board reads
// them (device/skin_block.hpp; scripts/firmware-emu --skin), atomically.  Returns its size.
std::size_t write_skin_block(const EmulatorRequest& r, const std::string& path);

}  // namespace tp::host
