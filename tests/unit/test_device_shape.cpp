// Shaped pulses on the device (protocol 6, lib/device): set_shape's bytes, the device's
// refusals of a shape (each leaving the table as it was), version 5's bytes unchanged, the
// loads as exact sums over the phases, live amplitudes on base codes, and the shaped record.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>
#include "device/device_core.hpp"
#include "device/pulse_record.hpp"
#include "device_support.hpp"

using namespace tp::device;

namespace {

__extension__ typedef unsigned __int128 U128;

constexpr std::uint32_t kToken = 0x5EA9E006u;

Capabilities shaped_caps() {
  Capabilities c;
  c.features = kFeatureShapedPulses;
  return c;
}

std::vector<std::uint8_t> table(std::uint16_t n, std::uint8_t channels = 8, std::uint16_t gap = 100) {
  std::vector<std::uint8_t> b;
  put_u32(b, kToken);
  put_u16(b, n);
  b.push_back(channels);
  put_u16(b, gap);
  return b;
}
std::vector<std::uint8_t> codes(std::uint16_t i, const std::vector<std::int16_t>& dense) {
  std::vector<std::uint8_t> b;
  put_u32(b, kToken);
  put_u16(b, i);
  const auto rest = encode_sparse(dense);
  b.insert(b.end(), rest.begin(), rest.end());
  return b;
}
std::vector<std::uint8_t> shape(std::uint16_t i, const PatternTiming& t) {
  return shape_frame(kToken, i, t);
}
std::vector<std::uint8_t> token() {
  return with_session(kToken, {});
}

using Phases = std::vector<std::pair<std::uint16_t, std::int16_t>>;

// What a table is, seen from outside: the pulses it delivers over 30 ms once started, and
// how much load each pattern has room for (the largest code on two channels that set_codes
// accepts), each on its own copy of the core.  Frames here use sequence numbers 200 and up.
struct Fingerprint {
  std::vector<std::tuple<int, std::uint64_t, std::vector<int>, std::vector<int>>> pulses;
  std::vector<int> room;
  bool operator==(const Fingerprint& o) const { return pulses == o.pulses && room == o.room; }
};

int largest_accepted(DeviceCore core, std::uint16_t pattern, std::size_t ch) {
  int lo = 0, hi = core.caps().max_code() + 1;  // lo accepted (or nothing is), hi refused
  std::uint8_t seq = 200;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    std::vector<std::int16_t> dense(8, 0);
    dense[ch] = static_cast<std::int16_t>(mid);
    dense[ch + 1] = static_cast<std::int16_t>(-mid);
    (send(core, seq++, Msg::set_codes, codes(pattern, dense), 0) == Result::ok ? lo : hi) = mid;
  }
  return lo;
}

Fingerprint fingerprint(const DeviceCore& core, std::uint16_t patterns) {
  Fingerprint f;
  DeviceCore run = core;
  if (send(run, 240, Msg::start, token(), 0) == Result::ok)
    run.advance(30000, [&](const DeliveredPulse& p) {
      std::vector<int> timing{static_cast<int>(p.timing.period_us), p.timing.width_us,
                              p.timing.balance_width_us, p.timing.shape.n};
      for (std::size_t k = 0; k < p.timing.shape.n; ++k) {
        timing.push_back(p.timing.shape.duration_us[k]);
        timing.push_back(p.timing.shape.units[k]);
      }
      f.pulses.emplace_back(p.pattern, p.t_us, std::vector<int>(p.codes.begin(), p.codes.end()),
                            timing);
    });
  for (std::uint16_t i = 0; i < patterns; ++i)
    for (std::size_t ch : {0u, 4u}) f.room.push_back(largest_accepted(core, i, ch));
  return f;
}

}  // namespace

