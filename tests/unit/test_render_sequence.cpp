// Rendering (lib/render/render.hpp): the plan's groups
// (no shared pad, crosstalk within its bound on the field evaluated again), its frame (no
// pulse ever deferred, rates never above the requested, the device's own checks pass),
// every lit pattern delivered, the same plan for the same input.
#include <catch2/catch.hpp>

#include <set>

#include "core/error.hpp"
#include "psych/profile.hpp"
#include "render/render.hpp"
#include "render_support.hpp"

using namespace tp;
using namespace tp::render_test;

TEST_CASE("a plan: groups share no pad, keep their crosstalk bound, and never collide",
          "[render]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  std::mt19937 rng(23);
  int multi = 0;
  for (int run = 0; run < 12; ++run) {
    RenderOptions o;
    o.crosstalk = run % 3 == 0 ? 0.05 : 0.2;
    const PadIntensities im = random_image(b, rng, run % 2 ? 0.9 : 0.3);
    const RenderPlan plan = plan_render(b, profile, im, o);
    INFO("run " << run << ": " << plan.lit.size() << " lit in " << plan.groups.size() << " groups");
    // Every lit pattern, once.
    std::vector<int> seen(plan.lit.size(), 0);
    for (const RenderGroup& g : plan.groups)
      for (const std::size_t i : g.members) {
        ++seen[i];
        CHECK(plan.lit[i].primary == g.primary);
      }
    for (const int s : seen) CHECK(s == 1);
    std::size_t lit = 0;
    for (const auto& v : im.value)
      for (const double x : v) lit += x > 0;
    CHECK(plan.lit.size() == lit);
    // Members: disjoint pads; crosstalk both ways within the bound (the field built anew).
    for (std::size_t g = 0; g < plan.groups.size(); ++g) {
      const auto& m = plan.groups[g].members;
      multi += m.size() > 1;
      std::vector<int> pad_users(b.pads(), 0);
      for (const std::size_t i : m) {
        const auto& w = b.entry[static_cast<std::size_t>(plan.lit[i].pad)]
                               [static_cast<std::size_t>(plan.lit[i].primary)]
                                   .weights;
        for (std::size_t e = 0; e < w.size(); ++e) pad_users[e] += w[e] != 0;
      }
      for (const int u : pad_users) CHECK(u <= 1);
      for (const std::size_t i : m)
        for (const std::size_t j : m)
          if (i != j)
            CHECK(crosstalk_oracle(b, plan.lit[i].primary, plan.lit[i].pad, plan.lit[i].current_mA,
                                   plan.lit[j].pad, plan.lit[j].current_mA) <= o.crosstalk);
      // The group's currents: its members' currents times their weights.
      const Stimulus& s = plan.mix.patterns[g];
      for (std::size_t e = 0; e < b.pads(); ++e) {
        double want = 0;
        for (const std::size_t i : m)
          want += plan.lit[i].current_mA * b.entry[static_cast<std::size_t>(plan.lit[i].pad)]
                                                  [static_cast<std::size_t>(plan.lit[i].primary)]
                                                      .weights[e];
        CHECK(s.currents_mA[e] == Approx(want).margin(1e-12));
      }
    }
    // The frame: rates at most the requested; the device's checks pass and find no slip.
    for (std::size_t p = 0; p < 3; ++p) CHECK(plan.rate_hz[p] <= o.rate_hz[p] * (1 + 1e-12));
    CHECK_NOTHROW(check_mix(plan.mix, o.limits));
    const MixFigures f = mix_figures(plan.mix);
    CHECK(f.worst_slip_us == 0);
    CHECK(f.utilisation <= 1.0);
    // The same input, the same plan.
    CHECK(plan_to_json(plan_render(b, profile, im, o)) == plan_to_json(plan));
  }
  CHECK(multi > 0);  // some patterns did fire together
}

