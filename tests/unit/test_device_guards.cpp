// The device's measured guards (protocol 7, issue 41 items 3 and 4; device_guards.cpp):
// from each pulse's readings the core derives the impedance, keeps the lowest as the
// channel's baseline, and stops the output at the first pulse that shows a pad without
// contact, a current not delivered (the compliance rail) or a charge density above
// Shannon's k on the contact area it estimates; set_guards' refusals; the measurements
// query and its paging; the version 7 capabilities.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

#include "device/device_core.hpp"
#include "device/pulse_record.hpp"
#include "device_support.hpp"

using namespace tp;
using namespace tp::device;

namespace {

constexpr std::uint32_t kToken = 0xC0FFEE07u;

Capabilities measuring_caps() {
  Capabilities c;
  c.features = kFeatureShapedPulses | kFeatureMeasures;
  c.compliance_V = 100;
  return c;
}

// 8 channels, codes +-code on channels 0 and 1, period 5 ms (or period_us), the given width.
Result start_output(DeviceCore& core, std::int16_t code, std::uint16_t width_us,
                    const Guards* guards = nullptr, std::uint32_t period_us = 5000) {
  PulseConfig c;
  c.period_us = period_us;
  c.width_us = c.balance_width_us = width_us;
  c.channels = 8;
  REQUIRE(send(core, 1, Msg::configure, with_session(kToken, encode(c)), 0) == Result::ok);
  REQUIRE(send(core, 2, Msg::set_weights,
               with_session(kToken, encode_weights({code, static_cast<std::int16_t>(-code), 0, 0,
                                                    0, 0, 0, 0})),
               0) == Result::ok);
  if (guards)
    REQUIRE(send(core, 3, Msg::set_guards, with_session(kToken, encode(*guards)), 0) ==
            Result::ok);
  return send(core, 4, Msg::start, with_session(kToken, {}), 0);
}

// The same with any 8 codes (summing to zero).
Result start_codes(DeviceCore& core, const std::vector<std::int16_t>& codes,
                   std::uint16_t width_us, const Guards* guards, std::uint32_t period_us) {
  PulseConfig c;
  c.period_us = period_us;
  c.width_us = c.balance_width_us = width_us;
  c.channels = 8;
  REQUIRE(send(core, 1, Msg::configure, with_session(kToken, encode(c)), 0) == Result::ok);
  REQUIRE(send(core, 2, Msg::set_weights, with_session(kToken, encode_weights(codes)), 0) ==
          Result::ok);
  if (guards)
    REQUIRE(send(core, 3, Msg::set_guards, with_session(kToken, encode(*guards)), 0) ==
            Result::ok);
  return send(core, 4, Msg::start, with_session(kToken, {}), 0);
}

// One channel's reading: voltage (mV), delivered current (nA), at the rail.
struct Reading {
  std::int32_t voltage_mV;
  std::int32_t current_nA;
  bool at_rail;
};
// The board: pulse k's readings of channel c, given the current asked (nA).
using Board = std::function<Reading(std::size_t k, std::size_t c, std::int32_t asked_nA)>;

// A load of z ohm on every channel: V = I z.
Reading ohmic(std::int32_t asked_nA, double z_ohm) {
  return {static_cast<std::int32_t>(std::lround(asked_nA * z_ohm * 1e-6)), asked_nA, false};
}

// Advances the core over [0, until_us) in steps of step_us, measuring each pulse with the
// board from inside advance()'s sink (as the emulators do).  Returns the pulses delivered.
std::size_t run(DeviceCore& core, const Board& board, std::uint64_t until_us,
                std::uint64_t step_us = 1000) {
  std::size_t k = 0;
  std::uint8_t seq = 10;
  for (std::uint64_t now = 0; now < until_us; now += step_us) {
    send(core, seq++, Msg::keepalive, with_session(kToken, {}), now);
    core.advance(now, [&](const DeliveredPulse& p) {
      PulseRecord r = record_of(p);
      ElectricalRecord m;
      for (std::size_t c = 0; c < r.channels; ++c) {
        if (r.main[c] == 0) continue;
        const auto asked = static_cast<std::int32_t>(r.main[c] * static_cast<std::int32_t>(r.step_nA));
        const Reading x = board(k, c, asked);
        m.carried[c] = true;
        m.voltage_mV[c] = x.voltage_mV;
        m.current_nA[c] = x.current_nA;
        m.at_rail[c] = x.at_rail;
      }
      core.measured(p.start_us, r, m);
      ++k;
    });
  }
  return k;
}

Measurements query(DeviceCore& core, std::uint8_t first, std::uint8_t n, std::uint8_t seq = 200) {
  std::vector<std::uint8_t> body;
  REQUIRE(send(core, seq, Msg::measurements, {first, n}, 0, &body) == Result::ok);
  const auto m = decode_measurements(body, 0);
  REQUIRE(m);
  return *m;
}

}  // namespace

