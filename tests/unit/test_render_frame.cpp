// The frame scheduler (lib/render/frame.hpp): no two groups ever in one slot of one cycle
// (checked cycle by cycle over the hyperperiod, apart from the residue arithmetic the
// scheduler uses), rates never above the requested, the device's time and the
// electrodes' RMS current as closed-form bounds on the periods, slots shared by residue.
#include <catch2/catch.hpp>

#include <numeric>
#include <random>

#include "render/frame.hpp"

using namespace tp;

namespace {

// One primary's problem (the others without groups): `groups` groups asking period_us,
// slots of slot_us, no electrode loads.
FrameProblem one_primary(int groups, double period_us, double slot_us, std::size_t p = 1) {
  FrameProblem fp;
  fp.groups[p] = groups;
  for (double& t : fp.period_us) t = 1e6 / 30;
  fp.period_us[p] = period_us;
  fp.slot_us = slot_us;
  fp.loads = false;
  return fp;
}

// Every group placed once, in a slot of the cycle at a residue below its period, and no
// slot of any cycle in the hyperperiod (lcm of the periods, computed here) used twice.
void check_collision_free(const FrameProblem& fp, const Frame& f) {
  const long slots = frame_slots(fp, f.cycle_us);
  std::uint64_t h = 1;
  for (std::size_t p = 0; p < 3; ++p)
    if (fp.groups[p] > 0) h = std::lcm(h, static_cast<std::uint64_t>(f.k[p]));
  REQUIRE(h <= (1u << 20));  // the slip check's bound (slip_check_fits)
  std::vector<char> used(h * static_cast<std::size_t>(slots), 0);
  for (std::size_t p = 0; p < 3; ++p) {
    REQUIRE(f.place[p].size() == static_cast<std::size_t>(fp.groups[p]));
    for (const auto& [slot, r] : f.place[p]) {
      REQUIRE(slot >= 0);
      REQUIRE(slot < slots);
      REQUIRE(r >= 0);
      REQUIRE(r < f.k[p]);
      for (auto n = static_cast<std::uint64_t>(r); n < h; n += static_cast<std::uint64_t>(f.k[p]))
        CHECK(++used[n * static_cast<std::size_t>(slots) + static_cast<std::size_t>(slot)] == 1);
    }
  }
}

}  // namespace

TEST_CASE("frame: a primary that fits keeps its rate exactly, in the shortest cycle",
          "[render][scheduler]") {
  // SAI at 200 Hz, three groups of 500 us slots: one slot of a 500 us cycle, period 10
  // cycles, each group in its own turn.
  const FrameProblem fp = one_primary(3, 5000, 500);
  const Frame f = plan_frame(fp);
  REQUIRE(f.score == 1.0);
  CHECK(f.cycle_us == 500);
  CHECK(f.k[1] == 10);
  CHECK(f.k[0] == 0);
  CHECK(f.k[2] == 0);
  CHECK_FALSE(f.packed);
  check_collision_free(fp, f);
}

TEST_CASE("frame: the device's time bounds the period, within the 1 % steps of the search",
          "[render][scheduler]") {
  // 20 groups of 500 us asking 200 Hz need 10 ms a round: the period is at least that
  // (the rounded utilisation refuses exactly 10000 us), and the search's 1 % steps find one
  // within 1 % of it.
  const FrameProblem fp = one_primary(20, 5000, 500);
  const Frame f = plan_frame(fp);
  REQUIRE(f.score > 0);
  const double period = static_cast<double>(f.k[1] * f.cycle_us);
  CHECK(period > 10000);
  CHECK(period <= 10000 * 1.01 + 1);
  CHECK(f.score == Approx(5000 / period));
  CHECK(utilisation_fits(fp, f));
  check_collision_free(fp, f);
  // Exactly the device's time: 20 x 500 / 10000 is 1, but its rounding up in 2^-20 is not.
  Frame exact = f;
  exact.cycle_us = 10000;
  exact.k = {0, 1, 0};
  CHECK_FALSE(utilisation_fits(fp, exact));
  exact.cycle_us = 10001;
  CHECK(utilisation_fits(fp, exact));
}

TEST_CASE("frame: an electrode's RMS current bounds the period in closed form",
          "[render][scheduler]") {
  // One group, 1 mA on one electrode, 200 us phases: 400 mA^2 us a pulse.  RMS at most
  // 0.1 mA: a period of at least 400 / 0.01 = 40000 us (25 Hz of the 200 asked).
  FrameProblem fp = one_primary(1, 5000, 500);
  fp.loads = true;
  for (std::size_t p = 0; p < 3; ++p) {
    fp.square[p].assign(1, 0.0);
    fp.charge[p].assign(1, 0.0);
  }
  fp.square[1][0] = 400;
  fp.charge[1][0] = 400;
  fp.max_rms_mA = 0.1;
  fp.max_mean_mA = 1;
  const Frame f = plan_frame(fp);
  REQUIRE(f.score > 0);
  const double period = static_cast<double>(f.k[1] * f.cycle_us);
  CHECK(period >= 40000);
  CHECK(period <= 40000 * 1.01 + 1);
  CHECK(electrode_loads_fit(fp, f));
  // The mean current likewise: 400 mA us a pulse at most 0.02 mA, 20000 us; the RMS
  // still rules.
  fp.max_mean_mA = 0.02;
  CHECK(static_cast<double>(plan_frame(fp).k[1] * plan_frame(fp).cycle_us) >= 40000);
  fp.max_rms_mA = 1;
  const Frame mean = plan_frame(fp);
  const double mean_period = static_cast<double>(mean.k[1] * mean.cycle_us);
  CHECK(mean_period >= 20000);
  CHECK(mean_period <= 20000 * 1.01 + 1);
  // A bound no period up to 10 s keeps: no frame.
  fp.max_rms_mA = 1e-4;
  CHECK(plan_frame(fp).score < 0);
}