TEST_CASE("set_shape round-trips, and 17 phases or a short length are bad_length", "[device][shape]") {
  const PatternTiming t = shaped_timing(5000, {{500, 1}, {200, 10}, {50, 0}, {500, -5}}, 1200, 7);
  std::vector<std::uint8_t> body;
  put_shape_pattern(body, t);
  CHECK(body.size() == kShapeHeadSize + 4 * 4);
  PatternTiming back;
  REQUIRE(decode_shape_pattern(body.data(), body.size(), back));
  CHECK(back.period_us == 5000);
  CHECK(back.phase_us == 1200);
  CHECK(back.max_pulses == 7);
  CHECK(back.width_us == 0);
  REQUIRE(back.shape.n == 4);
  for (std::size_t k = 0; k < 4; ++k) {
    CHECK(back.shape.duration_us[k] == t.shape.duration_us[k]);
    CHECK(back.shape.units[k] == t.shape.units[k]);
  }
  CHECK(back.length_us() == 1250);
  CHECK(back.max_units() == 10);
  CHECK(back.edges() == 5);
  // 19 + 4n bytes, 83 at 16 phases: within a frame's payload.
  Phases sixteen;
  for (int k = 0; k < 16; ++k) sixteen.emplace_back(50, static_cast<std::int16_t>(k % 2 ? -1 : 1));
  CHECK(shape(0, shaped_timing(5000, sixteen)).size() == 83);
  CHECK(83 <= kMaxPayload);

  Capabilities caps = shaped_caps();
  caps.max_phases = 4;
  DeviceCore core(caps);
  CHECK(send(core, 1, Msg::set_shape, shape(0, t), 0) == Result::wrong_session);
  REQUIRE(send(core, 2, Msg::configure_table, table(2), 0) == Result::ok);
  CHECK(send(core, 3, Msg::set_shape, shape(0, t), 0) == Result::ok);
  CHECK(send(core, 4, Msg::set_shape, shape(2, t), 0) == Result::no_pattern);
  // 17 phases (the count byte 17 and 17 phases' bytes); 5 phases on a device of 4.
  auto b17 = shape(1, shaped_timing(5000, sixteen));
  b17[18] = 17;
  b17.insert(b17.end(), {50, 0, 0, 0});  // a 17th phase: 50 us at 0
  REQUIRE(b17.size() == 19 + 4 * 17);
  REQUIRE(b17[18] == 17);
  CHECK(send(core, 5, Msg::set_shape, b17, 0) == Result::bad_length);
  CHECK(send(core, 6, Msg::set_shape,
             shape(1, shaped_timing(5000, {{100, 1}, {100, -1}, {100, 1}, {100, -1}, {50, 0}})),
             0) == Result::bad_length);
  // Lengths that disagree with the count, no phases, shorter than the head.
  auto short_one = shape(1, t);
  short_one.pop_back();
  CHECK(send(core, 7, Msg::set_shape, short_one, 0) == Result::bad_length);
  auto long_one = shape(1, t);
  long_one.push_back(0);
  CHECK(send(core, 8, Msg::set_shape, long_one, 0) == Result::bad_length);
  auto none = shape(1, t);
  none.resize(19);
  none[18] = 0;
  CHECK(send(core, 9, Msg::set_shape, none, 0) == Result::bad_length);
  none.resize(18);
  CHECK(send(core, 10, Msg::set_shape, none, 0) == Result::bad_length);
  // The shape the device keeps is the one sent: its pulses carry it.
  REQUIRE(send(core, 11, Msg::set_codes, codes(0, {100, -60, -40, 0, 0, 0, 0, 0}), 0) ==
          Result::ok);
  REQUIRE(send(core, 12, Msg::set_pattern, with_session(kToken, [] {
                 std::vector<std::uint8_t> b;
                 put_u16(b, 1);
                 put_timing(b, PatternTiming{});
                 return b;
               }()),
               0) == Result::ok);
  REQUIRE(send(core, 13, Msg::set_codes, codes(1, {0, 0, 0, 0, 5, -5, 0, 0}), 0) == Result::ok);
  REQUIRE(send(core, 14, Msg::start, token(), 0) == Result::ok);
  int shaped = 0, biphasic = 0;
  core.advance(20000, [&](const DeliveredPulse& p) {
    if (p.pattern == 0) {
      ++shaped;
      CHECK(p.t_us == 1200 + 5000u * static_cast<unsigned>(shaped - 1));
      REQUIRE(p.timing.shape.n == 4);
      CHECK(p.timing.shape.units[1] == 10);
      CHECK(p.timing.shape.duration_us[3] == 500);
      CHECK(std::vector<int>(p.codes.begin(), p.codes.end()) ==
            std::vector<int>{100, -60, -40, 0, 0, 0, 0, 0});
    } else {
      ++biphasic;
      CHECK(!p.timing.shaped());
    }
  });
  CHECK(shaped == 4);
  CHECK(biphasic == 5);
  CHECK(send(core, 15, Msg::set_shape, shape(0, t), 20000) == Result::bad_state);

  // The capabilities: 41 bytes (version 7), version 6's three fields before the compliance.
  std::vector<std::uint8_t> ident;
  DeviceCore fresh(shaped_caps());
  REQUIRE(send(fresh, 1, Msg::identify, {}, 0, &ident) == Result::ok);
  REQUIRE(ident.size() == kCapabilitiesSize);
  CHECK(ident[0] == 7);
  const auto c = decode_capabilities(ident, 0);
  REQUIRE(c);
  CHECK(c->max_phases == 16);
  CHECK(c->features == kFeatureShapedPulses);
  CHECK(c->max_edge_rate_hz == 160000);
  ident.push_back(0);
  CHECK(!decode_capabilities(ident, 0));  // a length that is neither
}

