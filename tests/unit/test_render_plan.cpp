// The still's plan step by step (lib/render/plan.hpp): lit -> groups -> frame -> mix, each
// against what it promises: the lit patterns at the profile's currents; the reach's
// crosstalk equal to each pattern's own field evaluated anew; the conflicts exactly where
// a pad is shared, a kin differs or the bound is broken; groups without a conflict
// inside; the frame's problem and rates in closed form; the mix's phases, counts and
// pixels as the frame placed them.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "core/error.hpp"
#include "render/colouring.hpp"
#include "render_support.hpp"

using namespace tp;
using namespace tp::render_test;

namespace {

// Some of every primary lit, pixel by pixel, from a seeded random image.
PadIntensities some_lit(const PixelBank& b) {
  std::mt19937 rng(39);
  return random_image(b, rng, 0.5);
}

}  // namespace

TEST_CASE("plan steps: lit patterns, their reach and their conflicts", "[render][plan]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  const PadIntensities im = some_lit(b);
  RenderOptions o;
  o.threads = 2;
  // lit: pixel-major, then by primary, every intensity above 0 once, at the profile's current.
  const std::vector<LitPattern> lit = lit_patterns(b, profile, im, o);
  std::size_t k = 0;
  for (std::size_t pad = 0; pad < 36; ++pad)
    for (int p = 0; p < 3; ++p) {
      const double v = im.value[pad][static_cast<std::size_t>(p)];
      if (!(v > 0)) continue;
      REQUIRE(k < lit.size());
      CHECK(lit[k].pad == static_cast<long>(pad));
      CHECK(lit[k].primary == p);
      CHECK(lit[k].intensity == v);
      CHECK(lit[k].current_mA == profile.current_mA(p, static_cast<long>(pad), v));
      ++k;
    }
  CHECK(k == lit.size());
  RenderOptions low = o;
  low.limits.max_current_mA = 0.5;  // SAI's comfort is 0.9 mA
  PadIntensities full = dark6();
  full.value[14][1] = 1.0;
  CHECK_THROWS_WITH(lit_patterns(b, profile, full, low),
                    Catch::Contains("image pixel (2, 2) lights SAI at 0.9 mA, above the current "
                                    "limit"));

  // The reach: crosstalk by superposition equals each pattern's field built anew; a
  // pattern onto itself is 1; pads shared exactly where both weights are not 0.
  const LitReach reach(b, lit, o.threads);
  int compared = 0;
  for (std::size_t i = 0; i < lit.size(); ++i)
    for (std::size_t j = 0; j < lit.size(); ++j) {
      const auto& wi = entry_of(b, lit[i]).weights;
      const auto& wj = entry_of(b, lit[j]).weights;
      bool share = false;
      for (std::size_t e = 0; e < wi.size(); ++e) share = share || (wi[e] != 0 && wj[e] != 0);
      CHECK(reach.share_pad(i, j) == share);
      if (lit[i].primary != lit[j].primary || (i + j) % 5 != 0) continue;  // a sample
      const double want = crosstalk_oracle(b, lit[i].primary, lit[i].pad, lit[i].current_mA,
                                           lit[j].pad, lit[j].current_mA);
      CHECK(reach.crosstalk(i, j) == Approx(want).epsilon(1e-9).margin(1e-12));
      if (i == j) CHECK(reach.crosstalk(i, i) == Approx(1.0));
      ++compared;
    }
  CHECK(compared > 20);

  // The conflicts of one primary: symmetric, edges exactly where the rule says.
  std::vector<std::size_t> nodes;
  for (std::size_t i = 0; i < lit.size(); ++i)
    if (lit[i].primary == 1) nodes.push_back(i);
  REQUIRE(nodes.size() > 4);
  for (const double bound : {0.02, 0.2}) {
    const auto adj = conflict_graph(reach, lit, nodes, {}, bound, o.threads);
    REQUIRE(adj.size() == nodes.size());
    for (std::size_t a = 0; a < nodes.size(); ++a)
      for (std::size_t c = 0; c < nodes.size(); ++c) {
        if (a == c) continue;
        const std::size_t i = nodes[a], j = nodes[c];
        const bool want =
            reach.share_pad(i, j) || std::max(reach.crosstalk(i, j), reach.crosstalk(j, i)) > bound;
        const bool edge = std::find(adj[a].begin(), adj[a].end(), c) != adj[a].end();
        CHECK(edge == want);
      }
  }
  // Every pattern its own kin: every pair conflicts.
  std::vector<long> kin(3 * 36);
  for (std::size_t i = 0; i < kin.size(); ++i) kin[i] = static_cast<long>(i);
  const auto alone = conflict_graph(reach, lit, nodes, kin, 1.0, o.threads);
  for (const auto& neighbours : alone) CHECK(neighbours.size() == nodes.size() - 1);
}