TEST_CASE("a plan: one pixel at its requested rate, a full image lowered, nothing dropped",
          "[render]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  PadIntensities im = dark6();
  im.value[14][1] = 128.0 / 255;
  RenderOptions o;
  const RenderPlan one = plan_render(b, profile, im, o);
  REQUIRE(one.groups.size() == 1);
  CHECK(one.rate_hz[1] == 200.0);
  CHECK_FALSE(one.lowered);
  CHECK(one.mix.patterns[0].currents_mA[14] == Approx(0.3 + 0.6 * 128 / 255));
  // Everything lit that has a pattern.
  for (std::size_t pad = 0; pad < 36; ++pad)
    for (std::size_t p = 0; p < 3; ++p) im.value[pad][p] = b.entry[pad][p].feasible ? 1.0 : 0.0;
  const RenderPlan all = plan_render(b, profile, im, o);
  CHECK(all.lowered);
  CHECK_FALSE(all.limited_by.empty());
  std::size_t members = 0;
  for (const RenderGroup& g : all.groups) members += g.members.size();
  CHECK(members == all.lit.size());
  CHECK_NOTHROW(check_mix(all.mix, o.limits));
  // A lit pixel whose primary has no pattern is refused, naming it.
  for (std::size_t pad = 0; pad < 36; ++pad)
    for (std::size_t p = 0; p < 3; ++p)
      if (!b.entry[pad][p].feasible) {
        im.value[pad][p] = 1.0;
        CHECK_THROWS_WITH(plan_render(b, profile, im, o), Catch::Contains("could not find"));
        return;
      }
}

TEST_CASE("a sequence: its pixels, its frames' amplitudes, its start", "[render]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  std::vector<PadIntensities> frames(2, dark6());
  frames[0].value[14] = {0, 1.0, 0};
  frames[1].value[14] = {0, 0.5, 0};
  frames[1].value[21] = {1.0 / 255, 0, 0};
  RenderOptions o;
  const RenderPlan plan = plan_sequence(b, profile, frames, o);
  REQUIRE(plan.groups.size() == 2);  // pad 14's SAI, pad 21's RA: nothing else
  for (const RenderGroup& g : plan.groups) CHECK(g.members.size() == 1);
  // Each at its comfort current; it starts from the first frame.
  CHECK(plan.mix.start_amplitudes_mA == std::vector<double>{0.0, 0.9});  // RA first
  // Through JSON, as render-tactile --frames and stimctl read it: the amplitudes checked.
  const Json doc = parse_json_strict(dump_json(sequence_to_json(plan, b)), "sequence");
  const Sequence seq = sequence_from_json(doc, b, profile, "--frames s.json");
  CHECK(seq.mix.start_amplitudes_mA == plan.mix.start_amplitudes_mA);
  const std::vector<double> a = frame_amplitudes(seq, profile, frames[1], "frame 2");
  CHECK(a[0] == Approx(0.4 + 0.6 / 255));
  CHECK(a[1] == Approx(0.6));
  CHECK(frame_amplitudes(seq, profile, frames[0], "frame 1") == plan.mix.start_amplitudes_mA);
  Mix loud = plan.mix;
  loud.start_amplitudes_mA[1] = 0.95;
  CHECK_THROWS_WITH(check_mix(loud, o.limits), Catch::Contains("start_amplitudes_mA"));
  // A frame lighting what the sequence does not hold.
  PadIntensities other = frames[1];
  other.value[0] = {0, 0, 1};
  CHECK_THROWS_WITH(frame_amplitudes(seq, profile, other, "frame 3"),
                    Catch::Contains("frame 3: pixel (0, 0) lights PC"));
  // No frames: every pattern the bank has, each alone.
  const RenderPlan all = plan_sequence(b, profile, std::vector<PadIntensities>{}, o);
  std::size_t feasible = 0;
  for (std::size_t pad = 0; pad < 36; ++pad)
    for (std::size_t p = 0; p < 3; ++p) feasible += b.entry[pad][p].feasible;
  CHECK(all.groups.size() == feasible);
  CHECK_NOTHROW(check_mix(all.mix, o.limits));
  CHECK(mix_figures(all.mix).worst_slip_us == 0);
}

