#pragma once
// Messages of the stimulator protocol (docs/protocol.md), version 7.  Portable: no OS
// calls and, in what the device core uses, no allocation (the std::vector forms at the end
// are the host's, in protocol_buffers.cpp, which the firmware does not build).  All multi-byte
// fields are little-endian.  Currents travel as signed DAC codes; a positive code is cathodic.
//
// Sessions: a host opens a session with `configure`, which carries a random, non-zero
// 32-bit token.  set_weights, start and keepalive carry the same token; the device refuses
// them (wrong_session) unless it is the current session's, and only frames of the session
// that started the output feed the watchdog.  `stop` ends the session (it disarms: the
// configuration, weights and token are forgotten), so a replayed `start` cannot restart an
// old stimulus.
//
// Patterns (version 4): a session holds a table of patterns, each its own codes (stored
// sparse: only its non-zero channels), pulse shape, period, phase and pulse count, which
// the device interleaves (scheduler.hpp).  `configure` is a table of one pattern whose
// codes set_weights gives (version 3's messages, unchanged); configure_table, set_pattern
// and set_codes build larger ones; set_amplitudes scales patterns down live.
//
// Shaped pulses (version 6): set_shape gives a pattern a pulse of up to kMaxPhases
// piecewise-constant phases, each a duration and a level in integer units.  The pattern's
// codes are then base codes b_c (summing to zero over the channels, as every pattern's
// do): channel c delivers b_c x units_k in phase k, so the current stays local at every
// instant, and the net charge of every channel is b_c x sum_k units_k x duration_k, zero
// for all channels exactly when that one sum is (the device refuses it otherwise,
// charge_not_zero).  Version 5's messages keep their bytes and their meaning.
//
// Measurements (version 7, issue 41): a device that measures every pulse (features bit 1)
// reports its compliance voltage, takes the electrodes' area and the density limit
// (set_guards), guards each electrode from its own measurements (lost contact, compliance,
// charge density on the contact area it estimates: Fault::contact, compliance, density)
// and answers `measurements` with each channel's last reading, its baseline and what
// stopped the output.  Version 6's messages keep their bytes and their meaning.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "device/frame.hpp"
#include "device/scheduler.hpp"

