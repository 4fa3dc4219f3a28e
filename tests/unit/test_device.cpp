// The device side: framing, the device core's refusals, watchdog and retransmissions,
// and the host's quantisation.  Includes a long randomised test of the frame decoder.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>

#include "core/error.hpp"
#include "device/device_core.hpp"
#include "host/stimulator.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;
using namespace tp::device;

namespace {

std::vector<std::uint8_t> frame_bytes(std::uint8_t seq, Msg type,
                                      const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> out;
  encode_frame(Frame{seq, static_cast<std::uint8_t>(type), payload}, out);
  return out;
}

// Sends one request to the core and returns the ack's result.
Result send(DeviceCore& core, std::uint8_t seq, Msg type, const std::vector<std::uint8_t>& payload,
            std::uint64_t now_us, std::vector<std::uint8_t>* body = nullptr) {
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

PulseConfig config8() {
  PulseConfig c;
  c.period_us = 5000;
  c.width_us = 200;
  c.balance_width_us = 400;
  c.channels = 8;
  return c;
}

}  // namespace

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
  CHECK(d.frame().payload == f.payload);
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
      const bool same =
          d.frame().seq == f.seq && d.frame().type == f.type && d.frame().payload == f.payload;
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

TEST_CASE("the device refuses what breaks a limit, and a refusal changes nothing",
          "[device][core]") {
  DeviceCore core(Capabilities{});
  const std::int16_t max = Capabilities{}.max_code();
  std::vector<std::int16_t> ok = {100, -50, -50, 0, 0, 0, 0, 0};
  CHECK(send(core, 1, Msg::set_weights, encode_weights(ok), 0) == Result::not_configured);
  CHECK(send(core, 2, Msg::start, {}, 0) == Result::not_configured);
  PulseConfig bad = config8();
  bad.width_us = 5;
  CHECK(send(core, 3, Msg::configure, encode(bad), 0) == Result::out_of_range);
  bad = config8();
  bad.balance_width_us = 100;  // shorter than the main phase: higher than it
  CHECK(send(core, 4, Msg::configure, encode(bad), 0) == Result::out_of_range);
  bad = config8();
  bad.period_us = 500;  // 2 kHz
  CHECK(send(core, 5, Msg::configure, encode(bad), 0) == Result::out_of_range);
  bad = config8();
  bad.channels = 9;
  CHECK(send(core, 6, Msg::configure, encode(bad), 0) == Result::channel_mismatch);
  CHECK(send(core, 7, Msg::configure, encode(config8()), 0) == Result::ok);
  CHECK(send(core, 8, Msg::set_weights, encode_weights(ok), 0) == Result::ok);
  std::vector<std::int16_t> over = {
      static_cast<std::int16_t>(max + 1), static_cast<std::int16_t>(-max - 1), 0, 0, 0, 0, 0, 0};
  CHECK(send(core, 9, Msg::set_weights, encode_weights(over), 0) == Result::out_of_range);
  std::vector<std::int16_t> unbalanced = {100, -99, 0, 0, 0, 0, 0, 0};
  CHECK(send(core, 10, Msg::set_weights, encode_weights(unbalanced), 0) == Result::sum_not_zero);
  CHECK(send(core, 11, Msg::set_weights, encode_weights({100, -100}), 0) ==
        Result::channel_mismatch);
  CHECK(send(core, 12, Msg::set_weights, {3, 1}, 0) == Result::bad_length);
  CHECK(send(core, 13, Msg::start, {}, 0) == Result::ok);
  CHECK(send(core, 14, Msg::configure, encode(config8()), 0) == Result::bad_state);
  // Pulses carry the last accepted weights only.
  std::vector<std::vector<std::int16_t>> seen;
  core.advance(20000, [&](const DeliveredPulse& p) { seen.push_back(p.codes); });
  REQUIRE(seen.size() == 5);  // t = 0, 5, 10, 15, 20 ms
  for (const auto& s : seen) CHECK(s == ok);
  CHECK(send(core, 15, Msg::stop, {}, 20000) == Result::ok);
  core.advance(100000, [&](const DeliveredPulse&) { FAIL("pulse after stop"); });
}

TEST_CASE("the watchdog stops output when keep-alives stop", "[device][core][watchdog]") {
  Capabilities caps;
  caps.watchdog_ms = 300;
  DeviceCore core(caps);
  send(core, 1, Msg::configure, encode(config8()), 0);
  send(core, 2, Msg::set_weights, encode_weights({10, -10, 0, 0, 0, 0, 0, 0}), 0);
  send(core, 3, Msg::start, {}, 1000);
  std::vector<std::uint64_t> t;
  auto sink = [&](const DeliveredPulse& p) { t.push_back(p.t_us); };
  core.advance(200000, sink);
  send(core, 4, Msg::keepalive, {}, 200000);  // fed at 0.2 s: deadline 0.5 s
  core.advance(2000000, sink);
  CHECK(core.status().state == State::idle);
  CHECK(core.status().fault == Fault::watchdog);
  REQUIRE(!t.empty());
  CHECK(t.back() < 500000);
  CHECK(t.back() >= 495000);
  std::vector<std::uint8_t> body;
  CHECK(send(core, 5, Msg::status, {}, 2000000, &body) == Result::ok);
  CHECK(decode_status(body, 0)->fault == Fault::watchdog);
}

TEST_CASE("the device stops by itself after max_pulses", "[device][core]") {
  DeviceCore core(Capabilities{});
  PulseConfig c = config8();
  c.max_pulses = 7;
  send(core, 1, Msg::configure, encode(c), 0);
  send(core, 2, Msg::set_weights, encode_weights({10, -10, 0, 0, 0, 0, 0, 0}), 0);
  send(core, 3, Msg::start, {}, 0);
  int n = 0;
  for (std::uint64_t now = 0; now < 100000; now += 1000) {
    send(core, static_cast<std::uint8_t>(4 + now / 1000), Msg::keepalive, {}, now);
    core.advance(now, [&](const DeliveredPulse&) { ++n; });
  }
  CHECK(n == 7);
  CHECK(core.status().fault == Fault::completed);
}

TEST_CASE("a retransmitted request is answered again but executed once", "[device][core]") {
  DeviceCore core(Capabilities{});
  send(core, 1, Msg::configure, encode(config8()), 0);
  const auto w = encode_weights({10, -10, 0, 0, 0, 0, 0, 0});
  CHECK(send(core, 2, Msg::set_weights, w, 0) == Result::ok);
  CHECK(send(core, 2, Msg::set_weights, w, 0) == Result::ok);
  CHECK(core.status().weight_updates == 1);
  CHECK(send(core, 3, Msg::set_weights, w, 0) == Result::ok);
  CHECK(core.status().weight_updates == 2);
}

TEST_CASE("host quantisation: codes sum to exactly zero and stay within half a step or so",
          "[device][quantize]") {
  Capabilities caps;
  const double step = caps.dac_step_nA * 1e-6;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<double> c(8);
    for (auto& v : c) v = u(rng);
    const double mean = std::accumulate(c.begin(), c.end(), 0.0) / 8;
    for (auto& v : c) v -= mean;
    const auto codes = host::quantize_currents(c, caps);
    CHECK(std::accumulate(codes.begin(), codes.end(), 0L) == 0);
    for (std::size_t i = 0; i < c.size(); ++i)
      CHECK(std::fabs(codes[i] * step - c[i]) <= 1.5 * step);
  }
}

