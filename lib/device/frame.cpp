#include "device/frame.hpp"

namespace tp::device {

std::uint16_t crc16(const std::uint8_t* data, std::size_t n, std::uint16_t crc) {
  for (std::size_t i = 0; i < n; ++i) {
    crc = static_cast<std::uint16_t>(crc ^ (data[i] << 8));
    for (int b = 0; b < 8; ++b)
      crc = static_cast<std::uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
  }
  return crc;
}

void encode_frame(const Frame& f, std::vector<std::uint8_t>& out) {
  encode_frame_to(f.seq, f.type, f.payload.data(), f.payload.size(),
                  [&](std::uint8_t b) { out.push_back(b); });
}

bool FrameDecoder::push(std::uint8_t byte) {
  if (byte == kFlag) {
    const bool had_content = len_ > 0 || broken_;
    bool ok = false;
    // seq, type, length, payload, crc: the length must match, then the CRC.
    if (started_ && !broken_ && !escaped_ && len_ >= 5 && buf_[2] == len_ - 5) {
      const std::uint16_t crc = static_cast<std::uint16_t>((buf_[len_ - 2] << 8) | buf_[len_ - 1]);
      if (crc16(buf_.data(), len_ - 2) == crc) {
        frame_.seq = buf_[0];
        frame_.type = buf_[1];
        frame_.payload.assign(buf_.data() + 3, buf_.data() + (len_ - 2));
        ok = true;
      }
    }
    if (!ok && started_ && had_content) ++errors_;
    started_ = true;  // a flag both ends one frame and opens the next
    reset();
    return ok;
  }
  if (!started_ || broken_) return false;  // wait for a flag
  if (byte == kEscape) {
    if (escaped_) broken_ = true;
    escaped_ = true;
    return false;
  }
  if (escaped_) {
    if (byte != (kFlag ^ 0x20) && byte != (kEscape ^ 0x20)) {
      broken_ = true;
      return false;
    }
    byte = static_cast<std::uint8_t>(byte ^ 0x20);
    escaped_ = false;
  }
  if (len_ == buf_.size()) {
    broken_ = true;  // too long: drop until the next flag
    return false;
  }
  buf_[len_++] = byte;
  return false;
}

}  // namespace tp::device
