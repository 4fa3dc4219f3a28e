// Shaped pulses (pulse/shape, pulse/stimulus): phases, their units, every limit on them.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "error_support.hpp"
#include "pulse/mix.hpp"
#include "pulse/shape.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;
using tp::test::message_of;

namespace {

Stimulus shaped(std::vector<Phase> phases, std::vector<double> currents = {1.0, -1.0}) {
  Stimulus s;
  s.currents_mA = std::move(currents);
  s.count = 10;
  s.shape.phases = std::move(phases);
  return s;
}

bool says(const std::function<void()>& f, const std::string& text) {
  const std::string m = message_of(f);
  INFO(m);
  return m.find(text) != std::string::npos;
}

}  // namespace

TEST_CASE("a shorthand and its phases give the same safety figures", "[pulse]") {
  for (const auto& [w, gap, bw] : std::vector<std::tuple<double, double, double>>{
           {200, 0, 200}, {200, 100, 800}, {100, 50, 400}}) {
    Stimulus a;
    a.currents_mA = {1.2, -0.4, -0.8};
    a.count = 5;
    a.shape.width_us = w;
    a.shape.interphase_us = gap;
    a.shape.balance_width_us = bw;
    Stimulus b = a;
    b.shape.phases = shorthand_phases(w, gap, bw);
    REQUIRE(b.shape.phases.size() == (gap > 0 ? 3u : 2u));
    CHECK_NOTHROW(check_stimulus(a, StimulusLimits{}));
    CHECK_NOTHROW(check_stimulus(b, StimulusLimits{}));
    const SafetyFigures fa = safety_figures(a), fb = safety_figures(b);
    CHECK(fb.peak_current_mA == Approx(fa.peak_current_mA).epsilon(1e-12));
    CHECK(fb.max_charge_per_phase_nC == Approx(fa.max_charge_per_phase_nC).epsilon(1e-12));
    CHECK(fb.max_rms_current_mA == Approx(fa.max_rms_current_mA).epsilon(1e-12));
    CHECK(fb.max_mean_current_mA == Approx(fa.max_mean_current_mA).epsilon(1e-12));
    CHECK(fb.shannon_k == Approx(fa.shannon_k).epsilon(1e-12));
    CHECK(fb.max_net_charge_nC < 1e-12);
    CHECK(b.shape.length_us() == a.shape.length_us());
    CHECK(same_phases(a.shape.delivered(), b.shape.delivered()));
  }
}

TEST_CASE("charge per phase is the charge of a same-sign run", "[pulse]") {
  // A cathodic staircase with a gap inside it, then one anodic phase: one run of each sign.
  const std::vector<Phase> p{{100, 1}, {50, 0.5}, {20, 0}, {50, 0.5}, {200, -0.75}};
  const ShapeSums s = shape_sums(p);
  REQUIRE(s.run_charge_us.size() == 2);
  CHECK(s.run_charge_us[0] == Approx(150.0));  // 100 x 1 + 50 x 0.5 + 50 x 0.5
  CHECK(s.run_charge_us[1] == Approx(150.0));
  CHECK(s.net_us == Approx(0.0).margin(1e-12));
  CHECK(s.peak_level == 1.0);
  CHECK(s.shortest_us == 20.0);
  CHECK(s.length_us == 420.0);
  const SafetyFigures f = safety_figures(shaped(p, {0.8, -0.8}));
  CHECK(f.max_charge_per_phase_nC == Approx(0.8 * 150.0));
  CHECK(f.max_mean_current_mA == Approx(0.8 * 300.0 / 5000.0));
  CHECK(f.max_rms_current_mA ==
        Approx(0.8 * std::sqrt((100 + 2 * 50 * 0.25 + 200 * 0.5625) / 5000.0)));
  CHECK(f.shortest_phase_us == 20.0);
  CHECK(f.level_unit == 4);
}

TEST_CASE("a shape's units: the least unit and exact zero charge", "[pulse]") {
  auto units = [](std::vector<Phase> p) { return shape_units(p); };
  const ShapeUnits a = units({{200, 1}, {800, -0.25}});
  CHECK(a.unit == 4);
  CHECK(a.units == std::vector<int>{4, -1});
  CHECK(units({{300, 1}, {900, -1.0 / 3}}).unit == 3);
  CHECK(says([&] { units({{500, 0.1}, {200, 1}, {100, -0.5}, {500, -0.3}}); },
             "not charge balanced"));
  CHECK(says([&] { units({{130, 1}, {1000, -0.13}}); }, "multiples of 1/U"));
  const ShapeUnits d = units({{500, 0.1}, {200, 1}, {100, 0}, {625, -0.4}});
  CHECK(d.unit == 10);
  CHECK(d.units == std::vector<int>{1, 10, 0, -4});
}

