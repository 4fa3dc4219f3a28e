// The calibration's adaptive procedure (lib/psych/staircase.hpp) against simulated
// observers: a deterministic one (its threshold found within the final step), stochastic
// ones (the staircase's mean estimate on the point Levitt's rule converges on), and the
// safety rules (never above the ceiling, no step up larger than the bound).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.hpp"
#include "core/number.hpp"
#include "psych/calibration.hpp"
#include "psych/staircase.hpp"

using namespace tp;

namespace {

// Runs a staircase to its end against an observer answer(level).
template <class Observer>
Staircase run(const StaircaseOptions& o, Observer&& answer) {
  Staircase s(o);
  while (!s.done()) s.respond(answer(s.level_mA()));
  return s;
}

void check_safety(const Staircase& s, const StaircaseOptions& o) {
  const auto& t = s.trials();
  for (std::size_t k = 0; k < t.size(); ++k) {
    REQUIRE(t[k].level_mA <= o.ceiling_mA);
    // No step up beyond the configured steps (themselves within max_step_up), and no
    // level below the floor.
    const double step = std::max(o.ascend_factor, o.step_factor);
    REQUIRE(step <= o.max_step_up);
    if (k > 0) REQUIRE(t[k].level_mA <= t[k - 1].level_mA * step * (1 + 1e-12));
    REQUIRE(t[k].level_mA >= kMinLevel_mA);
  }
}

}  // namespace

TEST_CASE("a deterministic observer's threshold is found within the final step",
          "[psych][staircase]") {
  StaircaseOptions o;
  o.ceiling_mA = 1.5;
  for (double hidden : {0.11, 0.37, 0.9, 1.3}) {
    const Staircase s = run(o, [&](double level) { return level > hidden; });
    INFO("hidden threshold " << hidden);
    REQUIRE(s.found());
    check_safety(s, o);
    const double final_step = std::sqrt(o.step_factor);
    CHECK(s.estimate_mA() >= hidden / final_step);
    CHECK(s.estimate_mA() <= hidden * final_step);
    CHECK(s.trials().front().ascending);
    CHECK(s.trials().size() < 60u);
  }
}

TEST_CASE("the mean estimate lies on the point the n-down-1-up rule converges on",
          "[psych][staircase]") {
  // A logistic psychometric function in log level: P(yes) = 1 / (1 + exp(-(ln L - ln T) /
  // s)).  n-down-1-up converges where P^n = 1/2 (Levitt 1971): P = 0.5, 0.707, 0.794.
  const double T = 0.4, slope = 0.08;
  for (int down : {1, 2, 3}) {
    StaircaseOptions o;
    o.down = down;
    o.reversals = 14;
    o.max_trials = 300;
    const double p = std::pow(0.5, 1.0 / down);
    const double target = T * std::exp(slope * std::log(p / (1 - p)));
    std::mt19937_64 rng(40 + down);
    std::uniform_real_distribution<double> u(0, 1);
    double log_sum = 0;
    int found = 0;
    for (int run_k = 0; run_k < 2000; ++run_k) {
      const Staircase s = run(o, [&](double level) {
        return u(rng) < 1 / (1 + std::exp(-(std::log(level) - std::log(T)) / slope));
      });
      if (!s.found()) continue;
      check_safety(s, o);
      log_sum += std::log(s.estimate_mA());
      ++found;
    }
    INFO(down << "-down-1-up: target " << target << " mA");
    REQUIRE(found > 1900);
    CHECK(std::exp(log_sum / found) ==
          Approx(target).epsilon(0.015));  // 2- and 3-down: 3.8 % apart
  }
}

TEST_CASE("nothing felt up to the ceiling: not found, and the ceiling never passed",
          "[psych][staircase]") {
  StaircaseOptions o;
  o.start_mA = 0.1;
  o.ceiling_mA = 0.6;
  const Staircase s = run(o, [](double) { return false; });
  CHECK_FALSE(s.found());
  check_safety(s, o);
  CHECK(s.trials().back().level_mA == o.ceiling_mA);
  // 0.1 x 1.25^k while below 0.6 (nine levels, to 0.596), then 0.6 itself
  CHECK(s.trials().size() == 10u);
  // Felt only at the ceiling: the staircase runs there, never above.
  const Staircase t = run(o, [&](double level) { return level >= o.ceiling_mA; });
  check_safety(t, o);
  CHECK(t.found());
  CHECK(t.estimate_mA() <= o.ceiling_mA);
}