TEST_CASE("the device refuses a shape that breaks a limit, and the table stays as it was",
          "[device][shape]") {
  const Capabilities caps = shaped_caps();
  REQUIRE(caps.max_code() == 2047);
  DeviceCore core(caps);
  REQUIRE(send(core, 1, Msg::configure_table, table(2), 0) == Result::ok);
  const PatternTiming a = shaped_timing(5000, {{200, 4}, {800, -1}});
  const PatternTiming b = shaped_timing(10000, {{100, 1}, {100, 0}, {100, -1}}, 2500);
  REQUIRE(send(core, 2, Msg::set_shape, shape(0, a), 0) == Result::ok);
  REQUIRE(send(core, 3, Msg::set_codes, codes(0, {400, -400, 0, 0, 0, 0, 0, 0}), 0) == Result::ok);
  REQUIRE(send(core, 4, Msg::set_shape, shape(1, b), 0) == Result::ok);
  REQUIRE(send(core, 5, Msg::set_codes, codes(1, {500, 0, 0, 0, -500, 0, 0, 0}), 0) == Result::ok);
  const Fingerprint before = fingerprint(core, 2);
  REQUIRE(before.pulses.size() == 10);  // 7 of pattern 0, 3 of pattern 1
  CHECK(before.room == std::vector<int>{511, 511, 2047, 2047});  // 511 x 4 <= 2047

  std::uint8_t seq = 10;
  // Each refusal with its result; the same frame corrected is accepted (on a copy).
  auto refused = [&](Msg type, const std::vector<std::uint8_t>& frame, Result r) {
    INFO("frame " << int{seq});
    CHECK(send(core, seq++, type, frame, 0) == r);
    CHECK(fingerprint(core, 2) == before);
  };
  auto accepted = [&](Msg type, const std::vector<std::uint8_t>& frame) {
    DeviceCore copy = core;
    CHECK(send(copy, seq++, type, frame, 0) == Result::ok);
  };
  const Msg S = Msg::set_shape;
  // Net charge: 200 x 4 - 799 x 1 != 0.
  refused(S, shape(0, shaped_timing(5000, {{200, 4}, {799, -1}})), Result::charge_not_zero);
  refused(S, shape(1, shaped_timing(5000, {{200, 1}, {200, 1}})), Result::charge_not_zero);
  // A phase below min_width, a zero-level gap of 5 us; with 10 us they pass.
  refused(S, shape(0, shaped_timing(5000, {{9, 4}, {36, -1}})), Result::out_of_range);
  accepted(S, shape(0, shaped_timing(5000, {{10, 4}, {40, -1}})));
  refused(S, shape(0, shaped_timing(5000, {{200, 4}, {5, 0}, {800, -1}})), Result::out_of_range);
  accepted(S, shape(0, shaped_timing(5000, {{200, 4}, {10, 0}, {800, -1}})));
  // The largest level's phases at most max_width (1000 us); the others up to 8000 us.
  refused(S, shape(0, shaped_timing(5000, {{1001, 1}, {1001, -1}})), Result::out_of_range);
  refused(S, shape(0, shaped_timing(9000, {{1001, 2}, {2002, -1}})), Result::out_of_range);
  accepted(S, shape(0, shaped_timing(5000, {{1000, 1}, {1000, -1}})));
  accepted(S, shape(0, shaped_timing(9000, {{1000, 2}, {2000, -1}})));
  refused(S, shape(0, shaped_timing(20000, {{1000, 9}, {9000, -1}})), Result::out_of_range);
  CHECK(check_shape(shaped_timing(20000, {{1000, 9}, {9000, -1}}).shape, caps) ==
        Result::out_of_range);  // for its 9000 us phase (9 x 400 is over the peak as well)
  CHECK(check_shape(shaped_timing(20000, {{1000, 8}, {8000, -1}}).shape, caps) == Result::ok);
  // Units: |u| <= 1024, not all zero.
  refused(S, shape(1, shaped_timing(5000, {{100, 1025}, {1025, -100}})), Result::out_of_range);
  CHECK(check_shape(shaped_timing(5000, {{100, 1025}, {1025, -100}}).shape, caps) ==
        Result::out_of_range);
  CHECK(check_shape(shaped_timing(5000, {{100, 1024}, {1024, -100}}).shape, caps) == Result::ok);
  refused(S, shape(1, shaped_timing(5000, {{100, 0}, {100, 0}})), Result::out_of_range);
  // The peak |b x u| <= 2047, whichever comes second: a shape of 8 units on codes of 400...
  refused(S, shape(0, shaped_timing(5000, {{100, 8}, {800, -1}})), Result::out_of_range);
  accepted(S, shape(0, shaped_timing(5000, {{100, 5}, {500, -1}})));
  // ... and codes of 512 on a shape of 4 units.
  refused(Msg::set_codes, codes(0, {512, -512, 0, 0, 0, 0, 0, 0}), Result::out_of_range);
  accepted(Msg::set_codes, codes(0, {511, -511, 0, 0, 0, 0, 0, 0}));
  // Electrode 0's RMS summed over both patterns above 1 mA (1.43 mA) and its mean above
  // 0.8 mA (1.10 mA) at 125 Hz; at 50 Hz both fit (0.94 and 0.52 mA).
  const Phases strong{{1000, 4}, {1000, -4}, {1000, 4}, {1000, -4}};
  refused(S, shape(1, shaped_timing(8000, strong)), Result::out_of_range);
  accepted(S, shape(1, shaped_timing(20000, strong)));
  // Not while running: every refusal above changed nothing, so the table starts as it was.
  REQUIRE(send(core, seq++, Msg::start, token(), 0) == Result::ok);
  CHECK(send(core, seq++, S, shape(0, a), 0) == Result::bad_state);
}

