#pragma once
// The unit tests' way of talking to a device core: whole frames in, the ack's result out.
#include <catch2/catch.hpp>

#include <utility>
#include <vector>

#include "device/device_core.hpp"

namespace tp::device {

inline std::vector<std::uint8_t> frame_bytes(std::uint8_t seq, Msg type,
                                             const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> out;
  encode_frame(Frame{seq, static_cast<std::uint8_t>(type), payload}, out);
  return out;
}

// Protocol 6's shaped timing: a period, then (duration_us, units) phases.
inline PatternTiming shaped_timing(
    std::uint32_t period_us, const std::vector<std::pair<std::uint16_t, std::int16_t>>& phases,
    std::uint32_t phase_us = 0, std::uint32_t max_pulses = 0) {
  PatternTiming t;
  t.period_us = period_us;
  t.phase_us = phase_us;
  t.max_pulses = max_pulses;
  t.width_us = t.interphase_us = t.balance_width_us = 0;
  t.shape.n = static_cast<std::uint8_t>(phases.size());
  for (std::size_t k = 0; k < phases.size() && k < kMaxPhases; ++k) {
    t.shape.duration_us[k] = phases[k].first;
    t.shape.units[k] = phases[k].second;
  }
  return t;
}

// A set_shape payload: the token, the pattern's index, its shaped timing.
inline std::vector<std::uint8_t> shape_frame(std::uint32_t token, std::uint16_t index,
                                             const PatternTiming& t) {
  std::vector<std::uint8_t> b;
  put_u32(b, token);
  put_u16(b, index);
  put_shape_pattern(b, t);
  return b;
}

// Sends one request to the core and returns the ack's result.
inline Result send(DeviceCore& core, std::uint8_t seq, Msg type,
                   const std::vector<std::uint8_t>& payload, std::uint64_t now_us,
                   std::vector<std::uint8_t>* body = nullptr) {
  const auto bytes = frame_bytes(seq, type, payload);
  std::vector<std::uint8_t> out;
  core.receive(bytes.data(), bytes.size(), now_us, out);
  FrameDecoder d;
  for (std::uint8_t b : out)
    if (d.push(b)) {
      REQUIRE(d.frame().type == static_cast<std::uint8_t>(Msg::ack));
      REQUIRE(d.frame().seq == seq);
      if (body) body->assign(d.frame().payload.begin() + 2, d.frame().payload.end());
      return static_cast<Result>(d.frame().payload[1]);
    }
  FAIL("no acknowledgement");
  return Result::ok;
}

}  // namespace tp::device