TEST_CASE("plan steps: groups, their currents, the frame and the mix", "[render][plan]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  RenderOptions o;
  o.threads = 2;
  o.crosstalk = 0.2;
  o.duration_s = 0.5;
  RenderPlan plan;
  plan.requested_hz = o.rate_hz;
  plan.lit = lit_patterns(b, profile, some_lit(b), o);
  group_patterns(b, o, {}, plan);
  // groups: by primary, every lit pattern in one, none holding a conflict; the worst
  // crosstalk among members is the plan's.
  const LitReach reach(b, plan.lit, o.threads);
  std::vector<int> seen(plan.lit.size(), 0);
  std::array<int, 3> per_primary{};
  double worst = 0;
  int shared = 0;
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    const RenderGroup& grp = plan.groups[g];
    if (g > 0) CHECK(plan.groups[g - 1].primary <= grp.primary);
    ++per_primary[static_cast<std::size_t>(grp.primary)];
    shared += grp.members.size() > 1;
    for (const std::size_t i : grp.members) {
      ++seen[i];
      CHECK(plan.lit[i].primary == grp.primary);
      for (const std::size_t j : grp.members)
        if (i != j) {
          CHECK_FALSE(reach.share_pad(i, j));
          CHECK(reach.crosstalk(i, j) <= o.crosstalk);
          worst = std::max(worst, reach.crosstalk(i, j));
        }
    }
  }
  for (const int s : seen) CHECK(s == 1);
  CHECK(per_primary == plan.groups_per_primary);
  CHECK(plan.worst_crosstalk == worst);
  CHECK(shared > 0);

  // Their currents: each member's current times its weights, summed.
  const auto currents = group_currents(b, plan);
  REQUIRE(currents.size() == plan.groups.size());
  for (std::size_t g = 0; g < plan.groups.size(); ++g)
    for (std::size_t e = 0; e < 36; ++e) {
      double want = 0;
      for (const std::size_t i : plan.groups[g].members)
        want += plan.lit[i].current_mA * entry_of(b, plan.lit[i]).weights[e];
      CHECK(currents[g][e] == Approx(want).margin(1e-12));
    }

  // The frame's problem in closed form: I^2 (w + (w / bw)^2 bw) and 2 |I| w per pulse.
  o.balance_width_us = 400;
  const FrameProblem fp = frame_problem(o, currents, plan);
  CHECK(fp.groups == plan.groups_per_primary);
  CHECK(fp.slot_us == 200 + 0 + 400 + 100);
  CHECK(fp.period_us[1] == 1e6 / 200);
  CHECK(fp.max_rms_mA == o.load_margin * o.limits.max_rms_current_mA);
  for (std::size_t p = 0; p < 3; ++p)
    for (std::size_t e = 0; e < 36; ++e) {
      double square = 0, charge = 0;
      for (std::size_t g = 0; g < plan.groups.size(); ++g)
        if (plan.groups[g].primary == static_cast<int>(p)) {
          const double i = currents[g][e];
          square += i * i * (200 + 0.25 * 400);
          charge += 2 * std::abs(i) * 200;
        }
      CHECK(fp.square[p][e] == Approx(square).margin(1e-12));
      CHECK(fp.charge[p][e] == Approx(charge).margin(1e-12));
    }
  o.balance_width_us = 200;

  // frame: the rates are the periods the frame gives, never above the requested.
  const Frame frame = frame_for(o, currents, plan);
  CHECK(plan.cycle_us == static_cast<double>(frame.cycle_us));
  CHECK(plan.slots == frame_slots(frame_problem(o, currents, plan), frame.cycle_us));
  double utilisation = 0;
  for (std::size_t p = 0; p < 3; ++p) {
    CHECK(plan.k[p] == frame.k[p]);
    if (plan.groups_per_primary[p] == 0) continue;
    CHECK(plan.rate_hz[p] == 1e6 / (static_cast<double>(frame.k[p]) * plan.cycle_us));
    CHECK(plan.rate_hz[p] <= o.rate_hz[p] * (1 + 1e-12));
    utilisation += plan.groups_per_primary[p] * slot_us(o) * o.rate_hz[p] / 1e6;
  }
  CHECK(plan.requested_utilisation == Approx(utilisation));
  CHECK(plan.lowered == (frame.score < 0.995));
  CHECK(plan.lowered == !plan.limited_by.empty());

  // mix: each group where the frame placed it, for the duration's whole periods.
  build_mix(b, o, currents, frame, plan);
  REQUIRE(plan.mix.patterns.size() == plan.groups.size());
  CHECK(plan.mix.gap_us == o.gap_us);
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    const RenderGroup& grp = plan.groups[g];
    const Stimulus& s = plan.mix.patterns[g];
    const auto p = static_cast<std::size_t>(grp.primary);
    CHECK(grp.slot < plan.slots);
    CHECK(grp.turn < plan.k[p]);
    CHECK(s.phase_us == grp.turn * plan.cycle_us + grp.slot * slot_us(o));
    CHECK(s.shape.frequency_hz == Approx(plan.rate_hz[p]));
    CHECK(s.count == static_cast<long>(std::floor(o.duration_s * plan.rate_hz[p] + 1e-9)));
    CHECK(s.currents_mA == currents[g]);
    CHECK(s.carried["primary"] == kPrimaries[p]);
    REQUIRE(s.carried["pixels"].size() == grp.members.size());
    for (std::size_t m = 0; m < grp.members.size(); ++m)
      CHECK(s.carried["pixels"][m] == plan.lit[grp.members[m]].pad);
  }
  CHECK_NOTHROW(check_mix(plan.mix, o.limits));
  CHECK(mix_figures(plan.mix).worst_slip_us == 0);
  // The steps in order are plan_render.
  CHECK(plan_to_json(plan) == plan_to_json(plan_render(b, profile, some_lit(b), o)));
}

TEST_CASE("plan steps: a duration's whole pulses, never stretched", "[render][plan]") {
  RenderOptions o;
  o.duration_s = 1.0;
  CHECK(pulse_count(o, 1, 5000) == 200);
  CHECK(pulse_count(o, 0, 1e6 / 30) == 30);
  o.duration_s = 0.0333;
  CHECK_THROWS_WITH(pulse_count(o, 0, 1e6 / 30),
                    Catch::Contains("--duration: the stimulus's 0.0333 s is shorter than one "
                                    "period of RA at its planned 30 Hz"));
  o.duration_s = 0.034;
  CHECK(pulse_count(o, 0, 1e6 / 30) == 1);
}
