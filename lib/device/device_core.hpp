#pragma once
// The stimulator's firmware logic, portable (no OS calls, time passed in): it decodes
// frames, checks every command against its own limits (refusing, never clipping), keeps
// the session, configuration and weights, and emits pulses on time.  The emulators
// (stim-emu on a pseudo-terminal, and stimctl --port emu in-process) run exactly this code.
//
// Safety, on the device side:
//  - its capabilities are lowered to the compile-time bounds (protocol.hpp, hard::): no
//    configuration can raise the current, width, rate or watchdog limits;
//  - set_weights: channel count must match, |code| <= max, and the codes must sum to zero;
//    a refused frame changes nothing;
//  - configure: width, balance width, gap and rate within the capabilities, and every
//    stretch between two edges (a gap, the time between pulses) at least the shortest
//    phase, min_width_us (phase_fits); the balancing phase carries the main phase's charge
//    (current scaled by width / balance width, never above the main phase's current);
//  - status.pulses counts delivered pulses only (not_delivered); a pulse that cannot be
//    delivered on time ends the output (overrun: Fault::overrun);
//  - start: at most max_pulse_rate_hz pulses a second over the table (pulse_rate_mHz);
//  - sessions: configure opens one (a non-zero token); set_weights, start and keepalive
//    must carry its token; stop ends it, so nothing of an old session can be restarted;
//  - watchdog: output stops when no frame *of the running session* arrived for
//    watchdog_ms; identify, status and other sessions' frames do not feed it;
//  - patterns (version 4): a table of up to kMaxPatterns patterns, each set and checked
//    like a configuration and its weights (Sum = 0, |code| <= max, shape and rate within
//    the capabilities); across the table, every electrode's RMS and mean current summed
//    over the patterns within the capabilities' bounds (ChannelLoad), the utilisation at
//    most 1 and the worst slip within max_slip_us (Scheduler), or the frame (or start) is
//    refused and changes nothing; set_amplitudes only scales a pattern's codes down;
//  - shaped pulses (version 6, set_shape): only on a device that claims them (features
//    bit 0, else not_supported); 1 to max_phases phases (bad_length), each min_width to
//    max_balance_width long, the strongest at most max_width, |units| <= hard::max_units
//    (out_of_range), the net charge sum units x duration exactly 0 (charge_not_zero); the
//    peak |base code| x max|units| within the largest code, whichever of set_codes and
//    set_shape comes second; the loads exact sums over the phases; start: at most
//    max_edge_rate_hz edges a second over the table (edge_rate_mHz);
//  - measurements (version 7, a device that measures: device_guards.cpp): each pulse's
//    readings give each channel's impedance and baseline; a pad without contact, a
//    current not delivered (the compliance rail) or a charge density above Shannon's k on
//    the estimated contact area ends the output before the next pulse (Fault::contact,
//    compliance, density), or with set_guards' suspend flag pauses only the patterns on a
//    lost pad (their pulses at the probe's current, in whole codes) until a probe finds
//    it again with room for its charge; set_hold scales a pattern to hold its pulse energy,
//    never above its codes as uploaded;
//  - a repeated frame (same seq, type and payload: a retransmission, or a replay of the
//    same bytes) is answered again from the cache, but neither executed twice nor allowed
//    to feed the watchdog; nor does a frame of the session whose seq is not newer (ahead by
//    1 to 127, modulo 256) than the last one that fed it: a replay of older frames.

#include <cstdint>
#include <vector>

#include "device/fixed_bytes.hpp"
#include "device/frame.hpp"
#include "device/protocol.hpp"
#include "device/scheduler.hpp"