TEST_CASE("guards: impedance derived from each reading, the lowest kept as the baseline",
          "[device][guards]") {
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, 1024, 200) == Result::ok);  // 1.000 mA at 977 nA a code
  // 20 kOhm, then 15 kOhm (sweat), then 18: the baseline follows the lowest.
  const std::size_t n = run(core, [](std::size_t k, std::size_t, std::int32_t i) {
    return ohmic(i, k < 3 ? 20000 : k < 6 ? 15000 : 18000);
  }, 40000);
  CHECK(n == 8);
  CHECK(core.status().state == State::running);
  const Measurements m = query(core, 0, 8);
  CHECK(m.head.measured == 8);
  CHECK(m.head.trip == Fault::none);
  REQUIRE(m.channels.size() == 8);
  CHECK(m.channels[0].carried);
  CHECK(m.channels[0].impedance_ohm == Approx(18000).margin(2));
  CHECK(m.channels[0].baseline_ohm == Approx(15000).margin(2));
  CHECK(m.channels[1].voltage_mV < 0);  // anodic: the voltage has its sign
  CHECK(m.channels[1].impedance_ohm == Approx(18000).margin(2));
  CHECK(!m.channels[2].carried);
  CHECK(m.channels[2].impedance_ohm == 0);
  // Paging: a page of channels 6 and 7; more than 13 a page, or past the last channel, refused.
  CHECK(query(core, 6, 2).channels.size() == 2);
  CHECK(send(core, 201, Msg::measurements, {0, 14}, 0) == Result::out_of_range);
  CHECK(send(core, 202, Msg::measurements, {7, 2}, 0) == Result::out_of_range);
  CHECK(send(core, 203, Msg::measurements, {0}, 0) == Result::bad_length);
}

TEST_CASE("guards: a pad without contact stops the output at the pulse that shows it",
          "[device][guards]") {
  SECTION("no current flowed: the source at its rail") {
    DeviceCore core(measuring_caps());
    REQUIRE(start_output(core, 1024, 200) == Result::ok);
    // Everything due at once (one advance over 50 ms): the trip still ends it before the
    // next pulse.
    const std::size_t n = run(core, [](std::size_t k, std::size_t c, std::int32_t i) {
      if (k >= 4 && c == 1) return Reading{-100000, 0, true};
      return ohmic(i, 20000);
    }, 60000, 50000);
    CHECK(n == 5);
    CHECK(core.status().fault == Fault::contact);
    CHECK(core.status().pulses == 5);
    const Measurements m = query(core, 0, 2);
    CHECK(m.head.trip == Fault::contact);
    CHECK(m.head.trip_channel == 1);
    CHECK(m.head.trip_t_us == 4 * 5000);
    CHECK(m.head.trip_ohm == kOpenOhm);
  }
  SECTION("an impedance above ten times the baseline: less than a tenth of the contact") {
    DeviceCore core(measuring_caps());
    REQUIRE(start_output(core, 1024, 200) == Result::ok);
    const std::size_t n = run(core, [](std::size_t k, std::size_t c, std::int32_t i) {
      return ohmic(i, c == 0 && k >= 3 ? (k == 3 ? 199000 : 201000) : 20000);
    }, 60000);
    CHECK(n == 5);  // 9.95 x the baseline passes; 10.05 x stops
    CHECK(core.status().fault == Fault::contact);
    CHECK(query(core, 0, 1).head.trip_t_us == 4 * 5000);
  }
}