namespace tp::device {

inline constexpr std::uint8_t kProtocolVersion = 7;
// The oldest version a host still speaks to (it gives such a device biphasic pulses only).
inline constexpr std::uint8_t kOldestProtocolVersion = 5;
// The most phases a shaped pulse has (set_shape).
inline constexpr std::size_t kMaxPhases = 16;
// Capabilities::features: the device delivers shaped pulses (set_shape); without it,
// set_shape is refused (not_supported).
inline constexpr std::uint8_t kFeatureShapedPulses = 0x01;
// Capabilities::features: the device measures each channel's voltage and current at every
// pulse's main phase's end and guards the electrodes from them (version 7).
inline constexpr std::uint8_t kFeatureMeasures = 0x02;

// The most channels a set_weights frame carries: token (4) + count (1) + 2 bytes a code
// must fit kMaxPayload; 64 is the supported maximum (the host's arrays have at most 64
// electrodes).  Both ends refuse more.
inline constexpr std::size_t kMaxChannels = 64;
static_assert(5 + 2 * kMaxChannels <= kMaxPayload, "a set_weights frame must carry every channel");
// The sparse codes of every pattern of a table share this many entries (a channel and a
// code each): 256 patterns of 32 non-zero channels, a display's bank of focal pixels.
inline constexpr std::size_t kCodePool = 8192;
static_assert(7 + 3 * kMaxChannels <= kMaxPayload, "a set_codes frame must carry every channel");
// An amplitude scale of 1: a pattern's codes as configured.
inline constexpr std::uint16_t kFullScale = 32768;

// The device's compile-time safety bounds.  A device's configured capabilities (its
// Capabilities) can only lower them: DeviceCore clamps what it is given to these.
namespace hard {
inline constexpr std::uint16_t max_current_uA = 2000;  // per channel, either phase
inline constexpr std::uint16_t min_width_us = 10;
inline constexpr std::uint16_t max_width_us = 1000;
inline constexpr std::uint16_t max_balance_width_us = 8000;
inline constexpr std::uint16_t max_rate_hz = 1000;
inline constexpr std::uint32_t max_period_us = 10000000;  // 10 s: rates down to 0.1 Hz
inline constexpr std::uint16_t min_watchdog_ms = 10;
inline constexpr std::uint16_t max_watchdog_ms = 1000;
inline constexpr std::int32_t max_dac_code = 32767;  // a 16-bit signed DAC
// Between pulses of different patterns (docs/protocol.md, "Scheduling").
inline constexpr std::uint16_t min_gap_us = 100;
// The most a pulse may be deferred behind another pattern's: tables that could defer more
// are refused.
inline constexpr std::uint16_t max_slip_us = 1000;
// Per electrode, summed over every pattern of a table (docs/safety.md): the RMS current
// and the mean absolute current (the charge per second both phases carry).
inline constexpr std::uint16_t max_rms_uA = 1000;
inline constexpr std::uint16_t max_mean_uA = 800;
// Pulses per second over every pattern of a table: what no device claims to sustain above
// (a device reports its own, lower, measured throughput: Capabilities::max_pulse_rate_hz).
inline constexpr std::uint16_t max_pulse_rate_hz = 10000;
// Edges per second over every pattern of a table (a pulse of n phases has n + 1): a
// 17-edge pulse at max_pulse_rate_hz.
inline constexpr std::uint32_t max_edge_rate_hz = 170000;
// The largest |units| of one phase of a shape: a phase delivers base code x units.
inline constexpr std::int16_t max_units = 1024;
}  // namespace hard

enum class Msg : std::uint8_t {
  identify = 0x01,         // -> ack + Capabilities
  configure = 0x02,        // session u32, PulseConfig -> ack (opens the session)
  set_weights = 0x03,      // session u32, count u8, count x int16 codes -> ack
  start = 0x04,            // session u32 -> ack
  stop = 0x05,             // (anything) -> ack; always honoured, ends the session
  status = 0x06,           // -> ack + Status (a query: never feeds the watchdog)
  keepalive = 0x07,        // session u32 -> ack + Status
  // first u8, n u8 -> ack + MeasurementsHead + n x ChannelMeasurement (a query, version 7)
  measurements = 0x08,
  configure_table = 0x10,  // session u32, patterns u16, channels u8, gap_us u16 -> ack
  set_pattern = 0x11,      // session u32, index u16, PatternTiming -> ack
  set_codes = 0x12,        // session u32, index u16, n u8, n x (channel u8, code i16) -> ack
  set_amplitudes = 0x13,   // session u32, first u16, n u8, n x scale u16 -> ack
  // session u32, index u16, period_us u32, phase_us u32, max_pulses u32, n u8,
  // n x (duration_us u16, units i16) -> ack (version 6: a pattern's timing, shaped)
  set_shape = 0x14,
  set_guards = 0x15,       // session u32, Guards -> ack (version 7)
  set_hold = 0x16,         // session u32, index u16, energy_ref u64 -> ack (version 7)
  ack = 0x80,              // device -> host: acked type u8, Result u8, body
};

enum class Result : std::uint8_t {
  ok = 0,
  unknown_type = 1,
  bad_length = 2,
  out_of_range = 3,      // a width, rate or current outside the device's limits
  not_configured = 4,    // set_weights/start before configure, start before set_weights
  sum_not_zero = 5,      // channel codes do not sum to zero
  channel_mismatch = 6,  // more channels than the device has, or not the configured count
  bad_state = 7,         // configure while running
  wrong_session = 8,     // the token is not the current session's (another host's, or stopped)
  table_full = 9,        // more patterns, or more sparse codes, than the device holds
  no_pattern = 10,       // a pattern index outside the table
  charge_not_zero = 11,  // a shape's sum of units x duration is not zero (version 6)
  not_supported = 12,    // the device cannot deliver this (a shape: features bit 0 clear)
};
const char* to_string(Result r);

enum class State : std::uint8_t { idle = 0, running = 1 };
enum class Fault : std::uint8_t {
  none = 0,
  watchdog = 1,
  link_lost = 2,
  completed = 3,
  stopped = 4,
  output_fault = 5,  // the device's output stage failed (a firmware's DAC): it delivers no more
  overrun = 6,       // the device could not deliver a pulse on time: the output stopped
  // Version 7's guards (a device that measures): the output stopped at a pulse that showed
  contact = 7,     // an electrode without contact (or with less than Guards::lost_contact)
  compliance = 8,  // an electrode needing more than the compliance voltage: not delivered
  density = 9,     // a charge density on the estimated contact area above Shannon's k
  // The board's stop input (a firmware's GPIO interrupt, an emulator's scripted equivalent)
  // opened the electrode switches: the output is latched off until a new session starts.
  stop_input = 10
};
inline constexpr Fault kLastFault = Fault::stop_input;
const char* to_string(Fault f);

struct Capabilities {
  std::uint8_t protocol = kProtocolVersion;
  std::uint8_t channels = 8;
  std::uint16_t max_current_uA = 2000;  // per channel, either phase
  std::uint16_t dac_step_nA = 977;      // one DAC code (12-bit signed over +-2 mA)
  std::uint16_t min_width_us = 10;
  std::uint16_t max_width_us = 1000;
  std::uint16_t max_balance_width_us = 8000;
  std::uint16_t max_rate_hz = 1000;
  std::uint16_t watchdog_ms = 300;  // output stops this long after the session's last frame
  std::uint8_t fw_major = 0, fw_minor = 4, fw_patch = 0;
  // Version 4: the pattern table and the bounds across patterns.
  std::uint16_t max_patterns = kMaxPatterns;
  std::uint16_t code_pool = static_cast<std::uint16_t>(kCodePool);
  std::uint16_t min_gap_us = hard::min_gap_us;
  std::uint16_t max_slip_us = hard::max_slip_us;
  std::uint16_t max_rms_uA = hard::max_rms_uA;
  std::uint16_t max_mean_uA = hard::max_mean_uA;
  // Version 5: the pulses per second, over every pattern, that the device delivers on time
  // (its measured throughput): a start that asks more is refused.
  std::uint16_t max_pulse_rate_hz = hard::max_pulse_rate_hz;
  // Version 6: shaped pulses.  The most phases of a shape; kFeature* bits (none unless a
  // device claims them: a device sets kFeatureShapedPulses only when its output stage
  // delivers shapes phase by phase); the edges per second over every pattern it delivers on
  // time (a start that asks more is refused).  A version 5 device reads as 0 phases, no
  // features and 4 edges a pulse at its max_pulse_rate_hz (decode_capabilities).
  std::uint8_t max_phases = static_cast<std::uint8_t>(kMaxPhases);
  std::uint8_t features = 0;
  std::uint32_t max_edge_rate_hz = 160000;
  // Version 7: the output stage's compliance voltage (0: not known; a version 6 device
  // reads as 0).
  std::uint16_t compliance_V = 0;
  bool shaped_pulses() const { return (features & kFeatureShapedPulses) != 0; }
  bool measures() const { return (features & kFeatureMeasures) != 0; }
  // The largest code: max_current_uA / dac_step_nA, never above a 16-bit DAC's.
  std::int32_t max_code() const;
};

// The capabilities a device may claim: `c` lowered to the compile-time bounds (hard::).
Capabilities within_hard_limits(Capabilities c);

struct PulseConfig {
  std::uint32_t period_us = 5000;
  std::uint16_t width_us = 200;
  std::uint16_t interphase_us = 0;
  std::uint16_t balance_width_us = 200;
  std::uint8_t channels = 8;
  std::uint32_t max_pulses = 0;  // the device stops by itself after this many; 0: no limit
};

struct Status {
  State state = State::idle;
  Fault fault = Fault::none;
  std::uint32_t pulses = 0;  // delivered since the last start: slots not delivered do not count
  std::uint32_t weight_updates = 0;
  std::uint16_t rx_errors = 0;    // damaged frames dropped
  std::uint16_t line_errors = 0;  // bytes received with a framing, noise or parity error
  std::uint16_t overruns = 0;     // bytes lost: receiver overrun or receive buffer full
  std::uint32_t max_slip_us = 0;  // the largest deferral of any pulse since the last start
  std::uint32_t deferred = 0;     // pulses deferred behind another pattern's
};

// The electrodes' guards (set_guards, version 7): what a device that measures needs beyond
// its own readings.  Ranges (docs/safety.md, "Measured guards"): area 0.0001 to 4000 mm^2
// (100 to 4 x 10^9 um^2), k 0.5 to 2.5, lost contact 0.01 to 0.9.
struct Guards {
  std::uint32_t area_um2 = 0;          // each electrode's area; 0: no density guard
  std::uint16_t shannon_k_milli = 1850;  // Shannon's k x 1000 (R. V. Shannon 1992: 1.85)
  // A pad whose estimated contact (its baseline impedance over its impedance, or its
  // delivered current over the asked one at the compliance rail) is below this, x 1000, has
  // lost contact.
  std::uint16_t lost_contact_milli = 100;
  // What a pad's lost contact does: stop the whole output (0), or (kGuardSuspend) pause
  // only the patterns that drive it, delivering their pulses scaled down to at most
  // probe_uA (10 to 500) on every pad until such a probe finds the contact again.
  std::uint16_t probe_uA = 50;
  std::uint8_t flags = 0;
};
inline constexpr std::uint8_t kGuardSuspend = 0x01;
inline constexpr std::size_t kGuardsSize = 11;
inline constexpr std::uint32_t kMinGuardAreaUm2 = 100;  // 0.0001 mm^2
inline constexpr std::uint32_t kMaxGuardAreaUm2 = 4000000000u;  // 4000 mm^2

// set_hold (version 7): a pattern's pulse energy held as the skin changes (stimctl
// --hold-sensation; docs/skin.md, "Sensation held").  energy_ref is the pattern's
// sum over its channels of Z_ref,c x code_c^2 at its codes as uploaded (Z in units of
// kHoldOhmUnit ohm, each at most kHoldMaxOhm): at each pulse the device scales the pattern
// by its amplitude x sqrt(energy_ref / the same sum with each channel's last impedance),
// never above its codes as uploaded (Tachi et al. 1977: equal sensation at equal pulse
// energy, the integral of Z I^2).  0: not held.
inline constexpr std::uint32_t kHoldOhmUnit = 4;
inline constexpr std::uint32_t kHoldMaxOhm = 1u << 24;
inline constexpr std::size_t kHoldSize = 10;  // index u16, energy_ref u64

// One channel's last reading (measurements, version 7).
struct ChannelMeasurement {
  bool carried = false;   // it carried current in the pulse measured
  bool at_rail = false;   // its voltage was at the compliance rail: not delivered as asked
  bool suspended = false; // lost contact: its patterns are paused (kGuardSuspend)
  std::int32_t voltage_mV = 0;       // at the main phase's end
  std::uint32_t impedance_ohm = 0;   // |V / I delivered|; kOpenOhm: no current flowed
  std::uint32_t baseline_ohm = 0;    // the lowest impedance this output (0: none yet)
};
inline constexpr std::size_t kChannelMeasurementSize = 13;
inline constexpr std::uint32_t kOpenOhm = 0xFFFFFFFFu;
inline constexpr std::uint8_t kNoChannel = 0xFF;  // a trip of no channel (the stop input)
// What stopped the output, and the count of pulses measured since the start.
struct MeasurementsHead {
  std::uint32_t measured = 0;  // pulses measured since the last start
  std::uint32_t suspended = 0;  // pulses delivered at the probe (kGuardSuspend) since then
  Fault trip = Fault::none;    // contact, compliance, density or stop_input; none
  std::uint8_t trip_channel = 0;  // kNoChannel: the stop input
  std::uint32_t trip_t_us = 0;  // the tripping pulse's start (the stop input's time), from the output's start
  std::uint32_t trip_ohm = 0;   // the channel's impedance then (kOpenOhm: no current)
  std::uint8_t first = 0, n = 0;  // the channels that follow
};
inline constexpr std::size_t kMeasurementsHeadSize = 20;
// The most channels one measurements reply carries (within kMaxPayload with its ack).
inline constexpr std::size_t kMeasurementsPerReply = 13;

// A shaped pulse (set_shape): n phases, phase k lasting duration_us[k] at units[k] x each
// channel's base code.  n == 0: not shaped (the pattern's biphasic widths).
struct Shape {
  std::uint8_t n = 0;
  std::uint16_t duration_us[kMaxPhases] = {};
  std::int16_t units[kMaxPhases] = {};
  // The strongest phase (the largest |units|, the first of them; 0 when n == 0): the one a
  // device that measures samples at its end.
  std::size_t strongest() const {
    std::size_t best = 0;
    int most = 0;
    for (std::size_t k = 0; k < n && k < kMaxPhases; ++k) {
      const int u = units[k] < 0 ? -units[k] : units[k];
      if (u > most) {
        most = u;
        best = k;
      }
    }
    return best;
  }
};

// A pattern's timing (set_pattern, set_shape): its pulse shape, period, phase (its first
// slot after the start) and pulse count (0: no limit).  A shaped pattern (shape.n > 0)
// has no widths (0): its phases are its shape.
struct PatternTiming {
  std::uint32_t period_us = 5000;
  std::uint32_t phase_us = 0;
  std::uint16_t width_us = 200;
  std::uint16_t interphase_us = 0;
  std::uint16_t balance_width_us = 200;
  std::uint32_t max_pulses = 0;
  Shape shape;
  bool shaped() const { return shape.n != 0; }
  // The pulse's length: its phases' durations summed.
  std::uint32_t length_us() const;
  // The largest |units| of its phases (the peak is |base code| x this); 1 when biphasic
  // (its balancing codes are never larger than the main phase's).
  std::int32_t max_units() const;
  // Edges a pulse has: phases + 1 (a biphasic pulse: 3, or 4 with a gap).
  std::uint32_t edges() const;
};

// Little-endian fields, appended to any byte buffer with push_back (a FixedBytes in the
// device, a std::vector in the host).
template <class B>
void put_u16(B& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v & 0xFF));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}
template <class B>
void put_u32(B& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
}
std::uint16_t get_u16(const std::uint8_t* p);
std::uint32_t get_u32(const std::uint8_t* p);

