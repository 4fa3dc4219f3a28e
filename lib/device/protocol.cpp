#include "device/protocol.hpp"

#include <algorithm>

namespace tp::device {

const char* to_string(Result r) {
  switch (r) {
    case Result::ok:
      return "ok";
    case Result::unknown_type:
      return "unknown message type";
    case Result::bad_length:
      return "bad message length";
    case Result::out_of_range:
      return "value outside the device's limits";
    case Result::not_configured:
      return "not configured";
    case Result::sum_not_zero:
      return "channel currents do not sum to zero";
    case Result::channel_mismatch:
      return "channel count does not match the device";
    case Result::bad_state:
      return "not allowed while running";
    case Result::wrong_session:
      return "not the device's current session (another host's, or already stopped)";
  }
  return "unknown result";
}

const char* to_string(Fault f) {
  switch (f) {
    case Fault::none:
      return "none";
    case Fault::watchdog:
      return "watchdog (no keep-alive)";
    case Fault::link_lost:
      return "link lost";
    case Fault::completed:
      return "completed";
    case Fault::stopped:
      return "stopped by the host";
    case Fault::output_fault:
      return "output stage fault (the device refuses further output until it is reset)";
  }
  return "unknown fault";
}

std::uint16_t get_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

std::int32_t Capabilities::max_code() const {
  if (dac_step_nA == 0) return 0;
  const std::uint32_t code = std::uint32_t{max_current_uA} * 1000u / dac_step_nA;
  return static_cast<std::int32_t>(std::min<std::uint32_t>(code, hard::max_dac_code));
}

bool phase_fits(const PulseConfig& c, const Capabilities& caps) {
  if (c.interphase_us != 0 && c.interphase_us < caps.min_width_us) return false;
  const std::uint64_t length = std::uint64_t{c.width_us} + c.interphase_us + c.balance_width_us;
  return c.period_us > length && c.period_us - length >= caps.min_width_us;
}

Capabilities within_hard_limits(Capabilities c) {
  c.protocol = kProtocolVersion;
  c.channels = static_cast<std::uint8_t>(std::clamp<std::size_t>(c.channels, 1, kMaxChannels));
  c.max_current_uA = std::min(c.max_current_uA, hard::max_current_uA);
  c.dac_step_nA = std::max<std::uint16_t>(c.dac_step_nA, 1);
  c.min_width_us = std::max(c.min_width_us, hard::min_width_us);
  c.max_width_us = std::min(c.max_width_us, hard::max_width_us);
  c.max_balance_width_us = std::min(c.max_balance_width_us, hard::max_balance_width_us);
  c.max_rate_hz = std::clamp<std::uint16_t>(c.max_rate_hz, 1, hard::max_rate_hz);
  c.watchdog_ms = std::clamp(c.watchdog_ms, hard::min_watchdog_ms, hard::max_watchdog_ms);
  return c;
}

std::optional<PulseConfig> decode_config(const std::uint8_t* p, std::size_t n) {
  if (n != kConfigSize) return std::nullopt;
  PulseConfig c;
  c.period_us = get_u32(p);
  c.width_us = get_u16(p + 4);
  c.interphase_us = get_u16(p + 6);
  c.balance_width_us = get_u16(p + 8);
  c.channels = p[10];
  c.max_pulses = get_u32(p + 11);
  return c;
}

bool decode_codes(const std::uint8_t* p, std::size_t n, Codes& out) {
  if (n == 0 || p[0] > kMaxChannels || n != 1 + 2 * std::size_t{p[0]}) return false;
  out.count = p[0];
  for (std::size_t i = 0; i < out.count; ++i)
    out.code[i] = static_cast<std::int16_t>(get_u16(p + 1 + 2 * i));
  return true;
}

std::uint32_t dac_step_nA(std::uint16_t max_current_uA, int dac_bits) {
  if (dac_bits < 2 || dac_bits > 16) return 0;
  const std::uint64_t codes = (std::uint64_t{1} << (dac_bits - 1)) - 1;
  const std::uint64_t na = std::uint64_t{max_current_uA} * 1000u;
  // round(na / codes), halves away from zero, in integers
  std::uint64_t step = std::max<std::uint64_t>(1, (2 * na + codes) / (2 * codes));
  if (na / step > codes) step = (na + codes - 1) / codes;
  return step > 65535 ? 0 : static_cast<std::uint32_t>(step);
}

}  // namespace tp::device
