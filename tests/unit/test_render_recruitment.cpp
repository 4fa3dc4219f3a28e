// The gamut's colours (lib/render/recruitment.hpp): a mode's recruitment read at a current
// (a count over sorted thresholds), the bank's JSON both ways, the image mapped into the
// gamut pixel by pixel (inside: back to itself; outside: as near as nearest_in_gamut, and
// counted), and a bank's recruitment sampled by the fibre model (its reference is the
// profile without calibration's threshold).
#include <catch2/catch.hpp>

#include <limits>

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
  j["modes"]["SAI"]["thresholds_mA"]["PC"] = Json::array({2.0, 1.0});
  CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"),
                    "bank: recruitment.modes.SAI.thresholds_mA.PC: not ascending");
  j = recruitment_to_json(r);
  j["modes"]["PC"]["pad"] = 3;
  CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"),
                    "bank: recruitment.modes.PC.pad: not a pad of the bank");
  j = recruitment_to_json(r);
  j["modes"]["RA"]["thresholds_mA"]["SAI"] = Json::array({-1.0});
  CHECK_THROWS_WITH(recruitment_from_json(j, 3, "bank: recruitment"),
                    "bank: recruitment.modes.RA.thresholds_mA.SAI: a threshold not above 0");
}

TEST_CASE("the gamut: an image mapped pixel by pixel, inside back to itself, outside counted",
          "[render][gamut]") {
  const BankRecruitment r = three_modes();
  const Profile p = profile_at(0.4, 0.8);
  const GamutColours c = gamut_colours(r, p, 0);
  CHECK(c[0] == std::array<double, 3>{0.75, 0.25, 0});
  CHECK(c[1] == std::array<double, 3>{0, 1, 0.25});
  CHECK(c[2] == std::array<double, 3>{0.25, 0.5, 1});
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
  const std::array<double, 3> inside = {0.5 * 0.75, 0.5 * 0.25 + 0.25, 0.25 * 0.25};
  im.value[0] = inside;
  im.value[1] = {1, 0, 0};
  im.value[2] = {0, 0, 0.5};
  const GamutAnswer out = nearest_in_gamut(c, {1, 0, 0});
  const GamutAnswer blue = nearest_in_gamut(c, {0, 0, 0.5});
  const GamutReport g = map_to_gamut(bank, p, im);
  CHECK(im.value[0][0] == Approx(0.5).margin(1e-6));
  CHECK(im.value[0][1] == Approx(0.25).margin(1e-6));
  CHECK(im.value[0][2] == Approx(0).margin(1e-6));
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
  // A person's profile reads the colour at the person's multiple of threshold: comfort at
  // 1.5 x threshold reads the thresholds at 1.5 x the reference.
  Profile narrow = profile_at(1.0, 1.5);
  CHECK(gamut_colours(r, narrow, 0)[0] == r.mode[0]->fractions(1.5));
  // calibrate's colours (add_colours) are those, carried by the profile, and read first.
  Profile person = narrow;
  add_colours(person, r);
  REQUIRE(person.primary[0]->colour);
  CHECK(*person.primary[0]->colour == r.mode[0]->fractions(1.5));
  person.primary[1]->colour = std::array<double, 3>{0.1, 0.2, 0.3};
  CHECK(gamut_colours(r, person, 0)[1] == std::array<double, 3>{0.1, 0.2, 0.3});
  CHECK(profile_to_json(person)["primaries"]["SAI"]["colour"] == Json::array({0.1, 0.2, 0.3}));
  // A mode the profile has no range for is no colour.
  narrow.primary[2].reset();
  CHECK(gamut_colours(r, narrow, 0)[2] == std::array<double, 3>{0, 0, 0});
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
}
