// psych::Calibration (lib/psych/calibration.hpp): its options' refusals, its trials' order
// and stimuli, a deterministic observer's threshold and comfort found within the
// staircase's step, what ended each staircase that found nothing, the session's length,
// stages and summary, and its log.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number.hpp"
#include "psych/calibration.hpp"
#include "render_support.hpp"

using namespace tp;
using namespace tp::render_test;

namespace {

// Runs a calibration to its end: answer(primary, comfort question?, level).
template <class Observer>
Calibration calibrate(const PixelBank& b, const CalibrationOptions& o, Observer&& answer) {
  Calibration c(b, o);
  while (!c.done()) c.respond(answer(c.primary(), c.comfort(), c.level_mA()));
  return c;
}

}  // namespace

TEST_CASE("calibration says what ended each staircase that found nothing", "[psych]") {
  const PixelBank b = two_pads();
  CalibrationOptions o;
  o.pads = {0};
  o.primaries = {1};
  using Catch::Matchers::Contains;
  auto note = [&](const CalibrationOptions& opt, auto&& answer) {
    const Calibration c = calibrate(b, opt, answer);
    REQUIRE(c.notes().size() == 1);
    return c.notes()[0];
  };
  // The threshold: nothing felt; felt once, then not at the ceiling; felt at the floor;
  // out of trials.  Each leaves the primary out, and none says "up to the ceiling" unless
  // the ceiling ended it.
  CHECK_THAT(note(o, [](int, bool, double) { return false; }),
             Contains("SAI at pixel (0, 0): not felt up to the ceiling, 1 mA; no threshold"));
  int k = 0;
  CHECK_THAT(note(o, [&](int, bool, double) { return k++ == 0; }),
             Contains("not felt 3 times in a row at the ceiling, 1 mA, after a \"felt\" below it"));
  const std::string floor = note(o, [](int, bool, double) { return true; });
  CHECK_THAT(floor, Contains("felt 3 times in a row at the floor, 0.001 mA"));
  CHECK_THAT(floor, !Contains("ceiling"));
  CalibrationOptions short_run = o;
  short_run.staircase.reversals = 30;
  short_run.staircase.max_trials = 20;
  k = 0;
  const std::string out = note(short_run, [&](int, bool, double l) { return l > 0.1 && k++ % 2; });
  CHECK_THAT(out, Contains("no threshold within 20 trials (--max-trials): "));
  CHECK_THAT(out, Contains(" of 30 reversals; no threshold, left out of the profile"));
  CHECK_THAT(out, !Contains("ceiling"));
  // The comfort limit, after a threshold at 0.3 mA: never too strong (the ceiling, kept);
  // too strong down to the floor, or out of trials (left out: nothing to trust).
  auto felt = [](double l) { return l > 0.3; };
  const Calibration numb = calibrate(b, o, [&](int, bool c, double l) { return !c && felt(l); });
  CHECK_THAT(numb.notes().at(0),
             Contains("never too strong up to the ceiling, 1 mA; comfort set to the ceiling"));
  CHECK(numb.profile().primary[1]->comfort_mA == 1.0);
  const Calibration raw = calibrate(b, o, [&](int, bool c, double l) { return c || felt(l); });
  CHECK_THAT(raw.notes().at(0), Contains("too strong 3 times in a row at the floor, 0.001 mA"));
  CHECK_THAT(raw.notes().at(0), Contains("no comfort limit, left out of the profile"));
  CHECK_FALSE(raw.profile().primary[1].has_value());
  // (A threshold found in 25 trials; "too strong" in runs of four: a reversal every fourth
  // trial, 6 of 8 by the 25th.)
  CalibrationOptions slow_run = o;
  slow_run.staircase.max_trials = 25;
  k = 0;
  const Calibration slow = calibrate(
      b, slow_run, [&](int, bool c, double l) { return c ? (k++ / 4) % 2 == 0 : felt(l); });
  REQUIRE(slow.notes().size() == 1);
  CHECK_FALSE(slow.profile().primary[1].has_value());
  CHECK_THAT(slow.notes().back(),
             Contains("no comfort limit within 25 trials (--max-trials): 6 of 8 reversals"));
}

