// The gamut's colours (lib/render/recruitment.hpp): a mode's recruitment read at a current
// (a count over sorted thresholds), the bank's JSON both ways, the image mapped into the
// gamut pixel by pixel (inside: back to itself; outside: as near as nearest_in_gamut, and
// counted), and a bank's recruitment sampled by the fibre model (its reference is the
// profile without calibration's threshold).
#include <catch2/catch.hpp>

#include <functional>
#include <limits>
#include <utility>

#include "core/error.hpp"
#include "render/recruitment.hpp"
#include "render/request.hpp"
#include "render_support.hpp"

using namespace tp;
using namespace tp::render_test;

namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// Three modes, four afferents a class each, references 1 mA: at 2 mA (a profile's comfort
// at twice threshold) RA recruits (3/4, 1/4, 0), SAI (0, 1, 1/4), PC (1/4, 1/2, 1).
BankRecruitment three_modes() {
  BankRecruitment r;
  r.per_class = 4;
  r.fibre_model = "mrg";
  r.max_mA = 10;
  r.pulse = pulse_spec_to_json(PulseSpec{});
  const std::array<std::array<std::vector<double>, 3>, 3> t = {{
      {{{0.5, 1.0, 1.5, 3.0}, {1.9, 2.5, 4.0, kNone}, {2.5, 3.0, 5.0, kNone}}},
      {{{2.5, 3.0, 5.0, kNone}, {0.2, 0.4, 1.0, 2.0}, {1.0, 3.0, 4.0, kNone}}},
      {{{1.5, 2.5, 3.0, kNone}, {1.0, 2.0, 3.0, 4.0}, {0.5, 1.0, 1.0, 1.5}}},
  }};
  for (std::size_t m = 0; m < 3; ++m) {
    ModeRecruitment q;
    q.pad = static_cast<long>(m);
    q.reference_mA = 1.0;
    q.thresholds_mA = t[m];
    r.mode[m] = q;
  }
  return r;
}

Profile profile_at(double threshold_mA, double comfort_mA) {
  Profile p;
  PrimaryRange range;
  range.threshold_mA = threshold_mA;
  range.comfort_mA = comfort_mA;
  for (auto& r : p.primary) r = range;
  return p;
}

}  // namespace

