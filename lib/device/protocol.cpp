#include "device/protocol.hpp"

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

std::vector<std::uint8_t> encode(const Capabilities& c) {
  std::vector<std::uint8_t> b;
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
  if (b.size() != at + 18) return std::nullopt;
  const std::uint8_t* p = b.data() + at;
  Capabilities c;
  c.channels = p[0];
  c.max_current_uA = get_u16(p + 1);
  c.dac_step_nA = get_u16(p + 3);
  c.min_width_us = get_u16(p + 5);
  c.max_width_us = get_u16(p + 7);
  c.max_balance_width_us = get_u16(p + 9);
  c.max_rate_hz = get_u16(p + 11);
  c.watchdog_ms = get_u16(p + 13);
  c.fw_major = p[15];
  c.fw_minor = p[16];
  c.fw_patch = p[17];
  if (c.channels == 0 || c.dac_step_nA == 0) return std::nullopt;
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

std::optional<PulseConfig> decode_config(const std::vector<std::uint8_t>& b) {
  if (b.size() != 15) return std::nullopt;
  PulseConfig c;
  c.period_us = get_u32(b.data());
  c.width_us = get_u16(b.data() + 4);
  c.interphase_us = get_u16(b.data() + 6);
  c.balance_width_us = get_u16(b.data() + 8);
  c.channels = b[10];
  c.max_pulses = get_u32(b.data() + 11);
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
  if (b.size() != at + 12) return std::nullopt;
  const std::uint8_t* p = b.data() + at;
  if (p[0] > 1 || p[1] > 3) return std::nullopt;
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

std::optional<std::vector<std::int16_t>> decode_weights(const std::vector<std::uint8_t>& b) {
  if (b.empty() || b.size() != 1 + 2 * std::size_t{b[0]}) return std::nullopt;
  std::vector<std::int16_t> codes(b[0]);
  for (std::size_t i = 0; i < codes.size(); ++i)
    codes[i] = static_cast<std::int16_t>(get_u16(b.data() + 1 + 2 * i));
  return codes;
}

}  // namespace tp::device
