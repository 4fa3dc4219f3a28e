#pragma once
// Byte-level framing of the stimulator protocol (docs/protocol.md), with no OS calls so
// that firmware can embed it.
//
//   0x7E | escaped( seq | type | length | payload (length bytes, <= kMaxPayload) | crc16 ) | 0x7E
//
// 0x7E and 0x7D inside a frame are sent as 0x7D followed by the byte XOR 0x20 (HDLC byte
// stuffing).  The CRC is CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF), big-endian, over
// seq, type, length and payload.  A frame whose length byte disagrees with what arrived,
// that fails its CRC, is too long or holds a bad escape is dropped whole: a receiver never
// acts on a damaged frame.  (The length byte matters: without it, a lost byte before a CRC
// ending in 0x00 passes the CRC far more often than 1 in 65536.)

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "device/fixed_bytes.hpp"

namespace tp::device {

inline constexpr std::uint8_t kFlag = 0x7E;
inline constexpr std::uint8_t kEscape = 0x7D;
inline constexpr std::size_t kMaxPayload = 200;

std::uint16_t crc16(const std::uint8_t* data, std::size_t n, std::uint16_t crc = 0xFFFF);

// The longest encoded frame: two flags and every other byte escaped.
inline constexpr std::size_t kMaxEncodedFrame = 2 + 2 * (3 + kMaxPayload + 2);

// A frame to send, as the host builds it.
struct Frame {
  std::uint8_t seq = 0;
  std::uint8_t type = 0;
  std::vector<std::uint8_t> payload;
};

// A received frame, in fixed storage (the device core allocates nothing).
struct RxFrame {
  std::uint8_t seq = 0;
  std::uint8_t type = 0;
  FixedBytes<kMaxPayload> payload;
  bool same_as(const RxFrame& o) const {
    return seq == o.seq && type == o.type && payload == o.payload;
  }
};

// Encodes one frame, handing each byte to put(std::uint8_t): no allocation.  n must be
// at most kMaxPayload.
template <class Put>
void encode_frame_to(std::uint8_t seq, std::uint8_t type, const std::uint8_t* payload,
                     std::size_t n, Put&& put) {
  const std::uint8_t head[3] = {seq, type, static_cast<std::uint8_t>(n)};
  const std::uint16_t crc = crc16(payload, n, crc16(head, 3));
  auto escaped = [&](std::uint8_t b) {
    if (b == kFlag || b == kEscape) {
      put(kEscape);
      put(static_cast<std::uint8_t>(b ^ 0x20));
    } else {
      put(b);
    }
  };
  put(kFlag);
  for (std::uint8_t b : head) escaped(b);
  for (std::size_t i = 0; i < n; ++i) escaped(payload[i]);
  escaped(static_cast<std::uint8_t>(crc >> 8));
  escaped(static_cast<std::uint8_t>(crc & 0xFF));
  put(kFlag);
}

// Appends the encoded frame to out (the host's form).
void encode_frame(const Frame& f, std::vector<std::uint8_t>& out);

class FrameDecoder {
 public:
  // Feeds one byte; true when it completed a valid frame, then available in frame().
  bool push(std::uint8_t byte);
  const RxFrame& frame() const { return frame_; }
  std::uint32_t errors() const { return errors_; }  // damaged frames dropped

 private:
  void reset() {
    len_ = 0;
    escaped_ = false;
    broken_ = false;
  }
  std::array<std::uint8_t, kMaxPayload + 5> buf_{};
  std::size_t len_ = 0;
  bool escaped_ = false;
  bool broken_ = false;
  bool started_ = false;
  std::uint32_t errors_ = 0;
  RxFrame frame_;
};

}  // namespace tp::device