namespace tp::device {

struct PulseRecord;       // pulse_record.hpp
struct ElectricalRecord;  // pulse_record.hpp

// A view of channel codes (the firmware has no allocator to copy them into).
struct CodeSpan {
  const std::int16_t* first = nullptr;
  std::size_t count = 0;
  const std::int16_t* begin() const { return first; }
  const std::int16_t* end() const { return first + count; }
  std::size_t size() const { return count; }
  std::int16_t operator[](std::size_t i) const { return first[i]; }
};

struct DeliveredPulse {
  std::uint64_t t_us;      // device time of the pulse's start (its slot plus its slip)
  std::uint64_t start_us;  // device time of the start command
  CodeSpan codes;          // main-phase DAC codes of every channel, + = cathodic; of a
                           // shaped pattern, its base codes (phase k: codes x units_k)
  const PatternTiming& timing;
  const Capabilities& caps;
  std::uint16_t pattern = 0;
  std::uint32_t slip_us = 0;  // how long it was deferred behind another pattern's pulse
};

// The latest a pulse may come after its slot; older slots are skipped, never delivered in
// a burst (an emulator whose process was descheduled).
inline constexpr std::uint64_t kMaxLateUs = 100000;
// The most pulses the start's exact schedule check simulates (Scheduler::worst_slip): a
// few milliseconds of a firmware's time, well within its watchdog.
inline constexpr std::uint32_t kMaxCheckedPulses = 16384;
// The host checks tables with the same rule and the same budget, so that what it sends the
// device accepts.
inline constexpr std::uint32_t kMaxCheckedPulsesHost = kMaxCheckedPulses;

class DeviceCore {
 public:
  // caps is lowered to the compile-time bounds (within_hard_limits).
  explicit DeviceCore(const Capabilities& caps) : caps_(within_hard_limits(caps)) {}

  // Bytes received at now_us; each reply frame goes to reply(const std::uint8_t*, size).
  template <class Reply>
  void receive(const std::uint8_t* data, std::size_t n, std::uint64_t now_us, Reply&& reply) {
    for (std::size_t i = 0; i < n; ++i)
      if (receive_byte(data[i], now_us)) reply(last_reply_.data(), last_reply_.size());
  }
  // The same, replies appended to out (the host's emulators).
  void receive(const std::uint8_t* data, std::size_t n, std::uint64_t now_us,
               std::vector<std::uint8_t>& out) {
    receive(data, n, now_us,
            [&out](const std::uint8_t* p, std::size_t k) { out.insert(out.end(), p, p + k); });
  }

  // Emits every pulse due by now_us to sink(const DeliveredPulse&), then applies the
  // watchdog.
  // A sink may report the pulse's measurements (measured()) before it returns: a guard that
  // trips then ends the output before the next pulse.
  template <class Sink>
  void advance(std::uint64_t now_us, Sink&& sink) {
    if (!begin_advance(now_us)) return;
    InAdvance in(*this);
    while (pulse_due(now_us)) {
      const ScheduledPulse p = sched_.next();
      sink(DeliveredPulse{p.start_us, start_us_, pulse_codes(p.pattern), timing_[p.pattern], caps_,
                          p.pattern, static_cast<std::uint32_t>(p.start_us - p.slot_us)});
      pulse_delivered();
      apply_trip();
    }
    expire(now_us);  // the watchdog
  }

  // A pulse's readings (a board that measures, or an emulator's skin: m's carried, at_rail,
  // voltage_mV and current_nA) for the pulse r of the output started at start_us
  // (device_guards.cpp): the core derives each channel's impedance into m.impedance_ohm,
  // keeps it as the channel's last reading, lowers the channel's baseline to it, and
  // applies the guards (docs/safety.md, "Measured guards").  A trip ends the output with
  // Fault::contact, compliance or density: at once, or, from advance()'s sink, before the
  // next pulse.  Readings of an earlier output are ignored.
  void measured(std::uint64_t start_us, const PulseRecord& r, ElectricalRecord& m);