inline constexpr std::size_t kCapabilitiesSize = 41;
inline constexpr std::size_t kCapabilitiesSizeV6 = 39;
inline constexpr std::size_t kCapabilitiesSizeV5 = 33;
inline constexpr std::size_t kConfigSize = 15;
inline constexpr std::size_t kTimingSize = 18;
inline constexpr std::size_t kStatusSize = 24;

template <class B>
void put_capabilities(B& b, const Capabilities& c) {
  b.push_back(c.protocol);
  b.push_back(c.channels);
  put_u16(b, c.max_current_uA);
  put_u16(b, c.dac_step_nA);
  put_u16(b, c.min_width_us);
  put_u16(b, c.max_width_us);
  put_u16(b, c.max_balance_width_us);
  put_u16(b, c.max_rate_hz);
  put_u16(b, c.watchdog_ms);
  b.push_back(c.fw_major);
  b.push_back(c.fw_minor);
  b.push_back(c.fw_patch);
  put_u16(b, c.max_patterns);
  put_u16(b, c.code_pool);
  put_u16(b, c.min_gap_us);
  put_u16(b, c.max_slip_us);
  put_u16(b, c.max_rms_uA);
  put_u16(b, c.max_mean_uA);
  put_u16(b, c.max_pulse_rate_hz);
  b.push_back(c.max_phases);
  b.push_back(c.features);
  put_u32(b, c.max_edge_rate_hz);
  put_u16(b, c.compliance_V);
}
template <class B>
void put_timing(B& b, const PatternTiming& t) {
  put_u32(b, t.period_us);
  put_u32(b, t.phase_us);
  put_u16(b, t.width_us);
  put_u16(b, t.interphase_us);
  put_u16(b, t.balance_width_us);
  put_u32(b, t.max_pulses);
}
template <class B>
void put_config(B& b, const PulseConfig& c) {
  put_u32(b, c.period_us);
  put_u16(b, c.width_us);
  put_u16(b, c.interphase_us);
  put_u16(b, c.balance_width_us);
  b.push_back(c.channels);
  put_u32(b, c.max_pulses);
}
template <class B>
void put_status(B& b, const Status& s) {
  b.push_back(static_cast<std::uint8_t>(s.state));
  b.push_back(static_cast<std::uint8_t>(s.fault));
  put_u32(b, s.pulses);
  put_u32(b, s.weight_updates);
  put_u16(b, s.rx_errors);
  put_u16(b, s.line_errors);
  put_u16(b, s.overruns);
  put_u32(b, s.max_slip_us);
  put_u32(b, s.deferred);
}