TEST_CASE("guards: a current not delivered as asked (compliance) stops the output",
          "[device][guards]") {
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, 1024, 200) == Result::ok);
  const std::size_t n = run(core, [](std::size_t k, std::size_t, std::int32_t i) {
    // From pulse 2 the load needs 125 V: the rail's 100 V pushes 80 % of the current.
    if (k >= 2) return Reading{i > 0 ? 100000 : -100000, i * 4 / 5, true};
    return ohmic(i, 20000);
  }, 60000);
  CHECK(n == 3);
  CHECK(core.status().fault == Fault::compliance);
  const Measurements m = query(core, 0, 2);
  CHECK(m.head.trip == Fault::compliance);
  CHECK(m.head.trip_channel == 0);
  CHECK(m.head.trip_ohm == 100000ull * 1000000 / (1024 * 977 * 4 / 5));  // 100 V / 0.8 mA
  CHECK(m.channels[0].at_rail);
}

TEST_CASE("guards: the charge density on the estimated contact area (Shannon's k)",
          "[device][guards]") {
  // 2 mA for 800 us on 5 mm^2: Q = 1.6 uC, k = log10(Q^2 / A) = 1.71 at full contact.
  // Shannon's 1.85 holds while the contact c >= Q^2 / (10^1.85 A) = 0.723.
  Guards g;
  g.area_um2 = 5000000;
  const std::int16_t code = 2047;  // 2000 uA at 977 nA a code: 1.99992 mA
  const double q_uC = code * 977e-9 * 800, c_min = q_uC * q_uC / (std::pow(10, 1.85) * 0.05);
  REQUIRE(c_min == Approx(0.7227).epsilon(1e-3));
  for (const double c : {c_min * 1.001, c_min * 0.999}) {
    DeviceCore core(measuring_caps());
    // 50 Hz: 0.57 mA RMS, within the device's 1 mA.
    REQUIRE(start_output(core, code, 800, &g, 20000) == Result::ok);
    // The pad's impedance, 10 kOhm at full contact, rises as 1 / c from pulse 3 on.
    const std::size_t n = run(core, [c](std::size_t k, std::size_t ch, std::int32_t i) {
      return ohmic(i, ch == 1 && k >= 3 ? 10000 / c : 10000);
    }, 200000);
    if (c > c_min) {
      CHECK(n == 10);
      CHECK(core.status().state == State::running);
    } else {
      CHECK(n == 4);
      CHECK(core.status().fault == Fault::density);
      CHECK(query(core, 0, 2).head.trip_channel == 1);
    }
  }
  // Without guards given (area 0), no density guard: only contact and compliance.
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, code, 800, nullptr, 20000) == Result::ok);
  CHECK(run(core, [](std::size_t k, std::size_t, std::int32_t i) {
          return ohmic(i, k >= 3 ? 20000 : 10000);
        }, 200000) == 10);
}

TEST_CASE("guards: suspending, a lost pad's pattern goes on at the probe until contact returns",
          "[device][guards]") {
  Guards g;
  g.flags = kGuardSuspend;
  g.probe_uA = 50;
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, 1024, 200, &g) == Result::ok);  // 1.000448 mA
  std::vector<std::int32_t> asked;  // channel 0's current as delivered, per pulse
  // Channel 1 lifted from pulse 3 to pulse 6 (no current flows), then back.
  const std::size_t n = run(core, [&](std::size_t k, std::size_t c, std::int32_t i) {
    if (c == 0) asked.push_back(i);
    if (c == 1 && k >= 3 && k <= 6) return Reading{-100000, 0, true};
    return ohmic(i, 20000);
  }, 60000);
  CHECK(n == 12);
  CHECK(core.status().state == State::running);
  REQUIRE(asked.size() == 12);
  // Pulses 0 to 3 as asked (3 finds the loss), 4 to 7 at the probe (7 finds the contact
  // again), 8 on as asked.
  for (std::size_t k = 0; k < 12; ++k) {
    INFO("pulse " << k);
    if (k >= 4 && k <= 7) {
      CHECK(asked[k] <= 50000);
      CHECK(asked[k] > 45000);
    } else {
      CHECK(asked[k] == 1024 * 977);
    }
  }
  const Measurements m = query(core, 0, 2);
  CHECK(m.head.suspended == 4);
  CHECK(m.head.trip == Fault::none);
  CHECK(!m.channels[1].suspended);
  // Compliance still stops everything.
  DeviceCore other(measuring_caps());
  REQUIRE(start_output(other, 1024, 200, &g) == Result::ok);
  CHECK(run(other, [](std::size_t k, std::size_t, std::int32_t i) {
          return k >= 2 ? Reading{100000, i / 2, true} : ohmic(i, 20000);
        }, 60000) == 3);
  CHECK(other.status().fault == Fault::compliance);
}

