#pragma once
// The host's side of the stimulator protocol: requests with sequence numbers, each
// answered by an acknowledgement with a result code, retransmitted on time-out.

#include <cstdint>
#include <vector>

#include "device/frame.hpp"
#include "device/protocol.hpp"
#include "host/transport.hpp"
#include "pulse/stimulus.hpp"

namespace tp::host {

// Why each time-out is what it is:
// An acknowledgement normally arrives within a millisecond on a pty and a few on a
// USB-serial adapter at 115200 baud (a frame is < 50 bytes); 40 ms leaves room for a
// loaded host without letting a lost frame stall the keep-alive schedule.
inline constexpr int kAckTimeoutMs = 40;
// Six attempts ride out a burst of damaged frames (1 % byte errors lose ~25 % of frames)
// and still give up within 240 ms, before a 300 ms device watchdog would fire.
inline constexpr int kAttempts = 6;
// Keep-alive period: several per watchdog period (the device's is 300 ms).
inline constexpr int kKeepAliveMs = 50;

// The host's bounds on a device's watchdog: it must stop a dead host's output within the
// host's safety bound, and leave room for more than one keep-alive (a lost frame).
inline constexpr int kMaxDeviceWatchdogMs = 300;
inline constexpr int kMinDeviceWatchdogMs = 2 * kKeepAliveMs;

class StimulatorClient {
 public:
  explicit StimulatorClient(Transport& t) : t_(t) {}

  device::Capabilities identify();
  // Opens a session: a fresh random non-zero token, carried by every later request.
  void configure(const device::PulseConfig& c);
  void set_weights(const std::vector<std::int16_t>& codes);
  // Protocol 4's table: opens a session of n patterns (like configure), then each
  // pattern's timing and its codes (sent sparse), and live amplitude scales.
  void configure_table(std::uint16_t patterns, std::uint8_t channels, std::uint16_t gap_us);
  void set_pattern(std::uint16_t index, const device::PatternTiming& t);
  // A shaped pattern's timing (protocol 6): its phases in units (t.shape).
  void set_shape(std::uint16_t index, const device::PatternTiming& t);
  void set_codes(std::uint16_t index, const std::vector<std::int16_t>& dense);
  void set_amplitudes(const std::vector<std::uint16_t>& scales);
  // Protocol 7, a device that measures: the session's guards (the electrodes' area, the
  // density limit, the contact fraction below which a pad is lost).
  void set_guards(const device::Guards& g);
  // Protocol 7: pattern index's held pulse energy (device::Msg::set_hold).
  void set_hold(std::uint16_t index, std::uint64_t energy_ref);
  // Protocol 7: each of the first `channels` channels' last reading and baseline, and what
  // stopped the output (a query, paged by kMeasurementsPerReply).
  device::Measurements measurements(std::size_t channels);
  // The same while the output runs: false (nothing changed) when the device has already
  // ended this session (its stimulus completed, its watchdog, a stop); any other refusal
  // is a failure naming it.
  bool set_weights_live(const std::vector<std::int16_t>& codes);
  bool set_amplitudes_live(const std::vector<std::uint16_t>& scales);
  void start();
  // Always honoured by the device; ends the session.
  void stop();
  // A query: never feeds the device's watchdog.
  device::Status status();
  // Feeds the watchdog of this session's output and returns the status.  When the device
  // has ended the session (completed, watchdog, link), returns the status it reports.
  device::Status keepalive();
  std::uint32_t session() const { return session_; }

  // Monotonic time (ns) at which the last request's first attempt was written.
  std::int64_t last_write_ns() const { return last_write_ns_; }
  int retransmissions() const { return retransmissions_; }

 private:
  struct Reply {
    device::Result result;
    std::vector<std::uint8_t> body;  // after type and result
  };
  // Sends a request and returns the acknowledgement; throws tp::Error (failure) when the
  // device stops answering.
  Reply exchange(device::Msg type, const std::vector<std::uint8_t>& payload);
  // exchange(), and a refusal is a tp::Error (failure) naming it.
  std::vector<std::uint8_t> request(device::Msg type, const std::vector<std::uint8_t>& payload);
  // request(), but false when the device refuses it as not of the current session.
  bool session_request(device::Msg type, const std::vector<std::uint8_t>& payload);
  static std::vector<std::uint8_t> amplitudes_payload(const std::vector<std::uint16_t>& scales,
                                                      std::size_t first);

  Transport& t_;
  device::FrameDecoder decoder_;
  std::uint8_t seq_ = 0;
  std::uint32_t session_ = 0;
  std::int64_t last_write_ns_ = 0;
  int retransmissions_ = 0;
};

// A random non-zero session token (the OS's random source).
std::uint32_t new_session_token();

// The largest code whose current (code x the DAC step) is at most limit_mA, and at most
// the device's largest code.
std::int32_t limit_code(double limit_mA, const device::Capabilities& caps);

// DAC codes for the main-phase currents, none above limit_mA (the limit in force: the
// stimulus's max_current_mA, the host's and the device's, whichever is lowest): each
// current rounded to the nearest DAC step, or toward zero where the nearest would cross
// the limit; then adjusted by single codes (largest error first, never beyond the limit)
// so that they sum to exactly zero.  Bad input when a current exceeds the limit or the
// sum cannot be made zero within it.  The balancing phase's codes (device::balance_codes)
// are never larger than the main phase's, so the limit holds for every phase.
std::vector<std::int16_t> quantize_currents(const std::vector<double>& currents_mA,
                                            const device::Capabilities& caps, double limit_mA);

// A pattern's codes as the device takes them: the biphasic pulse's main-phase codes
// (quantize_currents), or a shaped pulse's base codes, one per unit of 1/U of the level
// (shape_units): quantize_currents of currents / U within limit_mA / max|units|, so that
// every phase's codes (base x units) are within the limit and sum to zero.
std::vector<std::int16_t> pattern_codes(const Stimulus& s, const device::Capabilities& caps,
                                        double limit_mA);
// The stimulus those codes deliver: each channel's current at level 1 from its codes (a
// shaped pulse: base x U codes), for the limits to be checked again as delivered.
Stimulus delivered_stimulus(const Stimulus& s, const std::vector<std::int16_t>& codes,
                            const device::Capabilities& caps);

}  // namespace tp::host