template <class B>
void put_guards(B& b, const Guards& g) {
  put_u32(b, g.area_um2);
  put_u16(b, g.shannon_k_milli);
  put_u16(b, g.lost_contact_milli);
  put_u16(b, g.probe_uA);
  b.push_back(g.flags);
}
template <class B>
void put_measurements_head(B& b, const MeasurementsHead& h) {
  put_u32(b, h.measured);
  put_u32(b, h.suspended);
  b.push_back(static_cast<std::uint8_t>(h.trip));
  b.push_back(h.trip_channel);
  put_u32(b, h.trip_t_us);
  put_u32(b, h.trip_ohm);
  b.push_back(h.first);
  b.push_back(h.n);
}
template <class B>
void put_channel_measurement(B& b, const ChannelMeasurement& m) {
  b.push_back(static_cast<std::uint8_t>((m.carried ? 1 : 0) | (m.at_rail ? 2 : 0) |
                                        (m.suspended ? 4 : 0)));
  put_u32(b, static_cast<std::uint32_t>(m.voltage_mV));
  put_u32(b, m.impedance_ohm);
  put_u32(b, m.baseline_ohm);
}
// set_guards' body after the token; false when the length is wrong.
bool decode_guards(const std::uint8_t* p, std::size_t n, Guards& out);
// Within the documented ranges (0 area: no density guard).
bool guards_in_range(const Guards& g);