  // Pulses the core emitted for the output started at start_us (DeliveredPulse::start_us)
  // that never reached the electrodes (a firmware's engine dropped them when the output
  // stopped, or could not deliver them on time): the status counts delivered pulses only.
  // Reports for an earlier output are ignored.
  void not_delivered(std::uint64_t start_us, std::uint32_t n);
  // Pulses of the output started at start_us that the device could not deliver on time (a
  // firmware's engine, behind its schedule, had no room to queue them): they are not
  // counted, and the output ends with Fault::overrun, so that a host never takes fewer
  // pulses than it asked for as a completed stimulus.
  void overrun(std::uint64_t start_us, std::uint32_t n);
  // The board's stop input (a firmware's GPIO interrupt, which has already opened the
  // electrode switches; an emulator's scripted equivalent) at now_us: the output ends with
  // Fault::stop_input and the session with it, so nothing of it can be restarted: only a new
  // session (configure) delivers again.  The measurements' trip says when (channel 0xFF).
  void stop_input(std::uint64_t now_us);
  // The link is gone (port closed): stop output and end the session.
  void link_lost();
  // The output stage failed: stop output, end the session, and refuse every later
  // configure (bad_state) until the device is reset.
  void output_fault();
  // Counts every end of an output (stop, watchdog, completion, link lost, fault): a
  // firmware compares it after each frame to stop its output stage before it answers.
  std::uint32_t output_ends() const { return output_ends_; }
  // When something next happens (a pulse or the watchdog); UINT64_MAX when idle.
  std::uint64_t next_event_us() const;
  // The receiver's own counts (a UART's framing errors and overruns), for the status.
  void set_line_counts(std::uint32_t line_errors, std::uint32_t overruns);

  const Status& status() const { return status_; }
  // The running (or last) output's start command, device time.
  std::uint64_t output_start_us() const { return start_us_; }
  const Capabilities& caps() const { return caps_; }

 private:
  bool receive_byte(std::uint8_t byte, std::uint64_t now_us);  // true: a reply is ready
  void handle(const RxFrame& f, std::uint64_t now_us, FixedBytes<kMaxPayload>& body);
  Result configure(const FixedBytes<kMaxPayload>& payload);
  Result configure_table(const FixedBytes<kMaxPayload>& payload);
  Result set_weights(const FixedBytes<kMaxPayload>& payload);
  Result set_pattern(const FixedBytes<kMaxPayload>& payload);
  Result set_codes(const FixedBytes<kMaxPayload>& payload);
  Result set_amplitudes(const FixedBytes<kMaxPayload>& payload);
  Result set_shape(const FixedBytes<kMaxPayload>& payload);
  Result set_guards(const FixedBytes<kMaxPayload>& payload);
  Result set_hold(const FixedBytes<kMaxPayload>& payload);
  // Pattern i's scale under its held energy (device_guards.cpp): its amplitude's scale x
  // sqrt(energy_ref / energy now), at most kFullScale; its amplitude's scale when it is not
  // held or a channel has no reading yet.
  std::uint16_t hold_scale(std::uint16_t i) const;
  Result measurements(const FixedBytes<kMaxPayload>& payload, FixedBytes<kMaxPayload>& body) const;
  // The guards (device_guards.cpp): the first channel of the pulse that trips, and why.
  // What a pulse's charge per phase and asked current take, once a pulse
  // (device_guards.cpp).
  struct PulseTerms {
    float uC_per_code_us = 0;  // step x 1e-9: a code for a microsecond, in uC
    float shaped_uC_per_code = 0;  // a shape's largest same-sign run, in uC a code
    std::uint32_t units = 1;       // the measured phase's units (a shape's strongest)
  };
  // A channel that carried current in r: its reading, baseline and guards.
  Fault check_channel(const PulseRecord& r, const PulseTerms& t, ElectricalRecord& m,
                      std::size_t c);
  // Lost contact or density for a charge per phase (pC) at impedance z against base.
  Fault density_fault(float charge_pC, std::uint32_t z, std::uint32_t base) const;
  float full_charge_pC(std::size_t c) const;  // the table's largest on channel c
  void trip(Fault cause, std::size_t channel, std::uint64_t t_us);
  void apply_trip();  // a trip found during advance(), after the pulse in hand
  struct InAdvance {
    DeviceCore& core;
    explicit InAdvance(DeviceCore& c) : core(c) { core.in_advance_ = true; }
    ~InAdvance() { core.in_advance_ = false; }
  };
  Result start(std::uint64_t now_us);
  void open_table(std::uint32_t session, std::uint16_t n, std::uint8_t channels,
                  std::uint16_t gap_us);
  Result check_widths(const PatternTiming& t) const;  // a biphasic's widths, or its shape
  Result check_timing(const PatternTiming& t) const;
  // Pattern i's codes (if any) times t's largest units within the largest code.
  bool peak_fits(std::uint16_t i, const PatternTiming& t) const;
  Result put_timing(std::uint16_t i, const PatternTiming& t);
  // Pattern i's codes become these (checked first: |code|, Sum = 0, the load).
  Result put_codes(std::uint16_t i, const SparseCodes& c, std::uint8_t reserve);
  void load(std::uint16_t i, int sign);     // pattern i's share of load_, in or out
  CodeSpan pulse_codes(std::uint16_t i);    // dense, scaled by its amplitude (or the probe's)
  bool touches_suspended(std::uint16_t i) const;  // pattern i drives a suspended channel
  // The scale that brings pattern i's largest current to at most the probe's (kFullScale
  // when it is already within it).
  std::uint16_t probe_scale(std::uint16_t i) const;
  bool of_session(const RxFrame& f) const;  // carries the current session's token
  void expire(std::uint64_t now_us);        // the watchdog, at any call
  void end_session();
  bool begin_advance(std::uint64_t now_us);  // false when not running
  bool pulse_due(std::uint64_t now_us) const;
  void pulse_delivered();
  std::uint64_t deadline_us() const;