TEST_CASE("calibration: the session's length, its stages and its summary, from the procedure",
          "[psych]") {
  const PixelBank b = two_pads();
  CalibrationOptions o;
  o.pads = {0, 1};
  o.primaries = {2, 0};  // PC, then RA
  Calibration c(b, o);
  const CalibrationLength n = c.length();
  CHECK(n.staircases == 8);  // 2 pixels x 2 primaries x 2 questions
  CHECK(n.most == 8 * o.staircase.max_trials);
  CHECK(c.length_text() == "PC and RA at 2 pixels: 8 staircases, about " +
                               std::to_string(n.typical) + " trials of 0.5 s, at most 640");
  // "About": exactly the trials of observers at the levels it assumes (the threshold
  // halfway from the start to the ceiling in log level, comfort halfway from there).
  const double thr = std::sqrt(o.staircase.start_mA * o.staircase.ceiling_mA);
  const double comfort = std::sqrt(thr * o.staircase.ceiling_mA);
  std::vector<std::string> stages;
  while (!c.done()) {
    if (!c.stage_text().empty()) stages.push_back(c.stage_text());
    c.respond(c.level_mA() > (c.comfort() ? comfort : thr));
  }
  CHECK(static_cast<int>(c.trials().size()) == n.typical);
  REQUIRE(stages.size() == 8u);
  CHECK(stages[0] == "PC, primary 1 of 2, at pixel (0, 0), 1 of 2: the threshold, felt it?");
  CHECK(stages[1] == "PC, primary 1 of 2, at pixel (0, 0), 1 of 2: the comfort limit, too strong?");
  CHECK(stages[2] == "RA, primary 2 of 2, at pixel (0, 0), 1 of 2: the threshold, felt it?");
  CHECK(stages[7] == "RA, primary 2 of 2, at pixel (1, 0), 2 of 2: the comfort limit, too strong?");
  const Profile p = c.profile();
  const std::string s = c.summary();
  CHECK_THAT(s, Catch::Matchers::StartsWith(std::to_string(c.trials().size()) + " trials; PC "));
  CHECK_THAT(
      s, Catch::Matchers::Contains("; RA threshold " +
                                   number_text(std::round(p.primary[0]->threshold_mA * 1e4) / 1e4) +
                                   " mA, comfort "));
  CHECK_THAT(s, Catch::Matchers::EndsWith("(the medians of 2 pixels)"));
  // A primary not found is said so.
  CalibrationOptions one = o;
  one.pads = {1};
  const Calibration none = calibrate(
      b, one, [](int primary, bool q, double l) { return primary == 0 && l > (q ? 0.6 : 0.2); });
  CHECK_THAT(none.summary(), Catch::Matchers::Contains("; PC not found; RA threshold "));
}

TEST_CASE("calibration: every trial at the ceiling checked against a device before the first",
          "[psych]") {
  const PixelBank b = two_pads();
  CalibrationOptions o;
  o.pads = {0, 1};
  o.staircase.ceiling_mA = 0.8;
  const Calibration c(b, o);
  // A device of 0.5 mA: refused at the ceiling, naming it, the first unit that breaks it,
  // the device's reason and the highest ceiling that passes.
  std::vector<double> levels;
  auto device = [&](const Mix& m) {
    levels.push_back(m.patterns[0].amplitude_mA);
    for (double i : m.patterns[0].currents_mA)
      if (std::fabs(i) > 0.5) bad_input("current " + number_text(i) + " mA above 0.5 mA");
  };
  CHECK_THROWS_WITH(c.check_trials(device),
                    "--ceiling 0.8 mA: the device cannot deliver RA at pixel (0, 0) at it "
                    "(current 0.8 mA above 0.5 mA); lower --ceiling to 0.5 mA or less; "
                    "nothing was sent");
  try {
    c.check_trials(device);
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
  }
  // Within it: every unit (3 primaries x 2 pixels) checked once, at the ceiling.
  levels.clear();
  CalibrationOptions low = o;
  low.staircase.ceiling_mA = 0.5;
  const Calibration fits(b, low);
  CHECK_NOTHROW(fits.check_trials(device));
  CHECK(levels == std::vector<double>(6, 0.5));
  // A limit no level keeps: said so, with no ceiling to suggest.
  CHECK_THROWS_WITH(
      c.check_trials([](const Mix&) { bad_input("stimulus has 2 channels; the device has 1"); }),
      "RA at pixel (0, 0): the device cannot deliver its trials at any level: "
      "stimulus has 2 channels; the device has 1; nothing was sent");
  // Not bad input (the device lost): passed on as it is.
  CHECK_THROWS_WITH(c.check_trials([](const Mix&) { failure("device lost"); }), "device lost");
}

