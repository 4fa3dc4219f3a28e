#pragma once
// Emulated stimulators around the portable device core: a pulse recorder, the in-process
// link used by `stimctl --port emu`, and the pseudo-terminal device of `stim-emu`.

#include <cstdint>
#include <cstdio>
#include <string>

#include <memory>
#include <optional>

#include "device/device_core.hpp"
#include "core/files.hpp"
#include "host/transport.hpp"

namespace tp::host {

// Writes one JSON object per delivered pulse (device::format_record, as the firmware's
// monitor does):
//   {"t_s": 0.005, "currents_mA": [...], "net_charge_nC": [...]}
// t_s from the start command; currents are the main phase as the DAC makes them
// (code x step), positive = cathodic; net_charge_nC is the main phase's charge plus the
// balancing phase's, in whole DAC codes.  A shaped pulse's record has its phases
// (duration_us, units) and unit_currents_mA (docs/protocol.md, "Pulse records").
// Each line is written whole as the pulse is delivered (io/files.hpp: LineFile), so a
// killed emulator or host leaves whole lines (save perhaps the last); a write that fails (a full disk) is a
// runtime failure naming the file, thrown once: the record then stays as it is, and the
// caller stops the output.
class PulseRecorder {
 public:
  // Empty path: record nothing.  With a skin, every pulse is measured on it (its voltage and
  // impedance per channel in the record, docs/skin.md).
  explicit PulseRecorder(const std::string& path, const EmulatorSkin& skin = EmulatorSkin{});
  // Records the pulse; with a skin, measures it first and reports the readings to the
  // core (DeviceCore::measured: its guards may end the output before the next pulse).
  void record(const device::DeliveredPulse& p, device::DeviceCore& core);
  // The emulated board's turn at now_us: the core's pulses due, each recorded; and, when the
  // skin presses the stop input (its stop_input events) within a running output, the pulses
  // before it, then DeviceCore::stop_input at its time (the firmware's GPIO stop input).
  void advance(device::DeviceCore& core, std::uint64_t now_us);
  std::uint64_t pulses() const { return pulses_; }
  // The most any pulse came after its time (the time advance() was called for it, less
  // its scheduled start), us: how late the emulator delivers.
  std::uint64_t latest_us() const { return latest_us_; }
  // The pulses that came more than kLateUs after their time (the process was descheduled:
  // an emulator is a user-space program; each is delivered all the same, in order).
  static constexpr std::uint64_t kLateUs = 1000;
  std::uint64_t late() const { return late_; }
  double peak_mA() const { return peak_mA_; }
  bool failed() const { return failed_; }

 private:
  std::optional<LineFile> out_;
  std::shared_ptr<const device::SkinScenario> scenario_;  // keeps skin_'s scenario
  std::optional<device::SimulatedSkin> skin_;
  bool failed_ = false;
  std::uint64_t pulses_ = 0;
  std::uint64_t latest_us_ = 0, late_ = 0;
  double peak_mA_ = 0.0;
};

// The emulators' capabilities: caps, claiming shaped pulses (their PulseRecorder records
// each shaped pulse's phases as delivered), with caps' own max_phases and max_edge_rate_hz
// (by default 16 phases and 160000 edges a second); with a skin, measuring every pulse
// (kFeatureMeasures) at its compliance voltage (to the volt).
device::Capabilities emulator_capabilities(device::Capabilities caps,
                                           const EmulatorSkin& skin = EmulatorSkin{});

struct FaultInjection {
  double drop = 0.0;                 // fraction of bytes dropped, each direction
  double corrupt = 0.0;              // fraction of bytes with one bit flipped, each direction
  double stall_after_s = -1.0;       // stop answering (and reading) at this time after start-up...
  double stall_s = 0.0;              // ... for this long
  double disconnect_after_s = -1.0;  // close the line at this time after start-up
  double reply_delay_s = 0.0;        // answer every request this much later (a slow device)
  std::uint64_t seed = 1;
};

struct PtyEmulatorOptions {
  device::Capabilities caps;
  // Not empty: no built-in device; the line is forwarded to the device on this Unix socket
  // (the firmware in QEMU: scripts/firmware-emu), with the same fault injection.
  std::string forward_socket;
  std::string record_path;
  EmulatorSkin skin;  // --skin, --compliance-v
  std::string apply_log_path;  // "n t_ns" per applied weight frame (benchmarks)
  // "start t_ns wall_ns" / "stop t_ns wall_ns" (CLOCK_MONOTONIC, and CLOCK_REALTIME for
  // a shell's $EPOCHREALTIME) when a host's frame starts or stops the output (tests: a
  // record's t_s is from the start).
  std::string event_log_path;
  FaultInjection faults;
};

// Opens a pseudo-terminal, prints its path on stdout's first line, and runs the device until
// SIGINT/SIGTERM (returns 0) or a fault-injected disconnect.  Output stops first, always.
// With forward_socket, relays the line to that device instead, until it closes the socket;
// the path is printed once the device has answered an identify (a booting device drops
// what arrives too early).
int run_pty_emulator(const PtyEmulatorOptions& opt);

}  // namespace tp::host