TEST_CASE("recruitment: fractions at a current, JSON both ways, refusals",
          "[render][gamut]") {
  const BankRecruitment r = three_modes();
  const ModeRecruitment& ra = *r.mode[0];
  CHECK(ra.fractions(0.0) == std::array<double, 3>{0, 0, 0});
  CHECK(ra.fractions(1.0) == std::array<double, 3>{0.5, 0, 0});  // threshold <= current
  CHECK(ra.fractions(2.0) == std::array<double, 3>{0.75, 0.25, 0});
  CHECK(ra.fractions(1e9) == std::array<double, 3>{1, 0.75, 0.75});  // none: never
  const BankRecruitment back = recruitment_from_json(
      parse_json_strict(dump_json(recruitment_to_json(r)), "bank"), 3, "bank: recruitment");
  CHECK(back.per_class == 4);
  for (std::size_t m = 0; m < 3; ++m) {
    REQUIRE(back.mode[m]);
    CHECK(back.mode[m]->pad == r.mode[m]->pad);
    CHECK(back.mode[m]->thresholds_mA == r.mode[m]->thresholds_mA);
  }
  Json j = recruitment_to_json(r);
  j["modes"]["SAI"]["thresholds_mA"]["PC"] = Json::array({2.0, 1.0, 3.0, 4.0});
  CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"),
                    "bank: recruitment.modes.SAI.thresholds_mA.PC: not ascending");
  j = recruitment_to_json(r);
  j["modes"]["PC"]["pad"] = 3;
  CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"),
                    "bank: recruitment.modes.PC.pad: not a pad of the bank");
  j = recruitment_to_json(r);
  j["modes"]["RA"]["thresholds_mA"]["SAI"] = Json::array({-1.0, 1.0, 2.0, 3.0});
  CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"),
                    "bank: recruitment.modes.RA.thresholds_mA.SAI: a threshold not above 0");
  // As strict as the profile: every key known, each list the population long, every number
  // in its range, nothing dropped quietly.
  const std::pair<std::function<void(Json&)>, std::string> bad[] = {
      {[](Json& b) { b["colour"] = 1; }, "bank: recruitment: unknown key 'colour'"},
      {[](Json& b) { b["modes"]["RB"] = Json::object(); },
       "bank: recruitment.modes: unknown key 'RB'"},
      {[](Json& b) { b["modes"]["RA"] = nullptr; },
       "bank: recruitment.modes.RA: not an object (leave a mode out when it has none)"},
      {[](Json& b) { b["modes"]["PC"]["offset_mA"] = 0.1; },
       "bank: recruitment.modes.PC: unknown key 'offset_mA'"},
      {[](Json& b) { b["modes"]["PC"]["thresholds_mA"]["SA"] = Json::array(); },
       "bank: recruitment.modes.PC.thresholds_mA: unknown key 'SA'"},
      {[](Json& b) { b["modes"]["SAI"]["thresholds_mA"]["RA"].erase(0); },
       "bank: recruitment.modes.SAI.thresholds_mA.RA: expected 4 thresholds (the population), "
       "ascending, null for none"},
      {[](Json& b) { b["modes"]["SAI"]["thresholds_mA"]["RA"][2] = 11.0; },
       "bank: recruitment.modes.SAI.thresholds_mA.RA: a threshold above max_mA (10; null for "
       "none)"},
      {[](Json& b) { b["modes"]["RA"]["reference_mA"] = 12.0; },
       "bank: recruitment.modes.RA.reference_mA: outside (0, max_mA = 10]"},
      {[](Json& b) { b["max_mA"] = 0; }, "bank: recruitment.max_mA: outside (0, 1000]"},
      {[](Json& b) {
         b.erase("max_mA");
         b["modes"]["SAI"]["thresholds_mA"]["RA"][2] = 10.5;
       },
       "bank: recruitment.modes.SAI.thresholds_mA.RA: a threshold above max_mA (10; null for "
       "none)"},
      {[](Json& b) { b["seed"] = -1; }, "bank: recruitment.seed: not a whole number from 0"},
      {[](Json& b) { b["seed"] = "1"; }, "bank: recruitment.seed: not a whole number from 0"},
      {[](Json& b) { b["population"] = 1001; },
       "bank: recruitment.population: not a count from 1 to 1000"},
      {[](Json& b) { b["pulse"] = 200; },
       "bank: recruitment.pulse: not a pulse object (the recruitment's: width_us, ... or "
       "phases)"},
      {[](Json& b) { b.erase("pulse"); },
       "bank: recruitment.pulse: not a pulse object (the recruitment's: width_us, ... or "
       "phases)"},
      {[](Json& b) { b["region"] = 5; }, "bank: recruitment.region: not a string"},
      {[](Json& b) { b["fibre_model"] = 1; }, "bank: recruitment.fibre_model: not a string"},
  };
  for (const auto& [spoil, message] : bad) {
    j = recruitment_to_json(r);
    spoil(j);
    CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"), message);
  }
}

