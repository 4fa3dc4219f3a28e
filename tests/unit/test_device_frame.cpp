// The device protocol's frames: CRC, byte stuffing, the decoder (with a long randomised
// test) and the fixed buffers that refuse what does not fit (lib/device/frame).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>

#include <nlohmann/json.hpp>
#include "core/error.hpp"
#include "device/config_block.hpp"
#include "device/device_core.hpp"
#include "device/pulse_record.hpp"
#include "device_support.hpp"
#include "host/session.hpp"
#include "host/stimulator.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;
using namespace tp::device;


TEST_CASE("CRC-16/CCITT-FALSE check value", "[device][frame]") {
  const char* s = "123456789";
  CHECK(crc16(reinterpret_cast<const std::uint8_t*>(s), 9) == 0x29B1);
}

TEST_CASE("frames round-trip through stuffing, with flags and escapes in the payload",
          "[device][frame]") {
  const Frame f{0x7E, 0x7D, {0x7E, 0x7D, 0x00, 0xFF, 0x7E, 0x20, 0x5E}};
  std::vector<std::uint8_t> bytes;
  encode_frame(f, bytes);
  CHECK(std::count(bytes.begin(), bytes.end(), kFlag) == 2);  // only the delimiters
  FrameDecoder d;
  int frames = 0;
  for (std::uint8_t b : {std::uint8_t{0x13}, std::uint8_t{0x37}}) d.push(b);  // line noise first
  for (std::uint8_t b : bytes) frames += d.push(b);
  REQUIRE(frames == 1);
  CHECK(d.frame().seq == f.seq);
  CHECK(d.frame().type == f.type);
  CHECK(d.frame().payload.same_as(f.payload));
}

TEST_CASE("a damaged frame is dropped and the decoder resynchronises", "[device][frame]") {
  auto a = frame_bytes(1, Msg::keepalive, {});
  auto b = frame_bytes(2, Msg::status, {});
  a[3] ^= 0x01;  // flip one bit of the first frame
  FrameDecoder d;
  std::vector<int> seqs;
  for (auto* v : {&a, &b})
    for (std::uint8_t x : *v)
      if (d.push(x)) seqs.push_back(d.frame().seq);
  CHECK(seqs == std::vector<int>{2});
  CHECK(d.errors() >= 1);
}

TEST_CASE("randomised decoder fuzz: no crash, no damaged frame accepted", "[device][frame][fuzz]") {
  const auto t0 = std::chrono::steady_clock::now();
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<int> byte(0, 255), len(0, 40), pick(0, 99);
  long accepted_wrong_drop = 0, drop_trials = 0, frames_checked = 0, noise_accepted = 0;
  // TP_FUZZ_ITERATIONS sets the length (default 1,000,000: a few seconds).
  const char* env = std::getenv("TP_FUZZ_ITERATIONS");
  const long iterations = env ? std::atol(env) : 1000000;
  FrameDecoder d;
  for (long it = 0; it < iterations; ++it) {
    d = FrameDecoder{};  // each case on its own, so that every acceptance is attributed right
    Frame f{static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)), {}};
    for (int i = len(rng); i > 0; --i) f.payload.push_back(static_cast<std::uint8_t>(byte(rng)));
    std::vector<std::uint8_t> bytes;
    encode_frame(f, bytes);
    const int kind = pick(rng);
    if (kind < 40) {  // 1 to 3 bit flips inside the frame: CRC-16 (distance 4) catches all
      const int flips = 1 + pick(rng) % 3;
      std::vector<std::size_t> done;
      for (int k = 0; k < flips; ++k) {
        std::size_t pos;
        do pos = 1 + static_cast<std::size_t>(pick(rng) * 997) % (bytes.size() - 2);
        while (std::find(done.begin(), done.end(), pos) != done.end());
        done.push_back(pos);
        bytes[pos] = static_cast<std::uint8_t>(bytes[pos] ^ (1u << (pick(rng) % 8)));
      }
    } else if (kind < 60) {  // a dropped byte
      bytes.erase(bytes.begin() + 1 +
                  static_cast<long>(static_cast<std::size_t>(pick(rng) * 31) % (bytes.size() - 2)));
      ++drop_trials;
    } else if (kind < 70) {  // pure noise
      for (auto& b : bytes) b = static_cast<std::uint8_t>(byte(rng));
    }
    const bool intact = kind >= 70;
    bool got = false;
    for (std::uint8_t b : bytes) {
      if (!d.push(b)) continue;
      const bool same = d.frame().seq == f.seq && d.frame().type == f.type &&
                        d.frame().payload.same_as(f.payload);
      if (intact) {
        CHECK(same);
        got = true;
      } else if (kind < 40) {
        FAIL("a frame with 1-3 flipped bits was accepted");
      } else if (kind < 60 && !same) {
        ++accepted_wrong_drop;  // only by a CRC collision, ~1/65536
      } else if (kind >= 60) {
        ++noise_accepted;  // random bytes that happen to form a valid frame
      }
    }
    if (intact) {
      CHECK(got);
      ++frames_checked;
    }
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WARN("decoder fuzz: " << iterations << " cases (" << frames_checked << " intact frames) in "
                        << secs << " s; frames with a dropped byte accepted by CRC collision: "
                        << accepted_wrong_drop << " of " << drop_trials
                        << "; noise runs forming a valid frame: " << noise_accepted);
  CHECK(accepted_wrong_drop <= drop_trials / 100000);
}

TEST_CASE("fixed buffers refuse what does not fit and remember it", "[device][frame]") {
  FixedBytes<3> b;
  const std::uint8_t x[4] = {1, 2, 3, 4};
  b.append(x, 4);
  CHECK(b.size() == 3);
  CHECK(b.overflowed());
  CHECK(b.same_as(std::vector<std::uint8_t>{1, 2, 3}));
  b.clear();
  CHECK_FALSE(b.overflowed());
  // The longest frame fits the device's reply buffer.
  std::vector<std::uint8_t> out;
  encode_frame(Frame{0x7E, 0x7D, std::vector<std::uint8_t>(kMaxPayload, 0x7E)}, out);
  CHECK(out.size() <= kMaxEncodedFrame);
}
