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
  }
  return "unknown fault";
}

void put_u16(std::vector<std::uint8_t>& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v & 0xFF));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}
void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
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

std::vector<std::uint8_t> encode(const Capabilities& c) {
  std::vector<std::uint8_t> b;
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
  return b;
}

std::optional<Capabilities> decode_capabilities(const std::vector<std::uint8_t>& b,
                                                std::size_t at) {
  if (b.size() != at + kCapabilitiesSize) return std::nullopt;
  const std::uint8_t* p = b.data() + at;
  Capabilities c;
  c.protocol = p[0];
  c.channels = p[1];
  c.max_current_uA = get_u16(p + 2);
  c.dac_step_nA = get_u16(p + 4);
  c.min_width_us = get_u16(p + 6);
  c.max_width_us = get_u16(p + 8);
  c.max_balance_width_us = get_u16(p + 10);
  c.max_rate_hz = get_u16(p + 12);
  c.watchdog_ms = get_u16(p + 14);
  c.fw_major = p[16];
  c.fw_minor = p[17];
  c.fw_patch = p[18];
  if (c.channels == 0 || c.dac_step_nA == 0 || c.max_rate_hz == 0) return std::nullopt;
  return c;
}

std::vector<std::uint8_t> encode(const PulseConfig& c) {
  std::vector<std::uint8_t> b;
  put_u32(b, c.period_us);
  put_u16(b, c.width_us);
  put_u16(b, c.interphase_us);
  put_u16(b, c.balance_width_us);
  b.push_back(c.channels);
  put_u32(b, c.max_pulses);
  return b;
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

std::vector<std::uint8_t> encode(const Status& s) {
  std::vector<std::uint8_t> b;
  b.push_back(static_cast<std::uint8_t>(s.state));
  b.push_back(static_cast<std::uint8_t>(s.fault));
  put_u32(b, s.pulses);
  put_u32(b, s.weight_updates);
  put_u16(b, s.rx_errors);
  return b;
}

std::optional<Status> decode_status(const std::vector<std::uint8_t>& b, std::size_t at) {
  if (b.size() != at + kStatusSize) return std::nullopt;
  const std::uint8_t* p = b.data() + at;
  if (p[0] > 1 || p[1] > 4) return std::nullopt;
  Status s;
  s.state = static_cast<State>(p[0]);
  s.fault = static_cast<Fault>(p[1]);
  s.pulses = get_u32(p + 2);
  s.weight_updates = get_u32(p + 6);
  s.rx_errors = get_u16(p + 10);
  return s;
}

std::vector<std::uint8_t> encode_weights(const std::vector<std::int16_t>& codes) {
  std::vector<std::uint8_t> b;
  b.push_back(static_cast<std::uint8_t>(codes.size()));
  for (std::int16_t c : codes) put_u16(b, static_cast<std::uint16_t>(c));
  return b;
}

std::optional<std::vector<std::int16_t>> decode_weights(const std::uint8_t* p, std::size_t n) {
  if (n == 0 || p[0] > kMaxChannels || n != 1 + 2 * std::size_t{p[0]}) return std::nullopt;
  std::vector<std::int16_t> codes(p[0]);
  for (std::size_t i = 0; i < codes.size(); ++i)
    codes[i] = static_cast<std::int16_t>(get_u16(p + 1 + 2 * i));
  return codes;
}

std::vector<std::uint8_t> with_session(std::uint32_t session,
                                       const std::vector<std::uint8_t>& rest) {
  std::vector<std::uint8_t> b;
  b.reserve(4 + rest.size());
  put_u32(b, session);
  b.insert(b.end(), rest.begin(), rest.end());
  return b;
}

}  // namespace tp::device