std::optional<PulseConfig> decode_config(const std::uint8_t* p, std::size_t n);
std::optional<PatternTiming> decode_timing(const std::uint8_t* p, std::size_t n);

// set_shape's body after the token and the index: period_us u32 | phase_us u32 |
// max_pulses u32 | n u8 | n x (duration_us u16, units i16), 13 + 4n bytes.
inline constexpr std::size_t kShapeHeadSize = 13;
// The timing it gives (no widths; the shape's phases); false when the length disagrees with
// n, or n is 0 or above kMaxPhases.
bool decode_shape_pattern(const std::uint8_t* p, std::size_t n, PatternTiming& out);
template <class B>
void put_shape_pattern(B& b, const PatternTiming& t) {
  put_u32(b, t.period_us);
  put_u32(b, t.phase_us);
  put_u32(b, t.max_pulses);
  b.push_back(t.shape.n);
  for (std::size_t k = 0; k < t.shape.n && k < kMaxPhases; ++k) {
    put_u16(b, t.shape.duration_us[k]);
    put_u16(b, static_cast<std::uint16_t>(t.shape.units[k]));
  }
}
// A shape's own rules, shared by host and device (the device refuses with this result):
//  - not_supported unless the device delivers shapes (caps.shaped_pulses());
//  - bad_length unless 1 <= n <= caps.max_phases (and kMaxPhases);
//  - out_of_range unless every phase lasts min_width_us to max_balance_width_us (a
//    zero-level phase is a gap and gets the same rule), every |units| <= hard::max_units,
//    some phase is not zero, and every phase at the largest |units| lasts at most
//    max_width_us (a biphasic pulse's main-phase rule);
//  - charge_not_zero unless sum_k units_k x duration_k == 0, exactly: every channel's net
//    charge is its base code times that sum.
// The period, off time and loads are the pattern's rules (check_timing in the device).
Result check_shape(const Shape& s, const Capabilities& caps);
// Phase k's codes: base x units[k], each channel (the caller has checked the peak:
// |base| x max|units| <= the largest code, so nothing wraps).
void shape_codes(const std::int16_t* base, std::size_t n, const Shape& s, std::size_t k,
                 std::int16_t* out);
