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

namespace {

constexpr std::uint32_t kToken = 0xC0FFEE01u;
std::vector<std::uint8_t> token() {
  return with_session(kToken, {});
}
std::vector<std::uint8_t> configure(const PulseConfig& c) {
  return with_session(kToken, encode(c));
}
std::vector<std::uint8_t> weights(const std::vector<std::int16_t>& codes) {
  return with_session(kToken, encode_weights(codes));
}

PulseConfig config8() {
  PulseConfig c;
  c.period_us = 5000;
  c.width_us = 200;
  c.balance_width_us = 400;
  c.channels = 8;
  return c;
}

// An output of the session kToken: configure c (seq 1), codes 10 and -10 (seq 2), start
// at start_us (seq 3).  Returns the start's result.
Result start_output(DeviceCore& core, std::uint64_t start_us, const PulseConfig& c = config8()) {
  send(core, 1, Msg::configure, configure(c), 0);
  send(core, 2, Msg::set_weights, weights({10, -10, 0, 0, 0, 0, 0, 0}), 0);
  return send(core, 3, Msg::start, token(), start_us);
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

TEST_CASE("the device refuses what breaks a limit, and a refusal changes nothing",
          "[device][core]") {
  DeviceCore core(Capabilities{});
  const auto max = static_cast<std::int16_t>(Capabilities{}.max_code());
  std::vector<std::int16_t> ok = {100, -50, -50, 0, 0, 0, 0, 0};
  CHECK(send(core, 1, Msg::set_weights, weights(ok), 0) == Result::wrong_session);
  CHECK(send(core, 2, Msg::start, token(), 0) == Result::wrong_session);
  PulseConfig bad = config8();
  bad.width_us = 5;
  CHECK(send(core, 3, Msg::configure, configure(bad), 0) == Result::out_of_range);
  bad = config8();
  bad.balance_width_us = 100;  // shorter than the main phase: higher than it
  CHECK(send(core, 4, Msg::configure, configure(bad), 0) == Result::out_of_range);
  bad = config8();
  bad.period_us = 500;  // 2 kHz
  CHECK(send(core, 5, Msg::configure, configure(bad), 0) == Result::out_of_range);
  bad = config8();
  bad.channels = 9;
  CHECK(send(core, 6, Msg::configure, configure(bad), 0) == Result::channel_mismatch);
  bad = config8();
  bad.period_us = hard::max_period_us + 1;  // slower than 0.1 Hz
  CHECK(send(core, 16, Msg::configure, configure(bad), 0) == Result::out_of_range);
  CHECK(send(core, 17, Msg::configure, with_session(0, encode(config8())), 0) ==
        Result::wrong_session);  // 0 is no session
  CHECK(send(core, 18, Msg::configure, encode(config8()), 0) == Result::bad_length);  // no token
  CHECK(send(core, 7, Msg::configure, configure(config8()), 0) == Result::ok);
  CHECK(send(core, 19, Msg::start, token(), 0) == Result::not_configured);  // no weights yet
  CHECK(send(core, 8, Msg::set_weights, weights(ok), 0) == Result::ok);
  std::vector<std::int16_t> over = {
      static_cast<std::int16_t>(max + 1), static_cast<std::int16_t>(-max - 1), 0, 0, 0, 0, 0, 0};
  CHECK(send(core, 9, Msg::set_weights, weights(over), 0) == Result::out_of_range);
  std::vector<std::int16_t> unbalanced = {100, -99, 0, 0, 0, 0, 0, 0};
  CHECK(send(core, 10, Msg::set_weights, weights(unbalanced), 0) == Result::sum_not_zero);
  CHECK(send(core, 11, Msg::set_weights, weights({100, -100}), 0) == Result::channel_mismatch);
  CHECK(send(core, 12, Msg::set_weights, with_session(kToken, {3, 1}), 0) == Result::bad_length);
  CHECK(send(core, 20, Msg::set_weights, {1, 2}, 0) == Result::bad_length);  // shorter than a token
  CHECK(send(core, 13, Msg::start, token(), 0) == Result::ok);
  CHECK(send(core, 14, Msg::configure, configure(config8()), 0) == Result::bad_state);
  // Pulses carry the last accepted weights only.
  std::vector<std::vector<std::int16_t>> seen;
  core.advance(20000,
               [&](const DeliveredPulse& p) { seen.emplace_back(p.codes.begin(), p.codes.end()); });
  REQUIRE(seen.size() == 5);  // t = 0, 5, 10, 15, 20 ms
  for (const auto& s : seen) CHECK(s == ok);
  CHECK(send(core, 15, Msg::stop, {}, 20000) == Result::ok);
  core.advance(100000, [&](const DeliveredPulse&) { FAIL("pulse after stop"); });
  CHECK(core.status().fault == Fault::stopped);
}

TEST_CASE("the watchdog stops output when the session's keep-alives stop",
          "[device][core][watchdog]") {
  Capabilities caps;
  caps.watchdog_ms = 300;
  DeviceCore core(caps);
  start_output(core, 1000);
  std::vector<std::uint64_t> t;
  auto sink = [&](const DeliveredPulse& p) { t.push_back(p.t_us); };
  for (std::uint64_t now = 1000; now <= 200000; now += 1000) core.advance(now, sink);
  send(core, 4, Msg::keepalive, token(), 200000);  // fed at 0.2 s: deadline 0.5 s
  for (std::uint64_t now = 200000; now <= 2000000; now += 1000) core.advance(now, sink);
  CHECK(core.status().state == State::idle);
  CHECK(core.status().fault == Fault::watchdog);
  REQUIRE(!t.empty());
  CHECK(t.back() < 500000);
  CHECK(t.back() >= 495000);
  std::vector<std::uint8_t> body;
  CHECK(send(core, 5, Msg::status, {}, 2000000, &body) == Result::ok);
  CHECK(decode_status(body, 0)->fault == Fault::watchdog);
  // The watchdog ended the session: its keep-alive is refused from now on.
  CHECK(send(core, 6, Msg::keepalive, token(), 2000000) == Result::wrong_session);
}

TEST_CASE("a late frame cannot revive an expired session, and late pulses never come in a burst",
          "[device][core][watchdog]") {
  Capabilities caps;
  caps.watchdog_ms = 300;
  DeviceCore core(caps);
  start_output(core, 0);
  int n = 0;
  core.advance(100000, [&](const DeliveredPulse&) { ++n; });
  CHECK(n == 21);  // 0, 5, ..., 100 ms
  // Nothing advanced the device for 2 s (a descheduled emulator); then the session's
  // keep-alive arrives, late.  The watchdog ran out at 0.3 s: the session is over.
  CHECK(send(core, 4, Msg::keepalive, token(), 2100000) == Result::wrong_session);
  CHECK(core.status().state == State::idle);
  CHECK(core.status().fault == Fault::watchdog);
  core.advance(2100000, [&](const DeliveredPulse&) { ++n; });
  CHECK(n == 21);  // no catch-up burst of the 400 missed slots
  // Running, but advanced late: slots older than kMaxLateUs are skipped, not delivered.
  send(core, 5, Msg::configure, configure(config8()), 3000000);
  send(core, 6, Msg::set_weights, weights({10, -10, 0, 0, 0, 0, 0, 0}), 3000000);
  send(core, 7, Msg::start, token(), 3000000);
  std::vector<std::uint64_t> t;
  core.advance(3000000, [&](const DeliveredPulse& p) { t.push_back(p.t_us); });
  send(core, 8, Msg::keepalive, token(), 3250000);
  core.advance(3250000, [&](const DeliveredPulse& p) { t.push_back(p.t_us); });
  REQUIRE(!t.empty());
  for (std::uint64_t x : t) CHECK((x == 3000000 || x + kMaxLateUs >= 3250000));
  CHECK(t.size() <= 1 + kMaxLateUs / 5000 + 1);
}

TEST_CASE("only the session that started the output keeps it alive",
          "[device][core][watchdog][session]") {
  Capabilities caps;
  caps.watchdog_ms = 300;
  DeviceCore core(caps);
  REQUIRE(start_output(core, 0) == Result::ok);
  // A second host every 20 ms: identify, status, its own configure (refused: running), a
  // keep-alive and weights with another token, a frame with no token.  None may feed the
  // watchdog: the output stops 300 ms after the owner's last frame (t = 0).
  const std::uint32_t other = kToken ^ 0x5A5A5A5Au;
  std::uint8_t seq = 10;
  std::uint64_t last = 0;
  for (std::uint64_t now = 20000; now <= 1000000; now += 20000) {
    core.advance(now, [&](const DeliveredPulse& p) { last = p.t_us; });
    CHECK(send(core, seq++, Msg::identify, {}, now) == Result::ok);
    CHECK(send(core, seq++, Msg::status, {}, now) == Result::ok);
    const Result c = send(core, seq++, Msg::configure, with_session(other, encode(config8())), now);
    CHECK((c == Result::bad_state || c == Result::ok));
    if (c == Result::ok) break;  // the output had stopped: a new session may begin
    CHECK(send(core, seq++, Msg::keepalive, with_session(other, {}), now) == Result::wrong_session);
    CHECK(send(core, seq++, Msg::set_weights,
               with_session(other, encode_weights({5, -5, 0, 0, 0, 0, 0, 0})),
               now) == Result::wrong_session);
    CHECK(send(core, seq++, Msg::keepalive, {}, now) == Result::bad_length);
  }
  CHECK(core.status().fault == Fault::watchdog);
  CHECK(last < 300000);
  CHECK(last >= 295000);
  CHECK(core.status().weight_updates == 1);  // the other host's weights never applied
}

TEST_CASE("stop disarms: a replayed start cannot restart an old stimulus",
          "[device][core][session]") {
  DeviceCore core(Capabilities{});
  send(core, 1, Msg::configure, configure(config8()), 0);
  send(core, 2, Msg::set_weights, weights({10, -10, 0, 0, 0, 0, 0, 0}), 0);
  const auto start = frame_bytes(3, Msg::start, token());
  std::vector<std::uint8_t> out;
  core.receive(start.data(), start.size(), 0, out);
  REQUIRE(core.status().state == State::running);
  CHECK(send(core, 4, Msg::stop, token(), 10000) == Result::ok);
  // The same start frame again (a delayed copy on the line), and with a new seq.
  out.clear();
  core.receive(start.data(), start.size(), 20000, out);
  CHECK(core.status().state == State::idle);
  CHECK(send(core, 5, Msg::start, token(), 20000) == Result::wrong_session);
  CHECK(send(core, 6, Msg::set_weights, weights({10, -10, 0, 0, 0, 0, 0, 0}), 20000) ==
        Result::wrong_session);
  core.advance(1000000, [&](const DeliveredPulse& p) {
    if (p.t_us >= 10000) FAIL("pulse after stop");
  });
  // A new session needs a new configuration and weights; the old weights are gone.
  CHECK(send(core, 7, Msg::configure, configure(config8()), 30000) == Result::ok);
  CHECK(send(core, 8, Msg::start, token(), 30000) == Result::not_configured);
}

TEST_CASE("the device's compile-time bounds cannot be raised by its configuration",
          "[device][core][limits]") {
  Capabilities caps;
  caps.max_current_uA = 30000;  // 30 mA asked for
  caps.max_width_us = 60000;
  caps.max_rate_hz = 60000;
  caps.watchdog_ms = 60000;
  caps.channels = 255;
  DeviceCore core(caps);
  CHECK(core.caps().max_current_uA == hard::max_current_uA);
  CHECK(core.caps().max_width_us == hard::max_width_us);
  CHECK(core.caps().max_rate_hz == hard::max_rate_hz);
  CHECK(core.caps().watchdog_ms == hard::max_watchdog_ms);
  CHECK(core.caps().channels == kMaxChannels);
  // A raw frame of 29 mA codes (what --max-current 30 let through) is refused.
  send(core, 1, Msg::configure, configure(config8()), 0);
  const auto code29 = static_cast<std::int16_t>(29000000 / caps.dac_step_nA);
  CHECK(send(core, 2, Msg::set_weights,
             weights({code29, static_cast<std::int16_t>(-code29), 0, 0, 0, 0, 0, 0}),
             0) == Result::out_of_range);
  CHECK(core.status().weight_updates == 0);
}

TEST_CASE("the largest DAC code never wraps, up to a 16-bit DAC", "[device][limits]") {
  for (int step : {1, 30, 61, 62, 977, 7874}) {
    Capabilities c;
    c.dac_step_nA = static_cast<std::uint16_t>(step);
    CHECK(c.max_code() > 0);
    CHECK(c.max_code() <= hard::max_dac_code);
    CHECK(c.max_code() * std::int64_t{step} <= std::int64_t{c.max_current_uA} * 1000);
  }
}

TEST_CASE("frames carry at most kMaxChannels codes, at both ends", "[device][limits]") {
  std::vector<std::int16_t> many(kMaxChannels + 1, 0);
  const auto b = encode_weights(many);
  CHECK_FALSE(decode_weights(b.data(), b.size()));
  std::vector<std::int16_t> most(kMaxChannels, 0);
  const auto c = with_session(kToken, encode_weights(most));
  CHECK(c.size() <= kMaxPayload);
  CHECK(decode_weights(c.data() + 4, c.size() - 4));
  Capabilities caps;
  caps.channels = 200;
  CHECK_THROWS_AS(host::check_device(caps), Error);
  try {
    host::check_device(caps);
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
  }
}

TEST_CASE("the host refuses a device whose watchdog it cannot honour", "[device][limits]") {
  Capabilities caps;
  for (int ms : {99, 301, 1000}) {
    caps.watchdog_ms = static_cast<std::uint16_t>(ms);
    try {
      host::check_device(caps);
      FAIL("watchdog " << ms << " ms accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      const std::string m = e.what();
      CHECK(m.find(std::to_string(ms) + " ms") != std::string::npos);
      CHECK(m.find(ms > 300 ? "300 ms" : "100 ms") != std::string::npos);
    }
  }
  for (int ms : {100, 300}) {
    caps.watchdog_ms = static_cast<std::uint16_t>(ms);
    CHECK_NOTHROW(host::check_device(caps));
  }
}

TEST_CASE("the device stops by itself after max_pulses", "[device][core]") {
  DeviceCore core(Capabilities{});
  PulseConfig c = config8();
  c.max_pulses = 7;
  start_output(core, 0, c);
  int n = 0;
  for (std::uint64_t now = 0; now < 100000; now += 1000) {
    send(core, static_cast<std::uint8_t>(4 + now / 1000), Msg::keepalive, token(), now);
    core.advance(now, [&](const DeliveredPulse&) { ++n; });
  }
  CHECK(n == 7);
  CHECK(core.status().fault == Fault::completed);
}

TEST_CASE("a retransmitted request is answered again but executed once", "[device][core]") {
  DeviceCore core(Capabilities{});
  send(core, 1, Msg::configure, configure(config8()), 0);
  const auto w = weights({10, -10, 0, 0, 0, 0, 0, 0});
  CHECK(send(core, 2, Msg::set_weights, w, 0) == Result::ok);
  CHECK(send(core, 2, Msg::set_weights, w, 0) == Result::ok);
  CHECK(core.status().weight_updates == 1);
  CHECK(send(core, 3, Msg::set_weights, w, 0) == Result::ok);
  CHECK(core.status().weight_updates == 2);
}

TEST_CASE("a repeated frame answered from the cache does not feed the watchdog",
          "[device][core][watchdog]") {
  Capabilities caps;
  caps.watchdog_ms = 300;
  DeviceCore core(caps);
  start_output(core, 0);
  CHECK(send(core, 4, Msg::keepalive, token(), 100000) == Result::ok);  // deadline 0.4 s
  // The same keep-alive, byte for byte, every 50 ms: answered, but the output stops at
  // 0.4 s all the same.
  std::uint64_t last = 0;
  for (std::uint64_t now = 150000; now <= 1000000; now += 50000) {
    if (core.status().state != State::running) break;
    CHECK(send(core, 4, Msg::keepalive, token(), now) == Result::ok);
    core.advance(now, [&](const DeliveredPulse& p) { last = p.t_us; });
  }
  CHECK(core.status().state == State::idle);
  CHECK(core.status().fault == Fault::watchdog);
  CHECK(last < 400000);
  // A new keep-alive (the next sequence number) feeds it, as before.
  DeviceCore other(caps);
  start_output(other, 0);
  for (std::uint64_t now = 100000, seq = 4; now <= 1000000; now += 100000, ++seq) {
    CHECK(send(other, static_cast<std::uint8_t>(seq), Msg::keepalive, token(), now) == Result::ok);
    other.advance(now, [](const DeliveredPulse&) {});
  }
  CHECK(other.status().state == State::running);
}

TEST_CASE("older frames of the session, replayed in turn, do not feed the watchdog",
          "[device][core][watchdog]") {
  Capabilities caps;
  caps.watchdog_ms = 300;
  DeviceCore core(caps);
  start_output(core, 0);
  CHECK(send(core, 4, Msg::keepalive, token(), 50000) == Result::ok);
  CHECK(send(core, 5, Msg::keepalive, token(), 100000) == Result::ok);  // deadline 0.4 s
  // Keep-alives 4 and 5 replayed in turn every 20 ms (neither is the last frame, so the
  // retransmission cache does not catch them): answered, but the output stops at 0.4 s.
  std::uint64_t last = 0;
  int turn = 0;
  for (std::uint64_t now = 120000; now <= 1200000; now += 20000, ++turn) {
    if (core.status().state != State::running) break;
    send(core, turn % 2 == 0 ? 4 : 5, Msg::keepalive, token(), now);
    core.advance(now, [&](const DeliveredPulse& p) { last = p.t_us; });
  }
  CHECK(core.status().fault == Fault::watchdog);
  CHECK(last < 400000);
  // Sequence numbers wrap: 254, 255, 0, 1 are each newer than the one before.
  DeviceCore wrap(caps);
  send(wrap, 250, Msg::configure, configure(config8()), 0);
  send(wrap, 251, Msg::set_weights, weights({10, -10, 0, 0, 0, 0, 0, 0}), 0);
  send(wrap, 252, Msg::start, token(), 0);
  std::uint64_t now = 0;
  for (int seq : {253, 254, 255, 0, 1, 2, 3, 4, 5}) {
    now += 200000;
    CHECK(send(wrap, static_cast<std::uint8_t>(seq), Msg::keepalive, token(), now) == Result::ok);
    wrap.advance(now, [](const DeliveredPulse&) {});
  }
  CHECK(wrap.status().state == State::running);
}

TEST_CASE("configure refuses a gap or an off time shorter than the shortest phase",
          "[device][core][timing]") {
  Capabilities caps;
  caps.min_width_us = 50;
  auto result = [&](std::uint32_t period, std::uint16_t w, std::uint16_t gap, std::uint16_t bw) {
    DeviceCore core(caps);
    PulseConfig c = config8();
    c.period_us = period;
    c.width_us = w;
    c.interphase_us = gap;
    c.balance_width_us = bw;
    CHECK(phase_fits(c, core.caps()) ==
          (send(core, 1, Msg::configure, configure(c), 0) == Result::ok));
    return send(core, 2, Msg::configure, configure(c), 0);
  };
  // The cases at 1000 Hz: 300 + 100 + 599 leaves 1 us between pulses.
  CHECK(result(1000, 300, 100, 599) == Result::out_of_range);
  CHECK(result(1000, 300, 100, 551) == Result::out_of_range);
  CHECK(result(1000, 300, 100, 550) == Result::ok);  // off time 50 us: the shortest phase
  CHECK(result(1000, 300, 100, 500) == Result::ok);
  CHECK(result(1000, 300, 49, 500) == Result::out_of_range);  // a gap shorter than a phase
  CHECK(result(1000, 300, 50, 500) == Result::ok);
  CHECK(result(1000, 300, 0, 650) == Result::ok);
  CHECK(result(1000, 300, 0, 651) == Result::out_of_range);
}

TEST_CASE("pulses a device could not deliver are not counted", "[device][core][timing]") {
  DeviceCore core(Capabilities{});
  PulseConfig c = config8();
  c.max_pulses = 10;
  start_output(core, 1000, c);
  std::uint64_t start = 0;
  int emitted = 0;
  for (std::uint64_t now = 1000; now <= 60000; now += 1000) {
    send(core, static_cast<std::uint8_t>(4 + now / 1000), Msg::keepalive, token(), now);
    core.advance(now, [&](const DeliveredPulse& p) {
      start = p.start_us;
      ++emitted;
    });
  }
  CHECK(emitted == 10);
  CHECK(core.status().fault == Fault::completed);
  CHECK(core.status().pulses == 10);
  core.not_delivered(start, 3);  // an engine that dropped three
  CHECK(core.status().pulses == 7);
  core.not_delivered(start + 1, 3);  // another output's: ignored
  CHECK(core.status().pulses == 7);
  core.not_delivered(start, 100);  // never below zero
  CHECK(core.status().pulses == 0);
}

TEST_CASE("the DAC step in integers equals the rounding rule in doubles", "[device][limits]") {
  // The rule stim-emu applied in doubles before the firmware needed it in integers.
  for (int bits = 2; bits <= 16; ++bits)
    for (int ua = 1; ua <= 2000; ++ua) {
      const double codes = std::ldexp(1.0, bits - 1) - 1;
      const double na = ua * 1000.0;
      double step = std::max(1.0, std::round(na / codes));
      if (std::floor(na / step) > codes) step = std::ceil(na / codes);
      const std::uint32_t got = dac_step_nA(static_cast<std::uint16_t>(ua), bits);
      if (step > 65535)
        REQUIRE(got == 0);
      else
        REQUIRE(got == static_cast<std::uint32_t>(step));
      if (got)
        REQUIRE(static_cast<std::uint64_t>(ua) * 1000u / got <= static_cast<std::uint64_t>(codes));
    }
  CHECK(dac_step_nA(2000, 12) == 977);
  CHECK(dac_step_nA(2000, 1) == 0);
  CHECK(dac_step_nA(2000, 17) == 0);
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

TEST_CASE("the status carries the line's error counts", "[device][core]") {
  DeviceCore core(Capabilities{});
  core.set_line_counts(3, 70000);
  const auto s = decode_status(encode(core.status()), 0);
  REQUIRE(s);
  CHECK(s->line_errors == 3);
  CHECK(s->overruns == 0xFFFF);  // saturates
}

TEST_CASE("balancing codes sum to zero and stay within one code of the exact charge",
          "[device][record]") {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> code(-2047, 2047), width(10, 1000), nch(2, 64);
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = nch(rng);
    std::vector<std::int16_t> main(static_cast<std::size_t>(n));
    int sum = 0;
    for (int i = 0; i + 1 < n; ++i) {
      main[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(code(rng) / n);
      sum += main[static_cast<std::size_t>(i)];
    }
    main.back() = static_cast<std::int16_t>(-sum);
    const auto w = static_cast<std::uint16_t>(width(rng));
    const auto bw = static_cast<std::uint16_t>(trial % 3 == 0 ? w : w + width(rng) * 7);
    std::vector<std::int16_t> bal(main.size());
    balance_codes(CodeSpan{main.data(), main.size()}, w, bw, bal.data());
    REQUIRE(std::accumulate(bal.begin(), bal.end(), 0) == 0);
    for (std::size_t i = 0; i < main.size(); ++i) {
      const double exact = -double(main[i]) * w / bw;
      REQUIRE(std::fabs(bal[i] - exact) < 1.0);
      // Never above the main phase's current (the limit the host checked it against).
      REQUIRE(std::abs(bal[i]) <= std::abs(main[i]));
      if (bw == w) REQUIRE(bal[i] == -main[i]);
    }
  }
  // At the ends of the ranges: 16-bit codes, widths up to 65535 us (|code| x width just
  // below 2^31, computed in 32 bits).
  const std::int16_t ends[4] = {-32767, 32766, 1, 0};  // a device's codes: |code| <= 32767
  for (std::uint16_t w : {std::uint16_t{1}, std::uint16_t{65535}})
    for (std::uint16_t bw : {std::uint16_t{65535}, std::uint16_t{65534}, std::uint16_t{1}}) {
      if (bw < w) continue;
      std::int16_t bal[4];
      balance_codes(CodeSpan{ends, 4}, w, bw, bal);
      CHECK(bal[0] + bal[1] + bal[2] + bal[3] == 0);
      for (int i = 0; i < 4; ++i) CHECK(std::fabs(bal[i] + double(ends[i]) * w / bw) < 1.0);
    }
}

TEST_CASE("a pulse record is the JSON line the emulator and the firmware write",
          "[device][record]") {
  PulseRecord r;
  r.t_us = 1234567;
  r.channels = 3;
  r.main[0] = 1024;
  r.main[1] = -512;
  r.main[2] = -512;
  balance_codes(CodeSpan{r.main, 3}, 200, 800, r.balance);
  r.step_nA = 977;
  r.width_us = 200;
  r.balance_width_us = 800;
  char line[kMaxRecordLine];
  const std::string s(line, format_record(r, line));
  CHECK(s ==
        "{\"pattern\": 0, \"t_s\": 1.234567, \"slip_us\": 0, \"width_us\": 200, "
        "\"interphase_us\": 0, \"balance_width_us\": 800, "
        "\"currents_mA\": [1.000448, -0.500224, -0.500224], \"net_charge_nC\": [0, 0, 0]}\n");
  r.t_us = 5000;
  r.pattern = 255;
  r.slip_us = 350;
  CHECK(std::string(line, format_record(r, line))
            .rfind("{\"pattern\": 255, \"t_s\": 0.005, \"slip_us\": 350, ", 0) == 0);
  r.main[0] = 1023;
  r.main[2] = -511;
  balance_codes(CodeSpan{r.main, 3}, 200, 800, r.balance);  // 1023/4: a remainder
  r.measured = true;
  r.start_us = 1234569;
  r.measured_width_us = 200;
  r.measured_balance_us = 801;
  r.dropped_before = 2;
  const std::string m(line, format_record(r, line));
  const auto j = nlohmann::json::parse(m);
  CHECK(j["currents_mA"][0].get<double>() == Approx(1023 * 977e-6));
  // 1023 x 200 - 256 x 800 = -200 code-us: -0.1954 nC, as the DAC delivers it
  CHECK(j["net_charge_nC"][0].get<double>() == Approx(-200 * 977e-6).margin(1e-6));
  CHECK(j["start_us"] == 1234569);
  CHECK(j["balance_width_us"] == 801);
  CHECK(j["dropped_before"] == 2);
  // The widest record fits.
  PulseRecord big;
  big.t_us = UINT64_MAX / 2;
  big.pattern = UINT16_MAX;
  big.slip_us = UINT32_MAX;
  big.channels = kMaxChannels;
  for (auto& c : big.main) c = -32767;
  for (auto& c : big.balance) c = -32767;
  big.step_nA = 65535;
  big.width_us = big.balance_width_us = 65535;
  big.measured = true;
  big.start_us = UINT64_MAX;
  big.measured_width_us = big.measured_interphase_us = big.measured_balance_us = UINT32_MAX;
  big.dropped_before = UINT32_MAX;
  const std::size_t len = format_record(big, line);
  CHECK(len <= kMaxRecordLine);
  // Exactly, digit for digit, past 32 bits (the 64-bit paths of the formatter).
  const std::string b(line, len);
  CHECK(b.find("\"t_s\": 9223372036854.775807,") != std::string::npos);
  CHECK(b.find("\"slip_us\": 4294967295,") != std::string::npos);
  CHECK(b.find("\"currents_mA\": [-2147.385345, ") != std::string::npos);  // -32767 x 65535 nA
  // -32767 x 65535 nA x 65535 us, twice: -281457797169150 fC, no trailing zero
  CHECK(b.find("\"net_charge_nC\": [-281457797.16915, ") != std::string::npos);
  CHECK(b.find("\"start_us\": 18446744073709551615,") != std::string::npos);
  CHECK(b.find("\"dropped_before\": 4294967295}") != std::string::npos);
  CHECK_NOTHROW(nlohmann::json::parse(b));
  big.start_us = 1000000000;  // nine zeros after the leading digits
  CHECK(std::string(line, format_record(big, line)).find("\"start_us\": 1000000000,") !=
        std::string::npos);
  big.start_us = 4294967296;  // 2^32
  CHECK(std::string(line, format_record(big, line)).find("\"start_us\": 4294967296,") !=
        std::string::npos);
}

TEST_CASE("the firmware's configuration block: defaults, a valid block, and refusals",
          "[device][config]") {
  constexpr std::uint32_t bits = (1u << 12) | (1u << 14) | (1u << 16);
  std::uint8_t erased[kConfigBlockSize];
  std::fill(std::begin(erased), std::end(erased), std::uint8_t{0xFF});
  const DeviceConfig d = parse_config_block(erased, 8, bits);
  CHECK(d.source == DeviceConfig::Source::defaults);
  CHECK(d.channels == 8);
  CHECK(d.max_current_uA == 2000);
  // What `scripts/firmware-config --max-current 1` writes (tests/cli: the same bytes).
  std::uint8_t block[kConfigBlockSize] = {0x54, 0x50, 0x43, 0x46, 0x01, 0x00, 0x10, 0x00,
                                          0x08, 0x0c, 0xe8, 0x03, 0x2c, 0x01, 0x56, 0x47};
  const DeviceConfig c = parse_config_block(block, 8, bits);
  CHECK(c.source == DeviceConfig::Source::block);
  CHECK(c.channels == 8);
  CHECK(c.dac_bits == 12);
  CHECK(c.max_current_uA == 1000);
  CHECK(c.watchdog_ms == 300);
  // Every single-bit error is caught, and leaves a device that delivers nothing.
  for (std::size_t byte = 0; byte < kConfigBlockSize; ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::uint8_t bad[kConfigBlockSize];
      std::copy(std::begin(block), std::end(block), bad);
      bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1u << bit));
      const DeviceConfig b = parse_config_block(bad, 8, bits);
      REQUIRE(b.source == DeviceConfig::Source::invalid);
      REQUIRE(b.max_current_uA == 0);
    }
  // A valid CRC over values the hardware cannot honour: refused the same way.
  auto with = [&](std::size_t at, std::uint8_t v) {
    std::uint8_t b[kConfigBlockSize];
    std::copy(std::begin(block), std::end(block), b);
    b[at] = v;
    const std::uint16_t crc = crc16(b, 14);
    b[14] = static_cast<std::uint8_t>(crc & 0xFF);
    b[15] = static_cast<std::uint8_t>(crc >> 8);
    return parse_config_block(b, 8, bits);
  };
  CHECK(with(8, 9).source == DeviceConfig::Source::invalid);   // 9 channels on an 8-channel DAC
  CHECK(with(8, 0).source == DeviceConfig::Source::invalid);   // none
  CHECK(with(9, 13).source == DeviceConfig::Source::invalid);  // a 13-bit DAC is not fitted
  CHECK(with(9, 16).source == DeviceConfig::Source::block);
  CHECK(with(11, 0x08).source == DeviceConfig::Source::invalid);  // 2.28 mA: over the bound
  CHECK(with(13, 0x04).source == DeviceConfig::Source::invalid);  // watchdog 1068 ms
  // A 4-channel board: its defaults have 4 channels.
  CHECK(parse_config_block(erased, 4, bits).channels == 4);
}

TEST_CASE("every end of an output is counted, and an output fault refuses later sessions",
          "[device][core]") {
  DeviceCore core(Capabilities{});
  auto run = [&](std::uint8_t seq, std::uint64_t now) {
    REQUIRE(send(core, seq, Msg::configure, configure(config8()), now) == Result::ok);
    REQUIRE(send(core, seq + 1, Msg::set_weights, weights({10, -10, 0, 0, 0, 0, 0, 0}), now) ==
            Result::ok);
    REQUIRE(send(core, seq + 2, Msg::start, token(), now) == Result::ok);
  };
  CHECK(core.output_ends() == 0);
  run(1, 0);
  CHECK(send(core, 4, Msg::stop, {}, 1000) == Result::ok);
  CHECK(core.output_ends() == 1);
  CHECK(send(core, 5, Msg::stop, {}, 2000) == Result::ok);  // nothing running: no new end
  CHECK(core.output_ends() == 1);
  run(10, 3000);
  core.advance(3000 + 400000, [](const DeliveredPulse&) {});  // the watchdog
  CHECK(core.status().fault == Fault::watchdog);
  CHECK(core.output_ends() == 2);
  run(20, 500000);
  core.output_fault();
  CHECK(core.output_ends() == 3);
  CHECK(core.status().state == State::idle);
  CHECK(core.status().fault == Fault::output_fault);
  core.advance(600000, [](const DeliveredPulse&) { FAIL("a pulse after an output fault"); });
  CHECK(send(core, 30, Msg::configure, configure(config8()), 600000) == Result::bad_state);
  const auto s = decode_status(encode(core.status()), 0);
  REQUIRE(s);
  CHECK(s->fault == Fault::output_fault);
}