TEST_CASE("a sequence: pixels its frames light alike fire as one pattern, at their rate",
          "[render]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  // A column of SAI moving across: column c's six pixels lit alike in every frame.
  std::vector<PadIntensities> frames(6, dark6());
  for (std::size_t f = 0; f < 6; ++f)
    for (std::size_t r = 0; r < 6; ++r) frames[f].value[6 * r + f] = {0, f % 2 ? 0.5 : 1.0, 0};
  RenderOptions o;
  const RenderPlan plan = plan_sequence(b, profile, frames, o);
  // Rows three apart share no pad: each column in at most three patterns, never one of
  // two columns; no crosstalk above the bound.
  CHECK(plan.groups.size() < 36);
  std::set<std::size_t> columns_seen;
  for (const RenderGroup& g : plan.groups) {
    std::set<long> columns;
    for (const std::size_t i : g.members) columns.insert(plan.lit[i].pad % 6);
    CHECK(columns.size() == 1);
  }
  CHECK(plan.worst_crosstalk <= o.crosstalk);
  const RenderPlan alone = plan_sequence(b, profile, std::vector<PadIntensities>{}, o);
  CHECK(plan.rate_hz[1] > 1.5 * alone.rate_hz[1]);
  CHECK_NOTHROW(check_mix(plan.mix, o.limits));
  // Each frame's amplitudes set every member's current: the pattern's currents scaled.
  const Sequence seq = sequence_from_json(sequence_to_json(plan, b), b, profile, "s");
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const std::vector<double> a = frame_amplitudes(seq, profile, frames[f], "frame");
    for (std::size_t g = 0; g < plan.groups.size(); ++g)
      for (const std::size_t i : plan.groups[g].members) {
        const long pad = plan.lit[i].pad;
        const double want =
            profile.current_mA(1, pad, frames[f].value[static_cast<std::size_t>(pad)][1]);
        const Stimulus& s = plan.mix.patterns[g];
        CHECK(a[g] / s.amplitude_mA * s.currents_mA[static_cast<std::size_t>(pad)] ==
              Approx(want).margin(1e-12));
      }
  }
  // A frame lighting two pixels of one pattern unlike is refused, naming them.
  std::size_t g = 0;
  while (plan.groups[g].members.size() < 2) ++g;
  PadIntensities unlike = frames[0];
  const long p0 = plan.lit[plan.groups[g].members[0]].pad;
  const long p1 = plan.lit[plan.groups[g].members[1]].pad;
  unlike.value[static_cast<std::size_t>(p1)][1] = 0.25;
  CHECK_THROWS_WITH(
      frame_amplitudes(seq, profile, unlike, "frame 9"),
      Catch::Contains("frame 9: pixel (" + std::to_string(p0 % 6) + ", " + std::to_string(p0 / 6) +
                      ") and pixel (" + std::to_string(p1 % 6) + ", " + std::to_string(p1 / 6) +
                      ") fire as one SAI pattern"));
  // Another range for one of them (a per-pixel profile): they may not share a pattern.
  Json j = profile_json();
  j["pixels"] = Json::array({{{"pad", p1}, {"SAI", {{"threshold_mA", 0.2}, {"comfort_mA", 0.9}}}}});
  const Profile per_pixel = profile_from_json(j, 2.0, 36);
  CHECK_THROWS_WITH(sequence_from_json(sequence_to_json(plan, b), b, per_pixel, "s"),
                    Catch::Contains("another range than pixel"));
  const RenderPlan split = plan_sequence(b, per_pixel, frames, o);
  for (const RenderGroup& h : split.groups)
    for (const std::size_t i : h.members)
      if (split.lit[i].pad == p1) CHECK(h.members.size() == 1);
}

TEST_CASE("a sequence's stimulus fits only its array and a profile it can hold", "[render]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  std::vector<PadIntensities> frames(1, dark6());
  frames[0].value[14] = {0, 128.0 / 255, 0};
  const RenderPlan plan = plan_sequence(b, profile, frames, RenderOptions{});
  const Json doc = sequence_to_json(plan, b);
  // Another grid of as many pads (9 x 4), another pitch: refused, naming both.
  PixelBank wide = b;
  wide.doc.setup.array = ElectrodeArray::grid_of(9, 4, 2.0, 2.0, 1.0, 1.0);
  wide.columns = 9;
  wide.rows = 4;
  CHECK_THROWS_WITH(sequence_from_json(doc, wide, profile, "--frames s.json"),
                    Catch::Contains("--frames s.json: a sequence made for 6 x 6 pads (columns x "
                                    "rows), not the bank's 9 x 4: give the bank it was made with"));
  PixelBank far = b;
  far.doc.setup.array = ElectrodeArray::grid_of(6, 6, 2.5, 2.5, 1.0, 1.0);
  CHECK_THROWS_WITH(sequence_from_json(doc, far, profile, "s"),
                    Catch::Contains("\"pitch_mm\":2.5"));
  Json bare = doc;
  bare.erase("array");
  CHECK_THROWS_WITH(sequence_from_json(bare, b, profile, "s"), Catch::Contains("records no array"));
  // A profile whose comfort is above what a pattern was made for: refused, not clipped.
  const Profile strong = profile_from_json(profile_json(0.3, 1.5), 2.0, 36);
  CHECK_THROWS_WITH(sequence_from_json(doc, b, strong, "s"),
                    Catch::Contains("pixel (2, 2)'s SAI up to 1.5 mA, above the 0.9 mA"));
  // A weaker one is fine: 128/255 under it, not clipped.
  const Profile weak = profile_from_json(profile_json(0.2, 0.6), 2.0, 36);
  const Sequence seq = sequence_from_json(doc, b, weak, "s");
  CHECK(frame_amplitudes(seq, weak, frames[0], "f")[0] == Approx(0.2 + 0.4 * 128 / 255));
}