// A version-3 configuration as the timing of a table's one pattern.
PatternTiming timing_of(const PulseConfig& c);
// Pulses per second over n patterns, in thousandths (each 10^9 / period rounded up):
// exact in integers, for the device's throughput check (Capabilities::max_pulse_rate_hz).
std::uint64_t pulse_rate_mHz(const PatternTiming* t, std::size_t n);
inline bool within_pulse_rate(std::uint64_t rate_mHz, const Capabilities& caps) {
  return rate_mHz <= std::uint64_t{caps.max_pulse_rate_hz} * 1000u;
}
// Edges per second over n patterns, in thousandths: each pattern's ceil(10^9 / period) x
// its edges (PatternTiming::edges), for the device's check against max_edge_rate_hz.
std::uint64_t edge_rate_mHz(const PatternTiming* t, std::size_t n);
inline bool within_edge_rate(std::uint64_t rate_mHz, const Capabilities& caps) {
  return rate_mHz <= std::uint64_t{caps.max_edge_rate_hz} * 1000u;
}

// phase_fits for a pattern's timing.
bool phase_fits(const PatternTiming& t, const Capabilities& caps);

// The device's timing rule beyond the widths and the rate: a gap, if there is one (> 0),
// and the off time between one pulse's end and the next one's start (period - width - gap
// - balance width) are each at least the shortest phase, min_width_us.  A device loads the
// next phase's codes in each such stretch, so shorter ones could not be delivered on time.
// The host checks it before configuring; the device refuses (out_of_range) what breaks it.
bool phase_fits(const PulseConfig& c, const Capabilities& caps);