TEST_CASE("calibration's log: a header and one row per trial", "[psych]") {
  CHECK(calibration_log_header() ==
        "trial,primary,pad,column,row,question,level_mA,phase,response,reversal,pulses,peak_mA");
  CalibrationTrial t;
  t.n = 7;
  t.primary = 1;
  t.pad = 11;
  t.comfort = true;
  t.level_mA = 0.25;
  t.ascending = false;
  t.yes = true;
  t.reversal = true;
  CHECK(calibration_log_row(t, 8, 10, 0.2499) ==
        "7,SAI,11,3,1,too strong,0.25,staircase,yes,1,10,0.2499");
}

TEST_CASE("calibration: a deterministic observer's threshold and comfort, per pixel too",
          "[render][psych]") {
  const PixelBank& b = bank6();
  CalibrationOptions o;
  o.primaries = {1};  // SAI
  o.pads = {14, 21};
  const double thr[2] = {0.3, 0.2}, comfort[2] = {0.7, 0.5};
  Calibration cal(b, o);
  double top = 0;
  while (!cal.done()) {
    const Mix m = cal.stimulus();
    const std::size_t k = cal.pad() == 14 ? 0 : 1;
    const auto& w = b.entry[static_cast<std::size_t>(cal.pad())][1].weights;
    for (std::size_t e = 0; e < w.size(); ++e)
      REQUIRE(m.patterns[0].currents_mA[e] == Approx(cal.level_mA() * w[e]));
    top = std::max(top, cal.level_mA());
    cal.respond(cal.level_mA() > (cal.comfort() ? comfort[k] : thr[k]));
  }
  CHECK(top <= o.staircase.ceiling_mA);
  const Profile p = cal.profile();
  const double step = std::sqrt(o.staircase.step_factor);
  for (std::size_t k = 0; k < 2; ++k) {
    const PrimaryRange& r = *p.pixel.at(k == 0 ? 14 : 21)[1];
    CHECK(std::abs(std::log(r.threshold_mA / thr[k])) <= std::log(step) + 1e-12);
    CHECK(std::abs(std::log(r.comfort_mA / comfort[k])) <= std::log(step) + 1e-12);
  }
  // The primary's range: the lower middle of the pixels' (here, the lower of two).
  CHECK(p.primary[1]->threshold_mA == p.pixel.at(21)[1]->threshold_mA);
  CHECK_FALSE(p.primary[0].has_value());
  CHECK(profile_from_json(profile_to_json(p), 2.0, 36).primary[1]->threshold_mA ==
        p.primary[1]->threshold_mA);
  // Someone who never feels anything: no threshold, a note, no range.
  CalibrationOptions one = o;
  one.pads = {14};
  Calibration none(b, one);
  while (!none.done()) none.respond(false);
  CHECK_FALSE(none.profile().primary[1].has_value());
  REQUIRE(none.notes().size() == 1);
  CHECK_THAT(none.notes()[0], Catch::Contains("not felt up to the ceiling, 1 mA; no threshold"));
  // The bank's own current limit bounds the ceiling; a trial that some limit refuses at
  // the ceiling (the RMS current, with 1000 us phases at 2 mA) is refused before any trial.
  PixelBank low = b;
  low.doc.max_current_mA = 0.5;
  CHECK_THROWS_WITH(Calibration(low, one), Catch::Contains("above the bank's current limit"));
  CalibrationOptions wide = one;
  wide.width_us = wide.balance_width_us = 1000;
  wide.staircase.ceiling_mA = 2.0;
  CHECK_THROWS_WITH(Calibration(b, wide), Catch::Contains("above the limit"));
  // Never too strong: comfort is the ceiling.
  Calibration numb(b, one);
  while (!numb.done()) numb.respond(numb.comfort() ? false : numb.level_mA() > 0.3);
  CHECK(numb.profile().primary[1]->comfort_mA == o.staircase.ceiling_mA);
}