TEST_CASE("guards: a probe never carries more than the probe's current, in whole codes",
          "[device][guards]") {
  // An asymmetric pattern whose scaled codes scale_codes must round to a zero sum: 24 uA is
  // 24.56 codes of 977 nA, so at most 24 codes on any pad (found by review: 25 before).
  Guards g;
  g.flags = kGuardSuspend;
  g.probe_uA = 24;
  DeviceCore core(measuring_caps());
  REQUIRE(start_codes(core, {-48, -2, -42, 120, 131, -159, 0, 0}, 200, &g, 5000) == Result::ok);
  std::int32_t largest_after = 0;
  run(core, [&](std::size_t k, std::size_t c, std::int32_t i) {
    if (k >= 3) largest_after = std::max(largest_after, std::abs(i));
    if (c == 5 && k >= 2) return Reading{-100000, 0, true};
    return ohmic(i, 20000);
  }, 60000);
  CHECK(largest_after > 0);
  CHECK(largest_after <= 24000);
  CHECK(largest_after / 977 == 24);
}

TEST_CASE("guards: a pad back with too little contact for its charge stays suspended",
          "[device][guards]") {
  // 2 mA for 800 us on 5 mm^2 needs a contact of 0.72 (Shannon's 1.85): back at 0.3, the
  // probes go on and no full pulse is delivered (found by review: one went out, then tripped).
  Guards g;
  g.area_um2 = 5000000;
  g.flags = kGuardSuspend;
  DeviceCore core(measuring_caps());
  REQUIRE(start_codes(core, {2047, -2047, 0, 0, 0, 0, 0, 0}, 800, &g, 20000) == Result::ok);
  std::vector<std::int32_t> delivered;
  run(core, [&](std::size_t k, std::size_t c, std::int32_t i) {
    if (c == 0) delivered.push_back(i);
    if (c == 1 && k >= 3 && k <= 5) return Reading{-100000, 0, true};
    return ohmic(i, c == 1 && k > 5 ? 10000 / 0.3 : 10000);
  }, 300000);
  REQUIRE(delivered.size() == 15);
  CHECK(core.status().state == State::running);
  for (std::size_t k = 4; k < delivered.size(); ++k) CHECK(delivered[k] <= 50000);
  // Back at 0.8, above 0.72: resumed.
  DeviceCore back(measuring_caps());
  REQUIRE(start_codes(back, {2047, -2047, 0, 0, 0, 0, 0, 0}, 800, &g, 20000) == Result::ok);
  std::vector<std::int32_t> resumed;
  run(back, [&](std::size_t k, std::size_t c, std::int32_t i) {
    if (c == 0) resumed.push_back(i);
    if (c == 1 && k >= 3 && k <= 5) return Reading{-100000, 0, true};
    return ohmic(i, c == 1 && k > 5 ? 10000 / 0.8 : 10000);
  }, 300000);
  REQUIRE(resumed.size() == 15);
  CHECK(resumed[6] <= 50000);   // the probe that finds it
  CHECK(resumed[7] > 1900000);  // full again
  CHECK(back.status().state == State::running);
}

TEST_CASE("guards: a reading of 0 V does not clear the baseline, and a new output starts afresh",
          "[device][guards]") {
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, 1024, 200) == Result::ok);
  // 20 kOhm, then a shorted reading (0 V), then 300 kOhm: 15 x the baseline trips.
  const std::size_t n = run(core, [](std::size_t k, std::size_t c, std::int32_t i) {
    if (c == 0 && k == 1) return Reading{0, i, false};
    return ohmic(i, c == 0 && k >= 2 ? 300000 : 20000);
  }, 60000);
  CHECK(n == 3);
  CHECK(core.status().fault == Fault::contact);
  // No current flowed, yet not at the rail: no contact either.
  DeviceCore open(measuring_caps());
  REQUIRE(start_output(open, 1024, 200) == Result::ok);
  CHECK(run(open, [](std::size_t k, std::size_t c, std::int32_t i) {
          return c == 1 && k == 2 ? Reading{-500, 0, false} : ohmic(i, 20000);
        }, 60000) == 3);
  CHECK(open.status().fault == Fault::contact);
  // A new session and output: no trip, no baseline, nothing suspended from the old one.
  send(open, 50, Msg::stop, {}, 0);
  REQUIRE(start_output(open, 1024, 200) == Result::ok);
  const Measurements m = query(open, 0, 2, 60);
  CHECK(m.head.trip == Fault::none);
  CHECK(m.head.measured == 0);
  CHECK(m.channels[0].baseline_ohm == 0);
}