// Channel codes, in fixed storage.
struct Codes {
  std::array<std::int16_t, kMaxChannels> code{};
  std::size_t count = 0;
  const std::int16_t* begin() const { return code.data(); }
  const std::int16_t* end() const { return code.data() + count; }
  std::size_t size() const { return count; }
  std::int16_t operator[](std::size_t i) const { return code[i]; }
};
// The count byte and the codes of a set_weights payload (after the token); false when the
// length disagrees or count > kMaxChannels.
bool decode_codes(const std::uint8_t* p, std::size_t n, Codes& out);

// A pattern's codes, sparse: channel indices strictly increasing, each with its code.
struct SparseCodes {
  std::array<std::uint8_t, kMaxChannels> channel{};
  std::array<std::int16_t, kMaxChannels> code{};
  std::size_t count = 0;
};
// The count byte and the entries of a set_codes payload (after token and index); false
// when the length disagrees, count > kMaxChannels, or the channels do not increase.
bool decode_sparse(const std::uint8_t* p, std::size_t n, SparseCodes& out);

// codes x scale / kFullScale (scale <= kFullScale), each toward zero, then single codes
// away from zero where the remainders are largest (lowest channel first on ties) until they
// sum to zero as the inputs do: each within one code of the exact value and never larger
// in magnitude than its input.
void scale_codes(const std::int16_t* in, std::size_t n, std::uint16_t scale, std::int16_t* out);