TEST_CASE("frame: groups of two primaries share a slot where their residues never meet",
          "[render][scheduler]") {
  // RA every 2 cycles, PC every 4, one slot: RA's group takes residue 0 (mod 2), so PC's
  // may take 1 and 3 (mod 4): two fit, a third does not.
  FrameProblem fp;
  fp.slot_us = 500;
  fp.groups = {1, 0, 2};
  Frame f;
  f.cycle_us = 500;
  f.k = {2, 0, 4};
  REQUIRE(pack_slots(fp, 1, f));
  CHECK(f.place[0] == std::vector<std::pair<int, long>>{{0, 0}});
  CHECK(f.place[2] == std::vector<std::pair<int, long>>{{0, 1}, {0, 3}});
  check_collision_free(fp, f);
  fp.groups = {1, 0, 3};
  CHECK_FALSE(pack_slots(fp, 1, f));
  // Periods 3 and 4 (gcd 1) meet in every slot they share: one slot each.
  fp.groups = {1, 0, 1};
  f.k = {3, 0, 4};
  CHECK_FALSE(pack_slots(fp, 1, f));
  REQUIRE(pack_slots(fp, 2, f));
  CHECK(f.place[0][0].first != f.place[2][0].first);
  // The work bound ends a search that would pass it.
  fp.groups = {1, 0, 1};
  fp.packing_work = kMaxPackingWork;
  CHECK_FALSE(pack_slots(fp, 2, f));
}

TEST_CASE("frame: random problems never collide, never pass the requested rates",
          "[render][scheduler]") {
  std::mt19937 rng(39);
  const double rates[] = {30, 50, 125, 200, 250, 333, 1000};
  int packed = 0, lowered = 0;
  for (int run = 0; run < 60; ++run) {
    FrameProblem fp;
    fp.loads = false;
    fp.slot_us = std::uniform_int_distribution<int>(300, 700)(rng);
    for (std::size_t p = 0; p < 3; ++p) {
      fp.groups[p] = std::uniform_int_distribution<int>(0, 6)(rng);
      fp.period_us[p] = 1e6 / rates[std::uniform_int_distribution<int>(0, 6)(rng)];
    }
    if (fp.groups[0] + fp.groups[1] + fp.groups[2] == 0) continue;
    const Frame f = plan_frame(fp);
    INFO("run " << run << ": cycle " << f.cycle_us << " us, k " << f.k[0] << " " << f.k[1] << " "
                << f.k[2]);
    REQUIRE(f.score > 0);
    CHECK(f.score <= 1.0);
    double share = 0, utilisation = 0;
    for (std::size_t p = 0; p < 3; ++p) {
      if (fp.groups[p] == 0) {
        CHECK(f.k[p] == 0);
        continue;
      }
      const double period = static_cast<double>(f.k[p] * f.cycle_us);
      CHECK(period >= fp.period_us[p] - 1e-9);  // the rate at most the requested
      share += static_cast<double>(fp.groups[p]) / static_cast<double>(f.k[p]);
      utilisation += fp.groups[p] * fp.slot_us / period;
    }
    CHECK(share <= static_cast<double>(frame_slots(fp, f.cycle_us)) + 1e-9);
    CHECK(utilisation <= 1.0);
    CHECK(frame_within_limits(fp, f));
    CHECK(hyperperiod_cycles(f.k, std::uint64_t{1} << 20) > 0);
    check_collision_free(fp, f);
    packed += f.packed;
    lowered += f.score < 0.995;
    // Deterministic.
    const Frame again = plan_frame(fp);
    CHECK(again.cycle_us == f.cycle_us);
    CHECK(again.place == f.place);
  }
  CHECK(packed > 0);   // some frames share slots between primaries
  CHECK(lowered > 0);  // and some ask more than the device's time
}

TEST_CASE("frame: the hyperperiod is the lcm of the periods, frames compare by score",
          "[render][scheduler]") {
  CHECK(hyperperiod_cycles({4, 6, 0}, 100) == 12);
  CHECK(hyperperiod_cycles({4, 6, 10}, 100) == 60);
  CHECK(hyperperiod_cycles({0, 0, 0}, 100) == 1);
  CHECK(hyperperiod_cycles({7, 0, 5}, 34) == 0);  // 35 above the cap
  CHECK(hyperperiod_cycles({1000003, 999983, 0}, std::uint64_t{1} << 20) == 0);
  Frame a, b;
  a.score = 0.9;
  b.score = 0.8;
  CHECK(better_frame(a, b));
  CHECK_FALSE(better_frame(b, a));
  b.score = 0.9;
  a.sum = 2.0;
  b.sum = 2.5;
  CHECK(better_frame(b, a));
  b.sum = 2.0;
  a.cycle_us = 600;
  b.cycle_us = 500;
  CHECK(better_frame(b, a));
  // A cycle shorter than a slot holds none; one that cannot hold the groups' shares is
  // refused; one within it sets each primary's least period at least the requested.
  const FrameProblem fp = one_primary(4, 5000, 500);
  Frame f;
  CHECK_FALSE(frame_at_cycle(fp, 499, f));
  REQUIRE(frame_at_cycle(fp, 700, f));
  CHECK(f.k[1] == 8);  // 8 x 700 = 5600 >= 5000 > 7 x 700
  CHECK(f.score == Approx(5000.0 / 5600));
  CHECK(frame_slots(fp, 700) == 1);
  CHECK_FALSE(frame_at_cycle(one_primary(12, 5000, 500), 700, f));  // 12 / 8 of one slot
}
