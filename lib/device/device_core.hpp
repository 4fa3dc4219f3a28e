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
//  - configure: width, balance width, gap and rate within the capabilities; the balancing
//    phase carries the main phase's charge (current scaled by width / balance width);
//  - sessions: configure opens one (a non-zero token); set_weights, start and keepalive
//    must carry its token; stop ends it, so nothing of an old session can be restarted;
//  - watchdog: output stops when no frame *of the running session* arrived for
//    watchdog_ms; identify, status and other sessions' frames do not feed it;
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

// The latest a pulse may come after its slot; older slots are skipped, never delivered in
// a burst (an emulator whose process was descheduled).
inline constexpr std::uint64_t kMaxLateUs = 100000;

class DeviceCore {
 public:
  // caps is lowered to the compile-time bounds (within_hard_limits).
  explicit DeviceCore(const Capabilities& caps) : caps_(within_hard_limits(caps)) {}

  // Bytes received at now_us; replies are appended to out.
  void receive(const std::uint8_t* data, std::size_t n, std::uint64_t now_us,
               std::vector<std::uint8_t>& out);
  // Emits every pulse due by now_us, then applies the watchdog.
  void advance(std::uint64_t now_us, const std::function<void(const DeliveredPulse&)>& sink);
  // The link is gone (port closed): stop output and end the session.
  void link_lost();
  // When something next happens (a pulse or the watchdog); UINT64_MAX when idle.
  std::uint64_t next_event_us() const;

  const Status& status() const { return status_; }
  const Capabilities& caps() const { return caps_; }

 private:
  std::vector<std::uint8_t> handle(const Frame& f, std::uint64_t now_us);
  Result configure(const std::vector<std::uint8_t>& payload);
  Result set_weights(const std::vector<std::uint8_t>& payload);
  bool of_session(const Frame& f) const;  // carries the current session's token
  void expire(std::uint64_t now_us);      // the watchdog, at any call
  void end_session();

  Capabilities caps_;
  FrameDecoder decoder_;
  Status status_;
  PulseConfig config_;
  std::uint32_t session_ = 0;  // 0: no session
  bool configured_ = false;
  bool weights_set_ = false;
  std::vector<std::int16_t> weights_;
  std::uint64_t last_fed_us_ = 0;  // the running session's last frame
  std::uint64_t start_us_ = 0;
  std::uint64_t next_pulse_us_ = 0;
  bool have_last_ = false;
  Frame last_request_;
  std::vector<std::uint8_t> last_reply_;
};

}  // namespace tp::device