TEST_CASE("shaped stimulus checks: each limit refused with its reason", "[pulse]") {
  const StimulusLimits lim;
  auto refuses = [&](const Stimulus& s, const std::string& text) {
    return says([&] { check_stimulus(s, lim); }, text);
  };
  const Stimulus ok = shaped({{500, 0.1}, {200, 1}, {50, 0}, {500, -0.5}});
  CHECK_NOTHROW(check_stimulus(ok, lim));
  std::vector<Phase> many;
  for (int k = 0; k < 17; ++k) many.push_back({20, k % 2 ? -1.0 : 1.0});
  CHECK(refuses(shaped(many), "17 phases, more than 16"));
  CHECK(refuses(shaped({{9, 1}, {9, -1}}), "phase 1: duration 9 us outside [10, 8000] us"));
  CHECK(refuses(shaped({{1001, 1}, {1001, -1}}), "at the largest level, longer than"));
  CHECK(refuses(shaped({{200, 1}, {200.5, -1}}), "whole microseconds"));
  CHECK(refuses(shaped({{200, 1}, {201, -1}}), "not charge balanced"));
  CHECK(refuses(shaped({{200, 1}, {131, -200.0 / 131}}), "multiples of 1/U"));
  CHECK(refuses(shaped({{200, 0}, {200, 0}}), "every level is 0"));
  CHECK(refuses(shaped({{200, 17}, {3400, -1}}), "level 17 outside [-16, 16]"));
  // Peak: 1.5 mA at level 1.5 is 2.25 mA.
  CHECK(refuses(shaped({{100, 1.5}, {150, -1}}, {1.5, -1.5}), "at level 1.5 is 2.25 mA"));
  // RMS: 1 kHz, 1.5 mA at 400 + 400 us: 1.34 mA.
  Stimulus rms = shaped({{400, 1}, {400, -1}}, {1.5, -1.5});
  rms.shape.frequency_hz = 1000;
  CHECK(refuses(rms, "RMS current"));
  // Shannon's k: 2 mA x 1000 us = 2 uC per phase on 5 mm2 (40 uC/cm2): k = 1.9.
  Stimulus k = shaped({{1000, 1}, {1000, -1}}, {2, -2});
  k.shape.frequency_hz = 10;
  CHECK(refuses(k, "Shannon's k"));
  Stimulus fit = shaped({{1000, 1}, {4000, -0.25}});
  CHECK(refuses(fit, "does not fit its period"));
  // On a device (protocol 6): no widths, the phases in whole units of 1/U.
  Mix m;
  m.patterns = {ok};
  CHECK_NOTHROW(check_mix(m, lim));
  const device::PatternTiming t = pattern_timing(ok, 10);
  CHECK(t.width_us == 0);
  CHECK(t.shape.n == 4);
  CHECK(t.shape.duration_us[2] == 50);
  CHECK(t.shape.units[0] == 1);
  CHECK(t.shape.units[3] == -5);
  CHECK(t.length_us() == 1250);
}

TEST_CASE("a shaped stimulus round-trips through its document", "[pulse]") {
  Stimulus s = shaped({{500, 0.1}, {200, 1}, {50, 0}, {500, -0.5}});
  s.shape.frequency_hz = 100;
  const Json j = stimulus_to_json(s);
  CHECK(j["pulse"].size() == 2);  // phases and frequency_hz only
  CHECK(j["safety"]["level_unit"] == 10);
  CHECK(j["safety"]["shortest_phase_us"] == 50.0);
  const Stimulus back = stimulus_from_json(j);
  CHECK(same_phases(back.shape.phases, s.shape.phases));
  CHECK(back.shape.frequency_hz == 100);
  Json both = j;
  both["pulse"]["width_us"] = 200;
  CHECK(says([&] { stimulus_from_json(both); }, "give phases or width_us, not both"));
  Json bad = j;
  bad["pulse"]["phases"][1] = Json{{"duration_us", 200}};
  CHECK(says([&] { stimulus_from_json(bad); }, "pulse.phases[1]: expected"));
  // Corner points: one row at each edge of each phase.
  const auto rows = waveform_points(s, 1);
  REQUIRE(rows.size() == 1 + 2 * 4 + 1 + 1);
  CHECK(rows[2][0] == 500.0);
  CHECK(rows[2][1] == 0.1);
  CHECK(rows[3][0] == 500.0);
  CHECK(rows[3][1] == 1.0);
  CHECK(rows[9][0] == 1250.0);
  CHECK(rows[9][1] == 0.0);
}

TEST_CASE("phases from text", "[pulse]") {
  const auto p = phases_from_text("200:1, 100:0,800:-0.25", "--phases");
  REQUIRE(p.size() == 3);
  CHECK(p[2].duration_us == 800);
  CHECK(p[2].level == -0.25);
  CHECK(describe_phases(p) == "200 us at 1, 100 us at 0, 800 us at -0.25");
  CHECK(says([] { phases_from_text("200", "--phases"); }, "--phases: expected DURATION_US:LEVEL"));
  CHECK(says([] { phases_from_text("200:x", "--phases"); }, "--phases level: not a number"));
  std::string seventeen;
  for (int k = 0; k < 17; ++k) seventeen += (k ? ",20:" : "20:") + std::to_string(k % 2 ? -1 : 1);
  CHECK(says([&] { phases_from_text(seventeen, "--phases"); }, "more than 16 phases"));
}