TEST_CASE("the gamut: an image mapped pixel by pixel, inside back to itself, outside counted",
          "[render][gamut]") {
  const BankRecruitment r = three_modes();
  const Profile p = profile_at(0.4, 0.8);
  const GamutModes c = gamut_modes(r, p, 0);
  CHECK(c.full[0] == std::array<double, 3>{0.75, 0.25, 0});
  CHECK(c.full[1] == std::array<double, 3>{0, 1, 0.25});
  CHECK(c.full[2] == std::array<double, 3>{0.25, 0.5, 1});
  // At the person's threshold, each mode's fractions at its reference.
  CHECK(c.onset[0] == std::array<double, 3>{0.5, 0, 0});
  CHECK(c.onset[1] == std::array<double, 3>{0, 0.75, 0.25});
  CHECK(c.onset[2] == std::array<double, 3>{0, 0.25, 0.75});
  PixelBank bank = two_pads();  // 2 x 1 pads, every pattern feasible; two more for the image
  bank.columns = 2;
  bank.rows = 2;
  bank.entry.resize(4, bank.entry[0]);
  bank.doc.setup.array = ElectrodeArray::grid_of(2, 2, 2.0, 2.0, 1.0, 1.0);
  bank.recruitment = r;
  PadIntensities im;
  im.columns = 2;
  im.rows = 2;
  im.value.assign(4, {0, 0, 0});
  // Pad 0: 0.5 RA + 0.25 SAI mode, inside; pad 1: pure RA afferents, outside; pad 3: dark.
  // RA's mode at 0.5 (halfway from its onset colour to its full one) and SAI's at 0.25.
  const std::array<double, 3> inside = {0.625, 0.125 + 0.8125, 0.25};
  im.value[0] = inside;
  im.value[1] = {1, 0, 0};
  im.value[2] = {0, 0, 0.5};
  const GamutAnswer out = nearest_in_gamut(c, {1, 0, 0});
  const GamutAnswer blue = nearest_in_gamut(c, {0, 0, 0.5});
  const GamutReport g = map_to_gamut(bank, p, im);
  CHECK(im.value[0][0] == Approx(0.5).margin(1e-6));
  CHECK(im.value[0][1] == Approx(0.25).margin(1e-6));
  CHECK(im.value[0][2] == 0);  // off, not on at its threshold
  CHECK(g.error[0] < 1e-6);
  for (std::size_t m = 0; m < 3; ++m) {
    CHECK(im.value[1][m] == Approx(out.intensity[m]).margin(1e-12));
    CHECK(im.value[2][m] == Approx(blue.intensity[m]).margin(1e-12));
  }
  CHECK(im.value[3] == std::array<double, 3>{0, 0, 0});
  CHECK(g.requested == 3);
  CHECK(g.outside == 2);  // pure RA afferents, and PC without the SAI the PC mode brings
  CHECK(g.error[1] == Approx(out.error));
  CHECK(g.max_error == Approx(std::max(out.error, blue.error)));
  CHECK(g.mean_error == Approx((g.error[0] + out.error + blue.error) / 3));
  CHECK(gamut_summary(g).rfind("gamut: 2 of 3 pixels asked for outside the modes' gamut", 0) == 0);
  const Json j = gamut_to_json(g);
  CHECK(j["outside"] == 2);
  CHECK(j["error"].size() == 4);
  CHECK(j["onset_colours"]["SAI"] == Json::array({0, 0.75, 0.25}));
  CHECK(!j.contains("frames"));
  // A sequence's frames, tallied: counts summed, the most per pad, the mean over all.
  GamutReport tally;
  PadIntensities first = im, second = im;
  first.value = {inside, {1, 0, 0}, {0, 0, 0.5}, {0, 0, 0}};
  second.value = {{0, 0, 0}, {0, 0, 0.5}, {0, 0, 0}, {0, 0, 0}};
  map_frame(bank, p, first, tally);
  map_frame(bank, p, second, tally);
  CHECK(first.value == im.value);  // mapped as the still was
  CHECK(tally.frames == 2);
  CHECK(tally.requested == 4);
  CHECK(tally.outside == 3);
  CHECK(tally.error[1] == Approx(std::max(out.error, blue.error)));
  CHECK(tally.error[2] == Approx(blue.error));
  CHECK(tally.mean_error == Approx((g.error[0] + out.error + 2 * blue.error) / 4));
  CHECK(gamut_summary(tally).find(") over 2 frames") != std::string::npos);
  CHECK(gamut_to_json(tally)["frames"] == 2);
  // A person's profile reads the colour at the person's multiple of threshold: comfort at
  // 1.5 x threshold reads the thresholds at 1.5 x the reference.
  Profile narrow = profile_at(1.0, 1.5);
  CHECK(gamut_modes(r, narrow, 0).full[0] == r.mode[0]->fractions(1.5));
  CHECK(gamut_modes(r, narrow, 0).onset[0] == r.mode[0]->fractions(1.0));
  // calibrate's colours (add_colours) are those, carried by the profile, and read first.
  Profile person = narrow;
  add_colours(person, r);
  REQUIRE(person.primary[0]->colour);
  CHECK(*person.primary[0]->colour == r.mode[0]->fractions(1.5));
  person.primary[1]->colour = std::array<double, 3>{0.1, 0.2, 0.3};
  CHECK(gamut_modes(r, person, 0).full[1] == std::array<double, 3>{0.1, 0.2, 0.3});
  CHECK(profile_to_json(person)["primaries"]["SAI"]["colour"] == Json::array({0.1, 0.2, 0.3}));
  // A mode the profile has no range for is no colour.
  narrow.primary[2].reset();
  CHECK(gamut_modes(r, narrow, 0).full[2] == std::array<double, 3>{0, 0, 0});
  CHECK(gamut_modes(r, narrow, 0).onset[2] == std::array<double, 3>{0, 0, 0});
}