TEST_CASE("guards: set_guards' refusals, and readings of an earlier output", "[device][guards]") {
  Guards g;
  g.area_um2 = 1000000;
  {
    DeviceCore plain{Capabilities{}};  // a device that does not measure
    start_output(plain, 10, 200);
    CHECK(send(plain, 30, Msg::set_guards, with_session(kToken, encode(g)), 0) ==
          Result::not_supported);
  }
  DeviceCore core(measuring_caps());
  CHECK(send(core, 30, Msg::set_guards, with_session(kToken, encode(g)), 0) ==
        Result::wrong_session);
  REQUIRE(start_output(core, 10, 200) == Result::ok);
  CHECK(send(core, 31, Msg::set_guards, with_session(kToken, encode(g)), 0) == Result::bad_state);
  send(core, 32, Msg::stop, {}, 0);
  PulseConfig c;
  c.channels = 8;
  REQUIRE(send(core, 33, Msg::configure, with_session(kToken, encode(c)), 0) == Result::ok);
  auto refused = [&](Guards bad, Result want, std::uint8_t seq) {
    CHECK(send(core, seq, Msg::set_guards, with_session(kToken, encode(bad)), 0) == want);
  };
  Guards small = g, k_high = g, lost_low = g, probe_high = g, flags = g;
  small.area_um2 = 99;
  k_high.shannon_k_milli = 2501;
  lost_low.lost_contact_milli = 9;
  probe_high.probe_uA = 501;
  flags.flags = 2;
  refused(small, Result::out_of_range, 34);
  refused(k_high, Result::out_of_range, 35);
  refused(lost_low, Result::out_of_range, 36);
  refused(probe_high, Result::out_of_range, 40);
  refused(flags, Result::out_of_range, 41);
  auto short_frame = with_session(kToken, encode(g));
  short_frame.pop_back();
  CHECK(send(core, 37, Msg::set_guards, short_frame, 0) == Result::bad_length);
  refused(g, Result::ok, 38);
  // A reading of an output that is over changes nothing.
  PulseRecord r;
  r.channels = 8;
  r.main[0] = 10;
  ElectricalRecord m;
  m.carried[0] = m.at_rail[0] = true;
  core.measured(12345, r, m);
  CHECK(core.status().fault == Fault::stopped);
  CHECK(query(core, 0, 1, 39).head.measured == 0);
}

TEST_CASE("protocol 7: the capabilities carry the compliance, version 6's read without it",
          "[device][guards][protocol]") {
  Capabilities c = measuring_caps();
  c.compliance_V = 150;
  const auto b = encode(c);
  REQUIRE(b.size() == kCapabilitiesSize);
  const auto back = decode_capabilities(b, 0);
  REQUIRE(back);
  CHECK(back->compliance_V == 150);
  CHECK(back->measures());
  auto v6 = b;
  v6[0] = 6;
  v6.resize(kCapabilitiesSizeV6);
  const auto old = decode_capabilities(v6, 0);
  REQUIRE(old);
  CHECK(old->compliance_V == 0);
  CHECK(!old->measures());  // a version 6 device's bit 1 means nothing
  CHECK(old->shaped_pulses());
  v6.resize(kCapabilitiesSize);
  CHECK(!decode_capabilities(v6, 0));
}