TEST_CASE("the device refuses a shape without room for its off time, or on a device without shapes",
          "[device][shape]") {
  // A table of one pattern (no gap between patterns to count): the off time (period -
  // phases) at least min_width, and the pulse within its period.
  DeviceCore core(shaped_caps());
  REQUIRE(send(core, 1, Msg::configure_table, table(1), 0) == Result::ok);
  REQUIRE(send(core, 2, Msg::set_shape, shape(0, shaped_timing(5000, {{200, 4}, {800, -1}})), 0) ==
          Result::ok);
  REQUIRE(send(core, 3, Msg::set_codes, codes(0, {400, -400, 0, 0, 0, 0, 0, 0}), 0) == Result::ok);
  const Fingerprint before = fingerprint(core, 1);
  CHECK(send(core, 4, Msg::set_shape, shape(0, shaped_timing(1009, {{200, 4}, {800, -1}})), 0) ==
        Result::out_of_range);
  CHECK(send(core, 5, Msg::set_shape, shape(0, shaped_timing(1000, {{200, 4}, {800, -1}})), 0) ==
        Result::out_of_range);
  CHECK(fingerprint(core, 1) == before);
  DeviceCore copy = core;
  CHECK(send(copy, 6, Msg::set_shape, shape(0, shaped_timing(1010, {{200, 4}, {800, -1}})), 0) ==
        Result::ok);

  Capabilities plain;  // features 0: as the firmware until its engine runs phases
  DeviceCore dev(plain);
  REQUIRE(send(dev, 1, Msg::configure_table, table(1), 0) == Result::ok);
  const Fingerprint empty = fingerprint(dev, 1);
  CHECK(send(dev, 2, Msg::set_shape, shape(0, shaped_timing(5000, {{200, 4}, {800, -1}})), 0) ==
        Result::not_supported);
  CHECK(check_shape(shaped_timing(5000, {{200, 4}, {800, -1}}).shape, plain) ==
        Result::not_supported);
  CHECK(fingerprint(dev, 1) == empty);
}

