// The std::vector forms of the protocol's messages, for the host (stimctl, the emulators'
// tests).  The device core and the firmware use the allocation-free forms in protocol.hpp.

#include "device/protocol.hpp"

#include <cmath>

namespace tp::device {

std::vector<std::uint8_t> encode(const Capabilities& c) {
  std::vector<std::uint8_t> b;
  put_capabilities(b, c);
  return b;
}

// Version 5's 33 bytes, version 6's 39 or version 7's 41 (and later versions' 41, their own
// protocol byte): told by the length, which must agree with the protocol byte.
std::optional<Capabilities> decode_capabilities(const std::vector<std::uint8_t>& b,
                                                std::size_t at) {
  if (b.size() < at + kCapabilitiesSizeV5) return std::nullopt;
  const std::size_t size = b.size() - at;
  const bool v5 = b[at] <= 5, v6 = b[at] == 6;
  if (size != (v5 ? kCapabilitiesSizeV5 : v6 ? kCapabilitiesSizeV6 : kCapabilitiesSize))
    return std::nullopt;
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
  c.max_patterns = get_u16(p + 19);
  c.code_pool = get_u16(p + 21);
  c.min_gap_us = get_u16(p + 23);
  c.max_slip_us = get_u16(p + 25);
  c.max_rms_uA = get_u16(p + 27);
  c.max_mean_uA = get_u16(p + 29);
  c.max_pulse_rate_hz = get_u16(p + 31);
  if (v5) {  // no shapes; a biphasic pulse has at most 4 edges, which it checks as pulses
    c.max_phases = 0;
    c.features = 0;
    c.max_edge_rate_hz = 4u * c.max_pulse_rate_hz;
  } else {
    c.max_phases = p[33];
    c.features = p[34];
    c.max_edge_rate_hz = get_u32(p + 35);
  }
  // Version 7: the compliance voltage; the measuring feature only from a device that says it.
  c.compliance_V = v5 || v6 ? 0 : get_u16(p + 39);
  if (v5 || v6) c.features &= static_cast<std::uint8_t>(~kFeatureMeasures);
  if (c.max_edge_rate_hz == 0) return std::nullopt;
  if (c.channels == 0 || c.dac_step_nA == 0 || c.max_rate_hz == 0 || c.max_pulse_rate_hz == 0)
    return std::nullopt;
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
  if (p[0] > 1 || p[1] > static_cast<std::uint8_t>(kLastFault)) return std::nullopt;
  Status s;
  s.state = static_cast<State>(p[0]);
  s.fault = static_cast<Fault>(p[1]);
  s.pulses = get_u32(p + 2);
  s.weight_updates = get_u32(p + 6);
  s.rx_errors = get_u16(p + 10);
  s.line_errors = get_u16(p + 12);
  s.overruns = get_u16(p + 14);
  s.max_slip_us = get_u32(p + 16);
  s.deferred = get_u32(p + 20);
  return s;
}

std::vector<std::uint8_t> encode_weights(const std::vector<std::int16_t>& codes) {
  std::vector<std::uint8_t> b;
  b.push_back(static_cast<std::uint8_t>(codes.size()));
  for (std::int16_t c : codes) put_u16(b, static_cast<std::uint16_t>(c));
  return b;
}

std::vector<std::uint8_t> encode(const PatternTiming& t) {
  std::vector<std::uint8_t> b;
  put_timing(b, t);
  return b;
}

void add_dense(ChannelLoad& load, const std::vector<std::int16_t>& codes, const PatternTiming& t,
               int sign) {
  std::vector<std::uint8_t> ch;
  std::vector<std::int16_t> code;
  for (std::size_t i = 0; i < codes.size(); ++i)
    if (codes[i] != 0) {
      ch.push_back(static_cast<std::uint8_t>(i));
      code.push_back(codes[i]);
    }
  load.add(ch.data(), code.data(), ch.size(), t, sign);
}

std::vector<std::uint8_t> encode_sparse(const std::vector<std::int16_t>& dense) {
  std::vector<std::uint8_t> b{0};
  for (std::size_t i = 0; i < dense.size(); ++i)
    if (dense[i] != 0) {
      b.push_back(static_cast<std::uint8_t>(i));
      put_u16(b, static_cast<std::uint16_t>(dense[i]));
      ++b[0];
    }
  return b;
}

double ChannelLoad::rms_mA(std::size_t ch, std::uint32_t step_nA) const {
  return std::sqrt(static_cast<double>(ms_q16[ch]) / 65536.0) * step_nA * 1e-6;
}
double ChannelLoad::mean_mA(std::size_t ch, std::uint32_t step_nA) const {
  return static_cast<double>(mean_q16[ch]) / 65536.0 * step_nA * 1e-6;
}

std::optional<std::vector<std::int16_t>> decode_weights(const std::uint8_t* p, std::size_t n) {
  Codes c;
  if (!decode_codes(p, n, c)) return std::nullopt;
  return std::vector<std::int16_t>(c.begin(), c.end());
}

std::vector<std::uint8_t> encode(const Guards& g) {
  std::vector<std::uint8_t> b;
  put_guards(b, g);
  return b;
}

std::optional<Measurements> decode_measurements(const std::vector<std::uint8_t>& b,
                                                std::size_t at) {
  if (b.size() < at + kMeasurementsHeadSize) return std::nullopt;
  const std::uint8_t* p = b.data() + at;
  Measurements m;
  m.head.measured = get_u32(p);
  m.head.suspended = get_u32(p + 4);
  if (p[8] > static_cast<std::uint8_t>(kLastFault)) return std::nullopt;
  m.head.trip = static_cast<Fault>(p[8]);
  m.head.trip_channel = p[9];
  m.head.trip_t_us = get_u32(p + 10);
  m.head.trip_ohm = get_u32(p + 14);
  m.head.first = p[18];
  m.head.n = p[19];
  if (m.head.n > kMeasurementsPerReply ||
      b.size() != at + kMeasurementsHeadSize + m.head.n * kChannelMeasurementSize)
    return std::nullopt;
  for (std::size_t k = 0; k < m.head.n; ++k) {
    const std::uint8_t* q = p + kMeasurementsHeadSize + k * kChannelMeasurementSize;
    if (q[0] > 7) return std::nullopt;
    ChannelMeasurement c;
    c.carried = (q[0] & 1) != 0;
    c.at_rail = (q[0] & 2) != 0;
    c.suspended = (q[0] & 4) != 0;
    c.voltage_mV = static_cast<std::int32_t>(get_u32(q + 1));
    c.impedance_ohm = get_u32(q + 5);
    c.baseline_ohm = get_u32(q + 9);
    m.channels.push_back(c);
  }
  return m;
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
