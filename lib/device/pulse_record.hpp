#pragma once
// What a device delivers in one pulse, and its record: one JSON line, in integers (no
// floating point, no allocation), in the format of stim-emu --record (docs/protocol.md,
// "Pulse records"), with the timing a firmware measured.  Portable: the firmware's
// monitor writes these lines; the host's tests parse them.

#include <cstddef>
#include <cstdint>

#include "device/device_core.hpp"

namespace tp::device {

// The balancing phase's codes: each channel's -code x width / balance_width, the nearest
// code below, then one code up on the channels with the largest remainders (lowest
// channel first on ties) until they sum to zero, as every phase must.  Each is within one
// code of the exact value; with equal widths, exactly -code.  out holds main.size() codes.
void balance_codes(CodeSpan main, std::uint16_t width_us, std::uint16_t balance_width_us,
                   std::int16_t* out);

// What a device measured of each channel at a pulse's main phase's end (a shaped pulse's
// strongest phase, the first of them), none where it carried no current: the board's
// readings (voltage, the current delivered, whether the output stage was at its compliance
// rail) and the impedance the core derives from them (DeviceCore::measured).
struct ElectricalRecord {
  bool carried[kMaxChannels] = {};
  bool at_rail[kMaxChannels] = {};
  std::int32_t voltage_mV[kMaxChannels] = {};
  std::int32_t current_nA[kMaxChannels] = {};  // delivered, + = cathodic
  std::uint32_t impedance_ohm[kMaxChannels] = {};  // kOpenOhm: no current flowed
};

// A record is biphasic (the widths) or, when shape.n > 0, shaped (version 6): main holds the
// base codes, and phase k delivers main[c] x shape.units[k] codes for shape.duration_us[k].
struct PulseRecord {
  std::uint16_t pattern = 0;  // its pattern's index in the table
  std::uint64_t t_us = 0;     // the pulse's start as scheduled (slot + slip), from the start
  std::uint32_t slip_us = 0;  // how long the scheduler deferred it behind another pattern's
  std::uint8_t channels = 0;
  std::int16_t main[kMaxChannels] = {};     // codes of the main phase
  std::int16_t balance[kMaxChannels] = {};  // codes of the balancing phase
  std::uint32_t step_nA = 0;
  std::uint16_t width_us = 0, interphase_us = 0, balance_width_us = 0;  // configured
  // Measured by the device's clock at each edge (a firmware); absent when measured is false.
  bool measured = false;
  std::uint64_t start_us = 0;  // the main phase's first edge, from the start command
  std::uint32_t measured_width_us = 0, measured_interphase_us = 0, measured_balance_us = 0;
  Shape shape;                                         // as configured; n == 0: biphasic
  std::uint32_t measured_duration_us[kMaxPhases] = {};  // each phase, when measured
  std::uint32_t dropped_before = 0;  // records lost before this one (a full monitor line)
  // Measured at the main phase's end (a device that measures, or an emulator with a skin):
  // each channel's voltage and the impedance derived from it; absent when null.  (Apart, so
  // that a record without it costs a firmware nothing to make.)
  const ElectricalRecord* electrical = nullptr;
};

// A delivered pulse's record as an emulator delivers it (no measured timing): its pattern,
// time from the start and slip, main codes and step, and a biphasic pulse's balancing codes
// (balance_codes) and widths, or a shaped pulse's phases as configured.
PulseRecord record_of(const DeliveredPulse& p);

// The longest line format_record writes (64 channels, 16 phases, every field at its widest).
inline constexpr std::size_t kMaxRecordLine = 64 + 2 * kMaxChannels * 24 + 320 + kMaxPhases * 48;
// An electrical record's longest: each channel's voltage ("-2147483.648") and impedance
// ("4294967.295") too.
inline constexpr std::size_t kMaxElectricalRecordLine = kMaxRecordLine + 64 + kMaxChannels * 28;

// Writes the record as one JSON line ending in '\n' into out (capacity kMaxRecordLine at
// least, kMaxElectricalRecordLine for an electrical record); returns its length.  width_us, interphase_us and balance_width_us are the
// measured ones when measured, else the configured ones.  currents_mA: main codes x step;
// net_charge_nC: main x width + balance x balance width, per channel, as delivered.
// An electrical record adds "voltage_V" and "impedance_kohm", one per channel (null where
// it carried no current), before start_us.
// A shaped record has instead "phases": [{"duration_us", "units"}, ...] (measured
// durations when measured), "unit_currents_mA": base code x step (phase k's current is
// that x units), and net_charge_nC: base x step x sum units x duration (as configured), each
// exact whatever the record holds.
std::size_t format_record(const PulseRecord& r, char* out);

}  // namespace tp::device
