// The std::vector forms of the protocol's messages, for the host (stimctl, the emulators'
// tests).  The device core and the firmware use the allocation-free forms in protocol.hpp.

#include "device/protocol.hpp"

namespace tp::device {

std::vector<std::uint8_t> encode(const Capabilities& c) {
  std::vector<std::uint8_t> b;
  put_capabilities(b, c);
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
  put_config(b, c);
  return b;
}

std::vector<std::uint8_t> encode(const Status& s) {
  std::vector<std::uint8_t> b;
  put_status(b, s);
  return b;
}

std::optional<Status> decode_status(const std::vector<std::uint8_t>& b, std::size_t at) {
  if (b.size() != at + kStatusSize) return std::nullopt;
  const std::uint8_t* p = b.data() + at;
  if (p[0] > 1 || p[1] > 5) return std::nullopt;
  Status s;
  s.state = static_cast<State>(p[0]);
  s.fault = static_cast<Fault>(p[1]);
  s.pulses = get_u32(p + 2);
  s.weight_updates = get_u32(p + 6);
  s.rx_errors = get_u16(p + 10);
  s.line_errors = get_u16(p + 12);
  s.overruns = get_u16(p + 14);
  return s;
}

std::vector<std::uint8_t> encode_weights(const std::vector<std::int16_t>& codes) {
  std::vector<std::uint8_t> b;
  b.push_back(static_cast<std::uint8_t>(codes.size()));
  for (std::int16_t c : codes) put_u16(b, static_cast<std::uint16_t>(c));
  return b;
}

std::optional<std::vector<std::int16_t>> decode_weights(const std::uint8_t* p, std::size_t n) {
  Codes c;
  if (!decode_codes(p, n, c)) return std::nullopt;
  return std::vector<std::int16_t>(c.begin(), c.end());
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