TEST_CASE("start refuses more edges a second than the device makes", "[device][shape]") {
  Capabilities slow = shaped_caps();
  slow.max_edge_rate_hz = 16000;
  DeviceCore dev(slow);
  REQUIRE(send(dev, 1, Msg::configure_table, table(2), 0) == Result::ok);
  Phases p16;  // 16 phases at 500 Hz, twice: 2 x 500 x 17 = 17000 edges a second
  for (int k = 0; k < 16; ++k) p16.emplace_back(20, static_cast<std::int16_t>(k % 2 ? -1 : 1));
  const Phases p14(p16.begin(), p16.begin() + 14);  // 2 x 500 x 15 = 15000
  REQUIRE(send(dev, 2, Msg::set_shape, shape(0, shaped_timing(2000, p16)), 0) == Result::ok);
  REQUIRE(send(dev, 3, Msg::set_shape, shape(1, shaped_timing(2000, p16, 1000)), 0) == Result::ok);
  REQUIRE(send(dev, 4, Msg::set_codes, codes(0, {100, -100, 0, 0, 0, 0, 0, 0}), 0) == Result::ok);
  REQUIRE(send(dev, 5, Msg::set_codes, codes(1, {0, 0, 100, -100, 0, 0, 0, 0}), 0) == Result::ok);
  const std::vector<PatternTiming> ts{shaped_timing(2000, p16), shaped_timing(2000, p16)};
  CHECK(edge_rate_mHz(ts.data(), 2) == 17000000u);
  const Fingerprint before = fingerprint(dev, 2);
  CHECK(before.pulses.empty());  // the copy's start is refused too
  CHECK(send(dev, 6, Msg::start, token(), 0) == Result::out_of_range);
  CHECK(dev.status().state == State::idle);
  CHECK(fingerprint(dev, 2) == before);
  REQUIRE(send(dev, 7, Msg::set_shape, shape(1, shaped_timing(2000, p14, 1000)), 0) == Result::ok);
  CHECK(send(dev, 8, Msg::start, token(), 0) == Result::ok);
  // A biphasic pulse has 3 edges, 4 with a gap.
  PatternTiming bi;
  bi.period_us = 1000;
  CHECK(edge_rate_mHz(&bi, 1) == 3000000u);
  bi.interphase_us = 50;
  CHECK(edge_rate_mHz(&bi, 1) == 4000000u);
}

TEST_CASE("a v5 biphasic table is accepted and delivered as before", "[device][shape]") {
  DeviceCore core(shaped_caps());
  // Version 5's bytes, by hand: configure (token, period 5000, width 200, gap 0, balance
  // 400, 8 channels, 3 pulses) and set_weights (8 codes: 10, -10, 0, ...).
  const std::vector<std::uint8_t> configure{0x06, 0xE0, 0xA9, 0x5E, 0x88, 0x13, 0x00, 0x00,
                                            0xC8, 0x00, 0x00, 0x00, 0x90, 0x01, 0x08, 0x03,
                                            0x00, 0x00, 0x00};
  std::vector<std::uint8_t> weights{0x06, 0xE0, 0xA9, 0x5E, 0x08, 0x0A, 0x00, 0xF6, 0xFF};
  weights.resize(weights.size() + 12, 0);
  REQUIRE(send(core, 1, Msg::configure, configure, 0) == Result::ok);
  REQUIRE(send(core, 2, Msg::set_weights, weights, 0) == Result::ok);
  REQUIRE(send(core, 3, Msg::start, token(), 0) == Result::ok);
  std::vector<std::string> lines;
  core.advance(20000, [&](const DeliveredPulse& p) {
    CHECK(!p.timing.shaped());
    CHECK(p.timing.length_us() == 600);
    CHECK(p.timing.max_units() == 1);
    const PulseRecord r = record_of(p);  // as the emulators record it
    char line[kMaxRecordLine];
    lines.emplace_back(line, format_record(r, line));
  });
  REQUIRE(lines.size() == 3);
  CHECK(lines[1] ==
        "{\"pattern\": 0, \"t_s\": 0.005, \"slip_us\": 0, \"width_us\": 200, "
        "\"interphase_us\": 0, \"balance_width_us\": 400, \"currents_mA\": [0.00977, -0.00977, "
        "0, 0, 0, 0, 0, 0], \"net_charge_nC\": [0, 0, 0, 0, 0, 0, 0, 0]}\n");
  CHECK(core.status().fault == Fault::completed);
  // A table by version 5's set_pattern (18 bytes of timing) and set_codes.
  DeviceCore t5(shaped_caps());
  REQUIRE(send(t5, 1, Msg::configure_table, table(1), 0) == Result::ok);
  const std::vector<std::uint8_t> pattern{0x06, 0xE0, 0xA9, 0x5E, 0x00, 0x00,  // token, index 0
                                          0x10, 0x27, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                                          0x64, 0x00, 0x64, 0x00, 0xC8, 0x00,  // 100, 100, 200
                                          0x02, 0x00, 0x00, 0x00};
  REQUIRE(send(t5, 2, Msg::set_pattern, pattern, 0) == Result::ok);
  // Biphasic: |code| up to the largest code (units 1), whatever a shape would allow.
  REQUIRE(send(t5, 3, Msg::set_codes, codes(0, {2047, -2047, 0, 0, 0, 0, 0, 0}), 0) == Result::ok);
  REQUIRE(send(t5, 4, Msg::start, token(), 0) == Result::ok);
  int n = 0;
  t5.advance(20000, [&](const DeliveredPulse& p) {
    ++n;
    CHECK(p.timing.length_us() == 400);
    CHECK(p.timing.edges() == 4);
    CHECK(p.codes[0] == 2047);
  });
  CHECK(n == 2);
  // A version 5 device's 33-byte capabilities: no shapes, 4 edges a pulse.
  std::vector<std::uint8_t> v5;
  Capabilities c;
  c.protocol = 5;
  c.max_pulse_rate_hz = 1209;
  put_capabilities(v5, c);
  v5.resize(kCapabilitiesSizeV5);
  const auto d = decode_capabilities(v5, 0);
  REQUIRE(d);
  CHECK(d->protocol == 5);
  CHECK(d->max_phases == 0);
  CHECK(!d->shaped_pulses());
  CHECK(d->max_edge_rate_hz == 4 * 1209);
  CHECK(d->max_pulse_rate_hz == 1209);
  v5[0] = 6;  // a version 6 device must send all 39 bytes
  CHECK(!decode_capabilities(v5, 0));
}