TEST_CASE("a duration that holds no pulse of a pattern is refused, not stretched", "[render]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  PadIntensities im = dark6();
  im.value[14] = {1.0, 0, 0};  // RA at 30 Hz: 33 ms a pulse
  RenderOptions o;
  o.duration_s = 1e-9;
  CHECK_THROWS_WITH(plan_render(b, profile, im, o),
                    Catch::Contains("--duration: the stimulus's 1e-09 s is shorter than one period "
                                    "of RA"));
  o.duration_s = 0.034;
  CHECK(plan_render(b, profile, im, o).mix.patterns[0].count == 1);
  o.duration_s = 1e300;
  CHECK_THROWS_WITH(plan_render(b, profile, im, o), Catch::Contains("outside (0, 3600] s"));
  CHECK_THROWS_WITH(sequence_duration_s(108000, 30, StimulusLimits{}),
                    Catch::Contains("108000 frames at 30 fps"));
  CHECK(sequence_duration_s(59, 30, StimulusLimits{}) == 2.0);
}

TEST_CASE("render's messages: rates once each, ranges' keys known, counts in the singular",
          "[render]") {
  std::array<double, 3> r = {30, 200, 250};
  parse_rates("RA:10,PC:20", r);
  CHECK(r == std::array<double, 3>{10, 200, 20});
  CHECK_THROWS_WITH(parse_rates("RA:10,RA:20", r), Catch::Contains("--rates: RA given twice"));
  Json j = profile_json();
  j["primaries"]["SAI"]["comfort_ma"] = 0.8;
  CHECK_THROWS_WITH(profile_from_json(j, 2.0, 36),
                    Catch::Contains("profile: primaries.SAI: unknown key 'comfort_ma'"));
  Json px = profile_json();
  px["pixels"] = Json::array(
      {{{"pad", 3}, {"SAI", {{"threshold_mA", 0.1}, {"comfort_mA", 0.2}, {"note", "x"}}}}});
  CHECK_THROWS_WITH(profile_from_json(px, 2.0, 36),
                    Catch::Contains("pixels[0].SAI: unknown key 'note'"));
  CHECK(count_text(1, "slot") == "1 slot");
  CHECK(count_text(0, "slot") == "0 slots");
  const PixelBank& b = bank6();
  PadIntensities im = dark6();
  im.value[14][1] = 1.0;
  const RenderPlan one = plan_render(b, profile_from_json(profile_json(), 2.0, 36), im, {});
  CHECK_THAT(plan_summary(one), Catch::StartsWith("1 lit pattern in 1 group, cycle"));
  CHECK_THAT(plan_summary(one), Catch::EndsWith("(200 requested; 1 group)"));
  CHECK_THAT(plan_summary(one), Catch::Contains("cycle 500 us of 1 slot,"));  // k = 10 cycles
}

TEST_CASE("a plan: primaries share slots where their residues allow, and never collide",
          "[render]") {
  // A few pixels of each primary: each primary's own slots would lower SAI to 167 Hz
  // (the README's face); shared slots keep every rate within 5 % of its request.
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  PadIntensities im = dark6();
  for (const std::size_t pad : {7, 8, 9}) im.value[pad][0] = 1.0;
  for (const std::size_t pad : {14, 15, 16}) im.value[pad][1] = 1.0;
  for (const std::size_t pad : {26, 27}) im.value[pad][2] = 1.0;
  const RenderPlan plan = plan_render(b, profile, im, RenderOptions{});
  INFO(plan_to_json(plan).dump());
  for (std::size_t p = 0; p < 3; ++p) {
    CHECK(plan.rate_hz[p] <= plan.requested_hz[p]);
    CHECK(plan.rate_hz[p] >= 0.95 * plan.requested_hz[p]);
  }
  bool shared = false;  // some slot holds two primaries
  for (const RenderGroup& g : plan.groups)
    for (const RenderGroup& h : plan.groups)
      shared = shared || (g.slot == h.slot && g.primary != h.primary);
  CHECK(shared);
  const MixFigures f = mix_figures(plan.mix);
  CHECK(f.worst_slip_us == 0);
  CHECK_NOTHROW(check_mix(plan.mix, StimulusLimits{}));
}