// What the device bounds across a table, per electrode, summed over its patterns: the
// mean square current and the mean absolute current (the charge per second both phases
// carry), in integers so that host and device agree exactly and a pattern's share can be
// taken out again.  A channel of main code c (|c| = a) has a balancing code of at most
// b = ceil(a w / bw) in magnitude (balance_codes rounds each to the floor or the ceiling
// of the exact charge-balancing value), so it adds (a^2 w + b^2 bw) / T code^2 and
// (a w + b bw) / T codes, each rounded up in units of 2^-16: never under what the DAC
// delivers.  A shaped pattern (version 6) delivers exactly a |u_k| codes in phase k, so
// its shares are exact sums over its phases, a^2 sum u_k^2 d_k / T and a sum |u_k| d_k / T,
// rounded up the same way.  Each share needs a x max|u_k| <= 32768 (the device refuses
// larger codes first); a larger one counts as 2^62, above every bound.
struct ChannelLoad {
  std::uint64_t ms_q16[kMaxChannels] = {};
  std::uint64_t mean_q16[kMaxChannels] = {};
  // One channel's share at this timing (|code| a).
  static std::uint64_t ms_share(std::uint32_t a, const PatternTiming& t);
  static std::uint64_t mean_share(std::uint32_t a, const PatternTiming& t);
  // Adds (sign +1) or takes out (-1) a pattern's codes: n entries, channel[k] and code[k].
  void add(const std::uint8_t* channel, const std::int16_t* code, std::size_t n,
           const PatternTiming& t, int sign);
  // false when a channel's RMS or mean current is above the capabilities' bounds.
  bool within(const Capabilities& caps) const { return first_over(caps) == kMaxChannels; }
  // The first such channel; kMaxChannels when there is none.
  std::size_t first_over(const Capabilities& caps) const;
  // The host's figures, mA, for a DAC step.
  double rms_mA(std::size_t ch, std::uint32_t step_nA) const;
  double mean_mA(std::size_t ch, std::uint32_t step_nA) const;
};

// The current of one code of a signed DAC of dac_bits (2 to 16) spanning
// +-max_current_uA: the nearest whole nA, or the next one up where the nearest would need
// more codes than the DAC has (2^(bits-1) - 1).  0 when the protocol's 16-bit field cannot
// carry it.
std::uint32_t dac_step_nA(std::uint16_t max_current_uA, int dac_bits);

// The host's forms (protocol_buffers.cpp).
std::vector<std::uint8_t> encode(const Capabilities& c);
std::optional<Capabilities> decode_capabilities(const std::vector<std::uint8_t>& b, std::size_t at);
std::vector<std::uint8_t> encode(const PulseConfig& c);
std::vector<std::uint8_t> encode(const Status& s);
std::optional<Status> decode_status(const std::vector<std::uint8_t>& b, std::size_t at);
std::vector<std::uint8_t> encode_weights(const std::vector<std::int16_t>& codes);
std::vector<std::uint8_t> encode(const PatternTiming& t);
std::vector<std::uint8_t> encode(const Guards& g);
// A measurements reply's body (after the ack's type and result): its head and channels;
// nothing when malformed.
struct Measurements {
  MeasurementsHead head;
  std::vector<ChannelMeasurement> channels;  // head.first, head.first + 1, ...
};
std::optional<Measurements> decode_measurements(const std::vector<std::uint8_t>& b,
                                                std::size_t at);
// Adds (sign +1) or takes out (-1) a pattern's dense codes, as the device adds its sparse
// ones (only the non-zero channels).
void add_dense(ChannelLoad& load, const std::vector<std::int16_t>& codes, const PatternTiming& t,
               int sign = +1);
// A set_codes body after the index: the non-zero codes of a dense list, sparse.
std::vector<std::uint8_t> encode_sparse(const std::vector<std::int16_t>& dense);
// The count byte and the codes; nothing when the length disagrees or count > kMaxChannels.
std::optional<std::vector<std::int16_t>> decode_weights(const std::uint8_t* p, std::size_t n);

// The payloads of the session's messages: the token first, then the message's own fields.
std::vector<std::uint8_t> with_session(std::uint32_t session,
                                       const std::vector<std::uint8_t>& rest);

}  // namespace tp::device