namespace {

// ceil(x x 2^16 / period), exactly.
std::uint64_t q16(U128 x, std::uint32_t period) {
  return static_cast<std::uint64_t>(((x << 16) + period - 1) / period);
}

// A random charge-balanced shape the device accepts: pairs of phases m2 g at +m1 and
// m1 g at -m2 (each pair's charge 0), shuffled, some zero-level gaps between.
PatternTiming random_shape(std::mt19937& rng, const Capabilities& caps) {
  for (;;) {
    Phases p;
    const int pairs = std::uniform_int_distribution<int>(1, 7)(rng);
    for (int k = 0; k < pairs; ++k) {
      const int m1 = std::uniform_int_distribution<int>(1, 12)(rng);
      const int m2 = std::uniform_int_distribution<int>(1, 12)(rng);
      const int g = std::uniform_int_distribution<int>(10, 500)(rng);
      const int sign = rng() % 2 ? 1 : -1;
      p.emplace_back(static_cast<std::uint16_t>(m2 * g), static_cast<std::int16_t>(sign * m1));
      p.emplace_back(static_cast<std::uint16_t>(m1 * g), static_cast<std::int16_t>(-sign * m2));
    }
    std::shuffle(p.begin(), p.end(), rng);
    if (p.size() < kMaxPhases && rng() % 2)
      p.insert(p.begin() + 1, {static_cast<std::uint16_t>(10 + rng() % 200), std::int16_t{0}});
    std::uint32_t length = 0;
    for (const auto& ph : p) length += ph.first;
    const std::uint32_t period = std::max<std::uint32_t>(1000, length + 100) +
                                 std::uniform_int_distribution<std::uint32_t>(0, 5000)(rng);
    PatternTiming t = shaped_timing(period, p);
    if (check_shape(t.shape, caps) == Result::ok) return t;
  }
}

}  // namespace