TEST_CASE("calibration options: each refusal names its option, the first out of range",
          "[psych][calibration]") {
  const PixelBank b = two_pads();
  CalibrationOptions o;
  o.pads = {0, 1};
  CHECK_NOTHROW(check_calibration_options(o, b));
  CalibrationOptions t = o;
  t.trial_s = 0.01;
  CHECK_THROWS_WITH(check_calibration_options(t, b),
                    "--trial-duration: 0.01 s outside [0.05, 10] s");
  CalibrationOptions none = o;
  none.pads.clear();
  CHECK_THROWS_WITH(check_calibration_options(none, b), "calibrate: no pixel to measure");
  CalibrationOptions pad = o;
  pad.pads = {0, 2};
  CHECK_THROWS_WITH(check_calibration_options(pad, b), "--pixel: pad 2 is not one of the bank's 2");
  CalibrationOptions prim = o;
  prim.primaries = {1, 3};
  CHECK_THROWS_WITH(check_calibration_options(prim, b), "--primaries: not a primary");
  CalibrationOptions ceiling = o;
  PixelBank low = b;
  low.doc.max_current_mA = 0.5;
  CHECK_THROWS_WITH(check_calibration_options(ceiling, low),
                    "--ceiling: 1 mA is above the bank's current limit, 0.5 mA");
  // The constructor checks them too, and the first refusal wins.
  t.pads.clear();
  CHECK_THROWS_WITH(Calibration(b, t), "--trial-duration: 0.01 s outside [0.05, 10] s");
  try {
    check_calibration_options(t, b);
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
  }
}

TEST_CASE("calibration trials: pixels in the order given, each primary in turn, the same each run",
          "[psych][calibration]") {
  const PixelBank b = two_pads();
  CalibrationOptions o;
  o.pads = {1, 0};
  o.primaries = {2, 0};
  o.trial_s = 0.4;
  // An observer whose answers depend on the trial only: two runs give the same trials.
  auto observer = [](int primary, bool comfort, double level) {
    return level > (comfort ? 0.6 : 0.1 + 0.1 * primary);
  };
  std::vector<std::pair<long, int>> order;
  Calibration c(b, o);
  while (!c.done()) {
    const std::pair<long, int> unit{c.pad(), c.primary()};
    if (order.empty() || order.back() != unit) order.push_back(unit);
    // The trial's stimulus: the pixel's pattern at the level, at the primary's rate.
    const Mix m = c.stimulus();
    REQUIRE(m.patterns.size() == 1);
    const Stimulus& s = m.patterns[0];
    const auto& w =
        b.entry[static_cast<std::size_t>(c.pad())][static_cast<std::size_t>(c.primary())].weights;
    REQUIRE(s.currents_mA.size() == w.size());
    for (std::size_t e = 0; e < w.size(); ++e) CHECK(s.currents_mA[e] == c.level_mA() * w[e]);
    CHECK(s.amplitude_mA == c.level_mA());
    CHECK(c.level_mA() <= o.staircase.ceiling_mA);
    CHECK(s.shape.frequency_hz == o.rate_hz[static_cast<std::size_t>(c.primary())]);
    CHECK(s.count == std::lround(o.trial_s * s.shape.frequency_hz));
    CHECK(s.shape.width_us == o.width_us);
    CHECK(s.shape.balance_width_us == o.balance_width_us);
    c.respond(observer(c.primary(), c.comfort(), c.level_mA()));
  }
  CHECK(order == std::vector<std::pair<long, int>>{{1, 2}, {1, 0}, {0, 2}, {0, 0}});
  const Calibration again = calibrate(b, o, observer);
  REQUIRE(again.trials().size() == c.trials().size());
  for (std::size_t k = 0; k < c.trials().size(); ++k) {
    CHECK(again.trials()[k].level_mA == c.trials()[k].level_mA);
    CHECK(again.trials()[k].yes == c.trials()[k].yes);
    CHECK(again.trials()[k].primary == c.trials()[k].primary);
    CHECK(again.trials()[k].pad == c.trials()[k].pad);
    CHECK(again.trials()[k].comfort == c.trials()[k].comfort);
  }
  // Finished: no more trials, a response changes nothing, and every unit has its range.
  const std::size_t n = c.trials().size();
  c.respond(true);
  CHECK(c.trials().size() == n);
  const Profile p = c.profile();
  REQUIRE(p.primary[0].has_value());
  REQUIRE(p.primary[2].has_value());
  CHECK_FALSE(p.primary[1].has_value());
  CHECK(c.notes().empty());
  const double step = std::log(std::sqrt(o.staircase.step_factor)) + 1e-12;
  for (const long pad : {0L, 1L})
    for (const int primary : {0, 2}) {
      const PrimaryRange& r = *p.pixel.at(pad)[static_cast<std::size_t>(primary)];
      CHECK(std::abs(std::log(r.threshold_mA / (0.1 + 0.1 * primary))) <= step);
      CHECK(std::abs(std::log(r.comfort_mA / 0.6)) <= step);
    }
}
