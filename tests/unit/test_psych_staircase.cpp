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
  refused([](StaircaseOptions& o) { o.ceiling_mA = 2.5; }, "--ceiling: 2.5 mA outside (0, 2] mA");
  refused([](StaircaseOptions& o) { o.start_mA = 1.2; }, "--start: 1.2 mA outside [0.001, 1] mA");
  refused([](StaircaseOptions& o) { o.start_mA = 4.9e-324; }, "--start: ");
  refused([](StaircaseOptions& o) { o.ascend_factor = 1.6; }, "--step: 1.6 outside");
  refused([](StaircaseOptions& o) { o.step_factor = 1.0; }, "--step: 1 outside");
  refused([](StaircaseOptions& o) { o.max_step_up = 3; }, "--max-step: 3 outside (1, 2]");
  refused([](StaircaseOptions& o) { o.down = 4; }, "--down: 4 outside [1, 3]");
  refused([](StaircaseOptions& o) { o.reversals = 2; }, "--reversals: 2 outside [4, 30]");
  refused([](StaircaseOptions& o) { o.start_mA = std::nan(""); }, "--start: ");
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