TEST_CASE("a shaped pattern's load equals the exact sum over phases", "[device][shape]") {
  std::mt19937 rng(40);
  // The shares against exact sums, for any shape (balanced or not) and code.
  for (int it = 0; it < 1000; ++it) {
    const std::size_t n = 1 + rng() % kMaxPhases;
    Phases p;
    std::uint32_t length = 0;
    for (std::size_t k = 0; k < n; ++k) {
      p.emplace_back(static_cast<std::uint16_t>(10 + rng() % 7991),
                     static_cast<std::int16_t>(static_cast<int>(rng() % 2049) - 1024));
      length += p.back().first;
    }
    const PatternTiming t =
        shaped_timing(length + 1 + static_cast<std::uint32_t>(rng() % 1000000), p);
    const std::uint32_t peak = static_cast<std::uint32_t>(std::max(t.max_units(), 1));
    const auto a = static_cast<std::uint32_t>(rng() % (32768 / peak + 1));
    U128 ms = 0, mean = 0;
    for (const auto& ph : p) {
      const U128 c = U128{a} * static_cast<std::uint32_t>(std::abs(ph.second));
      ms += c * c * ph.first;
      mean += c * ph.first;
    }
    INFO("case " << it);
    REQUIRE(ChannelLoad::ms_share(a, t) == q16(ms, t.period_us));
    REQUIRE(ChannelLoad::mean_share(a, t) == q16(mean, t.period_us));
    // The host's figure from the same shares (add_dense) agrees with the double sums.
    ChannelLoad load;
    add_dense(load, {static_cast<std::int16_t>(a), static_cast<std::int16_t>(-a)}, t);
    double sq = 0, abs_sum = 0;
    for (const auto& ph : p) {
      const double i = a * std::abs(ph.second) * 977e-6;
      sq += i * i * ph.first;
      abs_sum += i * ph.first;
    }
    CHECK(load.rms_mA(1, 977) == Approx(std::sqrt(sq / t.period_us)).epsilon(1e-6).margin(1e-6));
    CHECK(load.mean_mA(1, 977) == Approx(abs_sum / t.period_us).epsilon(1e-6).margin(1e-6));
  }
  // A code whose peak would overflow the DAC counts as over every bound.
  const PatternTiming big = shaped_timing(5000, {{100, 1024}, {1024, -100}});
  CHECK(ChannelLoad::ms_share(33, big) > (std::uint64_t{1} << 57));
  CHECK(ChannelLoad::mean_share(33, big) > (std::uint64_t{1} << 57));

  // The device at the bounds: the largest code whose exact RMS and mean are within them
  // is accepted, one code more refused (by the load, or by the peak).
  const Capabilities caps = shaped_caps();
  const std::uint64_t step = caps.dac_step_nA;
  const U128 rms_nA = U128{caps.max_rms_uA} * 1000u;
  const U128 ms_limit = (rms_nA * rms_nA << 16) / (step * step);
  const U128 mean_limit = (U128{caps.max_mean_uA} * 1000u << 16) / step;
  int by_load = 0;
  for (int it = 0; it < 300; ++it) {
    const PatternTiming t = random_shape(rng, caps);
    auto within = [&](std::uint32_t a) {
      U128 ms = 0, mean = 0;
      for (std::size_t k = 0; k < t.shape.n; ++k) {
        const U128 c = U128{a} * static_cast<std::uint32_t>(std::abs(t.shape.units[k]));
        ms += c * c * t.shape.duration_us[k];
        mean += c * t.shape.duration_us[k];
      }
      return a * static_cast<std::uint32_t>(t.max_units()) <= 2047u &&
             q16(ms, t.period_us) <= ms_limit && q16(mean, t.period_us) <= mean_limit;
    };
    std::uint32_t a = 0;
    while (within(a + 1)) ++a;
    if (2047u / static_cast<std::uint32_t>(t.max_units()) > a) ++by_load;
    DeviceCore core(caps);
    REQUIRE(send(core, 1, Msg::configure_table, table(1), 0) == Result::ok);
    REQUIRE(send(core, 2, Msg::set_shape, shape(0, t), 0) == Result::ok);
    const auto code = [](std::uint32_t v) {
      return std::vector<std::int16_t>{0, static_cast<std::int16_t>(v), 0,
                                       static_cast<std::int16_t>(-static_cast<int>(v)), 0, 0, 0, 0};
    };
    INFO("case " << it << ", largest code " << a);
    CHECK(send(core, 3, Msg::set_codes, codes(0, code(a + 1)), 0) == Result::out_of_range);
    CHECK(send(core, 4, Msg::set_codes, codes(0, code(a)), 0) == Result::ok);
  }
  CHECK(by_load > 100);  // the load bound, not only the peak, decided many of them
}

TEST_CASE("amplitude scales keep a shape's charge at zero", "[device][shape]") {
  std::mt19937 rng(6);
  const Capabilities caps = shaped_caps();
  const PatternTiming t = shaped_timing(5000, {{500, 1}, {200, 10}, {50, 0}, {500, -5}});
  for (int it = 0; it < 50; ++it) {
    std::vector<std::int16_t> base(8);
    int sum = 0;
    for (std::size_t c = 0; c + 1 < 8; ++c) {
      base[c] = static_cast<std::int16_t>(static_cast<int>(rng() % 57) - 28);
      sum += base[c];
    }
    base[7] = static_cast<std::int16_t>(-sum);  // |.| <= 196: x 10 within 2047
    DeviceCore core(caps);
    REQUIRE(send(core, 1, Msg::configure_table, table(1), 0) == Result::ok);
    REQUIRE(send(core, 2, Msg::set_shape, shape(0, t), 0) == Result::ok);
    REQUIRE(send(core, 3, Msg::set_codes, codes(0, base), 0) == Result::ok);
    REQUIRE(send(core, 4, Msg::start, token(), 0) == Result::ok);
    std::vector<std::uint8_t> amp = token();
    put_u16(amp, 0);
    amp.push_back(1);
    const auto scale = static_cast<std::uint16_t>(rng() % (kFullScale + 1));
    put_u16(amp, scale);
    REQUIRE(send(core, 5, Msg::set_amplitudes, amp, 0) == Result::ok);
    int pulses = 0;
    core.advance(5000, [&](const DeliveredPulse& p) {
      if (p.t_us == 0) return;  // delivered before the scale
      ++pulses;
      REQUIRE(p.timing.shape.n == 4);
      PulseRecord r;
      r.channels = 8;
      r.step_nA = 977;
      r.shape = p.timing.shape;
      for (std::size_t c = 0; c < 8; ++c) {
        r.main[c] = p.codes[c];
        CHECK(std::abs(p.codes[c]) <= std::abs(base[c]));
        CHECK(std::abs(p.codes[c] - base[c] * static_cast<double>(scale) / kFullScale) < 1.0);
      }
      // At every phase the channels' codes sum to zero; over the pulse each channel's
      // charge is zero.
      for (std::size_t k = 0; k < 4; ++k) {
        std::int16_t phase[8];
        shape_codes(r.main, 8, t.shape, k, phase);
        int s = 0;
        for (std::int16_t v : phase) s += v;
        CHECK(s == 0);
      }
      char line[kMaxRecordLine];
      const auto j = nlohmann::json::parse(std::string(line, format_record(r, line)));
      for (const auto& q : j["net_charge_nC"]) CHECK(q.get<double>() == 0.0);
    });
    CHECK(pulses == 1);
  }
}