TEST_CASE("stimulus checks: limits, zero sum, balance; safety figures", "[pulse]") {
  Stimulus s;
  s.currents_mA = {1.0, -0.5, -0.5};
  s.count = 200;
  s.shape.balance_width_us = 400;  // longer and lower: -0.5x for 400 us
  CHECK_NOTHROW(check_stimulus(s, StimulusLimits{}));
  const SafetyFigures f = safety_figures(s);
  CHECK(f.peak_current_mA == 1.0);
  CHECK(f.max_charge_per_phase_nC == Approx(200.0));  // 1 mA x 200 us
  CHECK(f.max_net_charge_nC < 1e-12);
  CHECK(f.max_charge_density_uC_per_cm2 == Approx(200.0 / 5.0 * 0.1));  // 200 nC over 5 mm^2
  CHECK(f.max_rms_current_mA == Approx(std::sqrt((1.0 * 200 + 0.25 * 400) / 5000.0)));
  Stimulus bad = s;
  bad.currents_mA = {2.5, -2.5, 0};
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
  bad.currents_mA = {1.0, -0.9, 0};
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
  bad = s;
  bad.shape.frequency_hz = 2000;
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
  bad = s;
  bad.shape.width_us = 900;
  bad.shape.balance_width_us = 4500;  // does not fit a 5 ms period
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
}
