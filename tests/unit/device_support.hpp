#pragma once
// The unit tests' way of talking to a device core: whole frames in, the ack's result out.
#include <catch2/catch.hpp>

#include <vector>

#include "device/device_core.hpp"

namespace tp::device {

inline std::vector<std::uint8_t> frame_bytes(std::uint8_t seq, Msg type,
                                             const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> out;
  encode_frame(Frame{seq, static_cast<std::uint8_t>(type), payload}, out);
  return out;
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