TEST_CASE("a shaped pulse record is exact", "[device][shape][record]") {
  PulseRecord r;
  r.pattern = 3;
  r.t_us = 1234567;
  r.channels = 3;
  r.main[0] = 100;
  r.main[1] = -60;
  r.main[2] = -40;
  r.step_nA = 977;
  r.shape = shaped_timing(5000, {{500, 1}, {200, 10}, {50, 0}, {500, -5}}).shape;
  char line[kMaxRecordLine];
  CHECK(std::string(line, format_record(r, line)) ==
        "{\"pattern\": 3, \"t_s\": 1.234567, \"slip_us\": 0, \"phases\": ["
        "{\"duration_us\": 500, \"units\": 1}, {\"duration_us\": 200, \"units\": 10}, "
        "{\"duration_us\": 50, \"units\": 0}, {\"duration_us\": 500, \"units\": -5}], "
        "\"unit_currents_mA\": [0.0977, -0.05862, -0.03908], \"net_charge_nC\": [0, 0, 0]}\n");
  // Measured durations are shown; the charge is the configured phases' (as for widths).
  r.measured = true;
  r.start_us = 42;
  const std::uint32_t measured[4] = {501, 199, 50, 500};
  std::copy(measured, measured + 4, r.measured_duration_us);
  r.dropped_before = 1;
  auto j = nlohmann::json::parse(std::string(line, format_record(r, line)));
  CHECK(j["phases"][0]["duration_us"] == 501);
  CHECK(j["phases"][1]["duration_us"] == 199);
  CHECK(j["phases"][1]["units"] == 10);
  CHECK(j["start_us"] == 42);
  CHECK(j["dropped_before"] == 1);
  CHECK(j["net_charge_nC"] == nlohmann::json::array({0, 0, 0}));
  CHECK(!j.contains("width_us"));
  // A shape that is not balanced (which a device refuses) is recorded as it is:
  // 1000 codes x 977 nA x (200 - 199) us = 0.977 nC.
  r.measured = false;
  r.shape = shaped_timing(5000, {{200, 1}, {199, -1}}).shape;
  r.main[0] = 1000;
  r.main[1] = -1000;
  r.main[2] = 0;
  j = nlohmann::json::parse(std::string(line, format_record(r, line)));
  CHECK(j["net_charge_nC"] == nlohmann::json::array({0.977, -0.977, 0}));
  // The widest shaped record fits, exact past 64 bits: -32767 codes x 65535 nA x 16 phases
  // of 65535 us at -32768 units = 73782472781109657600 fC.
  PulseRecord big;
  big.t_us = UINT64_MAX / 2;
  big.pattern = UINT16_MAX;
  big.slip_us = UINT32_MAX;
  big.channels = kMaxChannels;
  for (auto& c : big.main) c = -32767;
  big.step_nA = 65535;
  big.shape.n = kMaxPhases;
  for (std::size_t k = 0; k < kMaxPhases; ++k) {
    big.shape.duration_us[k] = 65535;
    big.shape.units[k] = -32768;
    big.measured_duration_us[k] = UINT32_MAX;
  }
  big.measured = true;
  big.start_us = UINT64_MAX;
  big.dropped_before = UINT32_MAX;
  const std::size_t len = format_record(big, line);
  CHECK(len <= kMaxRecordLine);
  const std::string b(line, len);
  CHECK(b.find("{\"duration_us\": 4294967295, \"units\": -32768}]") != std::string::npos);
  CHECK(b.find("\"unit_currents_mA\": [-2147.385345, ") != std::string::npos);
  CHECK(b.find("\"net_charge_nC\": [73782472781109.6576, ") != std::string::npos);
  CHECK_NOTHROW(nlohmann::json::parse(b));
}