TEST_CASE("recruitment of a bank: the references are the model profile's thresholds",
          "[render][gamut][recruitment]") {
  const PixelBank& b = bank6();
  RecruitmentOptions o;
  o.per_class = 2;
  o.threads = 2;
  const BankRecruitment r = bank_recruitment(b, o);
  ModelProfileOptions mo;
  const ModelProfile mp = model_profile(b, mo);
  for (std::size_t m = 0; m < 3; ++m) {
    REQUIRE(r.mode[m]);
    CHECK(r.mode[m]->pad == mp.pixel[m]);
    CHECK(r.mode[m]->reference_mA == Approx(mp.profile.primary[m]->threshold_mA).epsilon(0.01));
    for (const auto& t : r.mode[m]->thresholds_mA) {
      CHECK(t.size() == 2);
      CHECK(std::is_sorted(t.begin(), t.end()));
    }
  }
  CHECK(dump_json(recruitment_to_json(bank_recruitment(b, o))) == dump_json(recruitment_to_json(r)));
  // A mode with no feasible pattern anywhere is left out, and said, not the whole run lost.
  PixelBank no_pc = b;
  for (auto& pixel : no_pc.entry) {
    pixel[2] = BankEntry{};
    pixel[2].present = true;
    pixel[2].reason = "no pattern";
  }
  std::vector<std::string> omitted;
  const BankRecruitment without = bank_recruitment(no_pc, o, &omitted);
  CHECK(!without.mode[2]);
  REQUIRE(without.mode[1]);
  CHECK(without.mode[1]->thresholds_mA == r.mode[1]->thresholds_mA);
  REQUIRE(omitted.size() == 1);
  CHECK(omitted[0] ==
        "recruitment: no PC mode sampled: the bank has no feasible pattern of it; "
        "render-tactile never drives it");
  o.per_class = 1001;
  CHECK_THROWS_WITH(bank_recruitment(b, o), "--population: 1001 outside [1, 1000]");

  // render-tactile with the bank's recruitment maps a still and reports it; without, says so.
  PixelBank with = b;
  with.recruitment = r;
  RenderRequest q;
  q.profile = profile_from_json(profile_json(), 2.0, 36);
  q.options.threads = 2;
  q.image = dark6();
  q.image.value[14] = {0, 1.0, 0};
  const RenderResult mapped = run_render(q, with);
  REQUIRE(mapped.gamut);
  CHECK(mapped.gamut->requested == 1);
  CHECK(mapped.document["gamut"]["requested"] == 1);
  CHECK(mapped.gamut_note.empty());
  const RenderResult plain = run_render(q, b);
  CHECK(!plain.gamut);
  CHECK(!plain.document.contains("gamut"));
  CHECK(plain.gamut_note.find("the bank carries no recruitment") != std::string::npos);
  // Another pulse than the recruitment's is said; a mapping that lights nothing says why.
  RenderRequest narrow = q;
  narrow.options.width_us = 100;
  narrow.options.balance_width_us = 100;
  CHECK(run_render(narrow, with).gamut_note ==
        "the bank's recruitment was sampled with a 200 us biphasic pulse, not this render's "
        "100 us biphasic pulse: the gamut's colours are that pulse's");
  // The recruitment's pulse compared by value (the same biphasic pulse given as its phases
  // is the same pulse), and read as strictly as any pulse.
  PixelBank same = with;
  same.recruitment->pulse = pulse_spec_to_json(PulseSpec{200, 0, 200, false, {{200, 1}, {200, -1}}});
  REQUIRE(same.recruitment->pulse.contains("phases"));
  CHECK(run_render(q, same).gamut_note.empty());
  same.recruitment->pulse = Json{{"width_us", "x"}};
  CHECK_THROWS_WITH(run_render(q, same), Catch::Matchers::StartsWith("bank: recruitment.pulse"));
  PixelBank none = with;
  none.recruitment->mode = {};
  q.image_name = "dot.png";
  CHECK_THROWS_WITH(run_render(q, none),
                    "dot.png: 1 pixel asks for colour, and the nearest the modes come to each is "
                    "nothing (RA: the bank's recruitment has no RA mode; SAI: the bank's "
                    "recruitment has no SAI mode; PC: the bank's recruitment has no PC mode)");
}
