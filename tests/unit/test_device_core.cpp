// The device core (lib/device/device_core): its refusals, the watchdog, sessions,
// retransmissions and the counts of every end of an output.
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