TEST_CASE("staircase options outside their ranges are bad input", "[psych][staircase]") {
  auto refused = [](auto change, const char* says) {
    StaircaseOptions o;
    change(o);
    try {
      Staircase s(o);
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      CHECK_THAT(e.what(), Catch::Matchers::StartsWith(says));
    }
  };
  refused([](StaircaseOptions& o) { o.ceiling_mA = 2.5; }, "ceiling 2.5 outside (0, 2]");
  refused([](StaircaseOptions& o) { o.start_mA = 1.2; }, "start level 1.2 outside [0.001, 1]");
  refused([](StaircaseOptions& o) { o.start_mA = 4.9e-324; }, "start level ");
  refused([](StaircaseOptions& o) { o.ascend_factor = 1.6; }, "ascending step 1.6 outside");
  refused([](StaircaseOptions& o) { o.step_factor = 1.0; }, "staircase step 1 outside");
  refused([](StaircaseOptions& o) { o.max_step_up = 3; }, "largest step up 3 outside");
  refused([](StaircaseOptions& o) { o.down = 4; }, "down count 4 outside [1, 3]");
  refused([](StaircaseOptions& o) { o.reversals = 2; }, "reversals 2 outside [4, 30]");
  refused([](StaircaseOptions& o) { o.start_mA = std::nan(""); }, "start level ");
}

TEST_CASE("a run never dwells at the ceiling, nor goes under the floor", "[psych][staircase]") {
  StaircaseOptions o;
  // One "yes" (a false alarm, or a comfort limit above the ceiling), then only "no": the
  // staircase climbs to the ceiling and ends there after kNoAtCeiling answers, not found.
  int calls = 0;
  const Staircase s = run(o, [&](double) { return calls++ == 0; });
  CHECK_FALSE(s.found());
  check_safety(s, o);
  int at_ceiling = 0;
  for (const auto& t : s.trials()) at_ceiling += t.level_mA >= o.ceiling_mA;
  CHECK(at_ceiling == kNoAtCeiling);
  CHECK(s.trials().size() < 30u);
  CHECK(s.end() == StaircaseEnd::no_at_ceiling);
  // Always "yes": the levels go down to the floor and stop there; kYesAtFloor answers
  // there end the run, not found (before: it dwelt there to its trial limit).
  const Staircase low = run(o, [](double) { return true; });
  check_safety(low, o);
  CHECK_FALSE(low.found());
  CHECK(low.end() == StaircaseEnd::yes_at_floor);
  int at_floor = 0;
  for (const auto& t : low.trials()) at_floor += t.level_mA <= kMinLevel_mA;
  CHECK(at_floor == kYesAtFloor);
  CHECK(static_cast<int>(low.trials().size()) < o.max_trials);
  // From the floor itself: the first three answers.
  o.start_mA = kMinLevel_mA;
  const Staircase floor = run(o, [](double) { return true; });
  CHECK(floor.end() == StaircaseEnd::yes_at_floor);
  CHECK(floor.trials().size() == static_cast<std::size_t>(kYesAtFloor));
}

TEST_CASE("each way a run ends is told apart", "[psych][staircase]") {
  StaircaseOptions o;
  CHECK(Staircase(o).end() == StaircaseEnd::running);
  CHECK(run(o, [](double l) { return l > 0.3; }).end() == StaircaseEnd::reversals);
  CHECK(run(o, [](double) { return false; }).end() == StaircaseEnd::ceiling);
  // Alternating answers, more reversals asked than the trials allow: out of trials, with
  // the reversals it made.
  o.reversals = 30;
  o.max_trials = 20;
  int k = 0;
  const Staircase t = run(o, [&](double) { return (k++ / 2) % 2 == 0; });
  CHECK(t.end() == StaircaseEnd::trials);
  CHECK_FALSE(t.found());
  CHECK(t.trials().size() == 20u);
  CHECK(t.reversals() > 0);
  CHECK(t.reversals() < 30);
}

namespace {

// A bank of two pixels in a row, each primary's pattern +1 at its own pad and -1 at the
// other's (as make-pulse checks it: balanced, within every limit at 1 mA).
PixelBank two_pads() {
  PixelBank b;
  b.columns = 2;
  b.rows = 1;
  b.pad_area_mm2 = 1;
  b.entry.resize(2);
  for (std::size_t pad = 0; pad < 2; ++pad)
    for (auto& e : b.entry[pad]) {
      e.present = e.feasible = true;
      e.weights = pad == 0 ? std::vector<double>{1, -1} : std::vector<double>{-1, 1};
    }
  return b;
}

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

TEST_CASE("the largest steps allowed: every run within them, against random observers",
          "[psych][staircase]") {
  StaircaseOptions o;
  o.ascend_factor = o.step_factor = o.max_step_up = 2;
  o.ceiling_mA = 2;
  o.start_mA = 0.01;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  int found = 0;
  for (int k = 0; k < 5000; ++k) {
    const double threshold = 0.01 + u(rng) * 2;
    const Staircase s =
        run(o, [&](double level) { return u(rng) < (level > threshold ? 0.9 : 0.1); });
    check_safety(s, o);
    found += s.found();
  }
  CHECK(found > 2000);
}
