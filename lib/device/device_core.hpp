#pragma once
// The stimulator's firmware logic, portable (no OS calls, time passed in): it decodes
// frames, checks every command against its own limits (refusing, never clipping), keeps
// the configuration and weights, and emits pulses on time.  The emulators (stim-emu on a
// pseudo-terminal, and stimctl --port emu in-process) run exactly this code.
//
// Safety, on the device side:
//  - set_weights: channel count must match, |code| <= max, and the codes must sum to zero;
//    a refused frame changes nothing.
//  - configure: width, balance width, gap and rate within the capabilities; the balancing
//    phase carries the main phase's charge (current scaled by width / balance width).
//  - watchdog: output stops when no valid frame arrived for watchdog_ms.
//  - a repeated frame (same seq, type and payload: a retransmission) is answered again
//    but not executed twice.

#include <cstdint>
#include <functional>
#include <vector>

#include "device/frame.hpp"
#include "device/protocol.hpp"

namespace tp::device {

struct DeliveredPulse {
  std::uint64_t t_us;                      // device time of the pulse's start
  std::uint64_t start_us;                  // device time of the start command
  const std::vector<std::int16_t>& codes;  // main-phase DAC codes, + = cathodic
  const PulseConfig& config;
  const Capabilities& caps;
};

class DeviceCore {
 public:
  explicit DeviceCore(Capabilities caps) : caps_(caps) {}

  // Bytes received at now_us; replies are appended to out.
  void receive(const std::uint8_t* data, std::size_t n, std::uint64_t now_us,
               std::vector<std::uint8_t>& out);
  // Emits every pulse due by now_us, then applies the watchdog.
  void advance(std::uint64_t now_us, const std::function<void(const DeliveredPulse&)>& sink);
  // The link is gone (port closed): stop output.
  void link_lost();
  // When something next happens (a pulse or the watchdog); UINT64_MAX when idle.
  std::uint64_t next_event_us() const;

  const Status& status() const { return status_; }
  const Capabilities& caps() const { return caps_; }

 private:
  std::vector<std::uint8_t> handle(const Frame& f, std::uint64_t now_us);
  Result configure(const std::vector<std::uint8_t>& payload);
  Result set_weights(const std::vector<std::uint8_t>& payload);

  Capabilities caps_;
  FrameDecoder decoder_;
  Status status_;
  PulseConfig config_;
  bool configured_ = false;
  bool weights_set_ = false;
  std::vector<std::int16_t> weights_;
  std::uint64_t last_valid_us_ = 0;
  std::uint64_t start_us_ = 0;
  std::uint64_t next_pulse_us_ = 0;
  bool have_last_ = false;
  Frame last_request_;
  std::vector<std::uint8_t> last_reply_;
};

}  // namespace tp::device