  Capabilities caps_;
  FrameDecoder decoder_;
  Status status_;
  std::uint32_t session_ = 0;  // 0: no session
  bool configured_ = false;
  bool faulted_ = false;
  std::uint32_t output_ends_ = 0;
  // The pattern table.
  struct Pattern {
    bool timing_set = false, codes_set = false;
    std::uint16_t first = 0;  // its codes: pool entries first .. first + count
    std::uint8_t count = 0, room = 0;
    std::uint16_t scale = kFullScale;
  };
  std::uint16_t patterns_ = 0;
  std::uint8_t channels_ = 0;
  Pattern pattern_[kMaxPatterns];
  PatternTiming timing_[kMaxPatterns];
  std::uint8_t pool_channel_[kCodePool] = {};
  std::int16_t pool_code_[kCodePool] = {};
  std::uint32_t pool_used_ = 0;
  ChannelLoad load_;
  Scheduler sched_;
  std::int16_t dense_[kMaxChannels] = {}, scaled_[kMaxChannels] = {};
  std::uint64_t last_fed_us_ = 0;  // the running session's last frame that fed the watchdog
  std::uint8_t fed_seq_ = 0;       // and its sequence number
  std::uint64_t start_us_ = 0;
  // Measurements (version 7): the session's guards, each channel's last reading, and what
  // tripped; reset at each start.
  Guards guards_;
  // 10^k x the area in cm^2 (0: no density guard); single precision, as the guards compute
  // (device_guards.cpp).
  float density_limit_uC2_ = 0;
  ChannelMeasurement reading_[kMaxChannels];
  MeasurementsHead readings_;
  Fault pending_trip_ = Fault::none;
  std::uint64_t suspended_ = 0;  // bit c: channel c lost contact (kGuardSuspend)
  std::uint64_t hold_ref_[kMaxPatterns] = {};  // set_hold's energy_ref (0: not held)
  bool in_advance_ = false;
  bool have_last_ = false;
  RxFrame last_request_;
  FixedBytes<kMaxEncodedFrame> last_reply_;
};

}  // namespace tp::device
