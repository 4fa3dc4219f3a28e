// The person's profile (psych/profile): its currents, and every range outside its bounds
// refused.
#include <catch2/catch.hpp>

#include <string>

#include "core/error.hpp"
#include "psych/profile.hpp"
#include "render_support.hpp"

using namespace tp;
using namespace tp::render_test;

TEST_CASE("a profile: its currents, and every range outside its bounds refused", "[render]") {
  const Profile p = profile_from_json(profile_json(), 2.0, 64);
  CHECK(p.current_mA(1, 0, 0.0) == 0.0);
  CHECK(p.current_mA(1, 0, 1.0) == Approx(0.9));
  CHECK(p.current_mA(1, 0, 0.5) == Approx(0.6));
  CHECK(p.current_mA(0, 7, 1.0 / 255) == Approx(0.4 + 0.6 / 255));
  Json j = profile_json();
  j["pixels"] = Json::array({{{"pad", 3}, {"SAI", {{"threshold_mA", 0.1}, {"comfort_mA", 0.2}}}}});
  const Profile q = profile_from_json(j, 2.0, 64);
  CHECK(q.current_mA(1, 3, 1.0) == Approx(0.2));
  CHECK(q.current_mA(1, 4, 1.0) == Approx(0.9));
  CHECK(q.current_mA(0, 3, 1.0) == Approx(1.0));  // its other primaries: the profile's
  CHECK(profile_to_json(q) == j);
  auto refused = [](const Json& bad, const std::string& says) {
    try {
      profile_from_json(bad, 2.0, 64);
      FAIL("accepted: " << bad.dump());
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      CHECK_THAT(e.what(), Catch::Contains(says));
    }
  };
  refused(profile_json(0.5, 0.4), "below its threshold");
  refused(profile_json(0.3, 2.5), "above the current limit");
  refused(profile_json(0.0, 0.4), "outside [0.001, 2] mA");
  refused(profile_json(0.0005, 0.4), "outside [0.001, 2] mA");
  Json f = profile_json();
  f["format"] = "tactile-primaries/profile/2";
  refused(f, "format");
  Json far = profile_json();
  far["pixels"] =
      Json::array({{{"pad", 64}, {"SAI", {{"threshold_mA", 0.1}, {"comfort_mA", 0.2}}}}});
  refused(far, "not one of the array's 64 pads");
  Json odd = profile_json();
  odd["primaries"]["XY"] = {{"threshold_mA", 0.1}, {"comfort_mA", 0.2}};
  refused(odd, "not a primary");
  // The model's threshold beside the person's (calibrate): carried both ways, in range.
  Json model = profile_json();
  model["primaries"]["SAI"]["model_threshold_mA"] = 0.0864;
  const Profile m = profile_from_json(model, 2.0, 64);
  CHECK(m.primary[1]->model_threshold_mA == 0.0864);
  CHECK(m.primary[0]->model_threshold_mA == 0);  // not known
  CHECK(profile_to_json(m) == model);
  model["primaries"]["SAI"]["model_threshold_mA"] = 0.0;
  refused(model, "primaries.SAI.model_threshold_mA: 0 mA outside (0, 1000] mA");
  model["primaries"]["SAI"].erase("model_threshold_mA");
  model["primaries"]["SAI"]["colour"] = Json::array({0.5, 1.0, 0.0});
  CHECK(*profile_from_json(model, 2.0, 64).primary[1]->colour == std::array<double, 3>{0.5, 1, 0});
  model["primaries"]["SAI"]["colour"] = Json::array({0.5, 1.5, 0.0});
  refused(model, "primaries.SAI.colour: 1.5 outside [0, 1]");
  model["primaries"]["SAI"]["colour"] = Json::array({0.5});
  refused(model, "primaries.SAI.colour: expected 3 fractions (RA, SAI, PC)");
  model["primaries"]["SAI"].erase("colour");
  model["primaries"]["SAI"]["model_mA"] = 0.1;
  refused(model, "unknown key 'model_mA'");
  Json partial = profile_json();
  partial["primaries"].erase("PC");
  const Profile r = profile_from_json(partial, 2.0, 64);
  CHECK_THROWS_AS(r.current_mA(2, 0, 1.0), Error);
}