TEST_CASE("stop input: the output ends at once, and only a new session delivers again",
          "[device][guards]") {
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, 1024, 200) == Result::ok);
  const std::size_t before = run(core, [](std::size_t, std::size_t, std::int32_t i) {
    return ohmic(i, 20000);
  }, 12000);  // pulses at 0, 5 and 10 ms
  CHECK(before == 3);
  const std::uint32_t ends = core.output_ends();
  core.stop_input(12345);
  CHECK(core.output_ends() == ends + 1);  // the firmware's engine follows it
  CHECK(core.status().state == State::idle);
  CHECK(core.status().fault == Fault::stop_input);
  CHECK(core.status().pulses == 3);
  std::size_t after = 0;
  core.advance(100000, [&](const DeliveredPulse&) { ++after; });
  CHECK(after == 0);
  const Measurements m = query(core, 0, 8);
  CHECK(m.head.trip == Fault::stop_input);
  CHECK(m.head.trip_channel == kNoChannel);
  CHECK(m.head.trip_t_us == 12345);
  // The old session cannot be restarted: its token ended with it.
  CHECK(send(core, 90, Msg::start, with_session(kToken, {}), 13000) == Result::wrong_session);
  // Pressed while idle, it still counts as an end (the stage stops and stays off).
  core.stop_input(14000);
  CHECK(core.output_ends() == ends + 2);
  // A new session delivers again.
  REQUIRE(start_output(core, 1024, 200) == Result::ok);
  CHECK(core.status().state == State::running);
  CHECK(core.status().fault == Fault::none);
  CHECK(std::string(to_string(Fault::stop_input)).find("stop input") != std::string::npos);
}

TEST_CASE("guards: a trip after the core completed is an end a firmware follows",
          "[device][guards]") {
  // A firmware's core completes when it hands its last pulse to the engine, before any of
  // the last pulses' readings: a guard that trips on one of them must end the output again
  // (output_ends), so that the firmware drops what its engine still holds.
  DeviceCore core(measuring_caps());
  PulseConfig c;
  c.period_us = 1000;
  c.width_us = c.balance_width_us = 200;
  c.channels = 8;
  c.max_pulses = 5;
  REQUIRE(send(core, 1, Msg::configure, with_session(kToken, encode(c)), 0) == Result::ok);
  REQUIRE(send(core, 2, Msg::set_weights,
               with_session(kToken, encode_weights({1024, -1024, 0, 0, 0, 0, 0, 0})), 0) ==
          Result::ok);
  REQUIRE(send(core, 3, Msg::start, with_session(kToken, {}), 0) == Result::ok);
  std::vector<PulseRecord> handed;
  std::uint64_t start = 0;
  core.advance(10000, [&](const DeliveredPulse& p) {
    handed.push_back(record_of(p));
    start = p.start_us;
  });
  REQUIRE(handed.size() == 5);
  CHECK(core.status().fault == Fault::completed);
  const std::uint32_t ends = core.output_ends();
  // Pulse 1 measured fine; pulse 2 finds channel 0 without contact (at the rail, nothing
  // delivered).
  for (std::size_t k = 0; k < 3; ++k) {
    ElectricalRecord m;
    for (std::size_t ch = 0; ch < 2; ++ch) {
      const auto asked = static_cast<std::int32_t>(handed[k].main[ch] * static_cast<std::int32_t>(handed[k].step_nA));
      const bool lifted = k == 2 && ch == 0;
      m.carried[ch] = true;
      m.at_rail[ch] = lifted;
      m.current_nA[ch] = lifted ? 0 : asked;
      m.voltage_mV[ch] = lifted ? 100000 : asked / 100;
    }
    core.measured(start, handed[k], m);
  }
  CHECK(core.status().fault == Fault::contact);
  CHECK(core.output_ends() == ends + 1);
}

TEST_CASE("stop input: pressed while idle, it keeps why the last output ended",
          "[device][guards]") {
  DeviceCore core(measuring_caps());
  REQUIRE(start_output(core, 1024, 200) == Result::ok);
  run(core, [](std::size_t k, std::size_t c, std::int32_t i) {
    return k == 2 && c == 0 ? Reading{100000, 0, true} : ohmic(i, 20000);
  }, 20000);
  REQUIRE(core.status().fault == Fault::contact);
  const std::uint32_t ends = core.output_ends();
  core.stop_input(30000);
  CHECK(core.status().fault == Fault::contact);  // not hidden by the later press
  CHECK(core.output_ends() == ends + 1);         // but the stage still stops
  CHECK(query(core, 0, 8).head.trip == Fault::contact);
}
