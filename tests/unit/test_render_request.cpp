// render-tactile's request (lib/render/request.hpp): the duration's defaults, the bank's
// limits, and run_render's document, the same as the plan's own steps give.
#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "render/request.hpp"
#include "render_support.hpp"

using namespace tp;
using namespace tp::render_test;

TEST_CASE("request: the duration by default, the bank's current limit and size",
          "[render][request]") {
  RenderRequest r;
  CHECK(render_duration_s(r, 0) == 1.0);  // a still
  r.sequence = true;
  CHECK(render_duration_s(r, 0) == r.options.limits.max_duration_s);  // no frames
  CHECK(render_duration_s(r, 59) == 2.0);  // 59 frames at 30 fps and one more period
  r.fps = 10;
  CHECK(render_duration_s(r, 59) == 6.0);
  CHECK_THROWS_WITH(render_duration_s(r, 36000), Catch::Contains("36000 frames at 10 fps"));
  r.duration_s = 0.25;
  CHECK(render_duration_s(r, 59) == 0.25);

  PixelBank big;
  big.entry.resize(72);
  big.doc.max_current_mA = 1.5;
  RenderRequest s;
  CHECK_THROWS_WITH(fit_to_bank(s, big),
                    Catch::Contains("bank: 72 pads, more than a stimulator drives (64); --plan "
                                    "plans it"));
  s.plan_only = true;
  fit_to_bank(s, big);
  CHECK(s.options.limits.max_current_mA == 1.5);
  big.doc.max_current_mA = 5;
  fit_to_bank(s, big);
  CHECK(s.options.limits.max_current_mA == 1.5);  // never raised
}

TEST_CASE("request: run_render's document, warnings and refusals", "[render][request]") {
  const PixelBank& b = bank6();
  const Profile profile = profile_from_json(profile_json(), 2.0, 36);
  RenderRequest r;
  r.profile = profile;
  r.options.threads = 2;
  r.image = dark6();
  r.image.value[14] = {0, 1.0, 0};
  r.image.value[21] = {1.0, 0, 0};
  r.image_name = "two.png";
  const RenderResult still = run_render(r, b);
  const RenderPlan plan = plan_render(b, profile, r.image, r.options);
  CHECK(still.document == mix_to_json(plan.mix));
  CHECK(plan_to_json(still.plan) == plan_to_json(plan));
  CHECK(still.warning.empty());  // the person's own profile
  CHECK(still.lowered == lowered_text(plan, "image"));
  CHECK(still.plan_ms >= 0);
  r.plan_only = true;
  CHECK(run_render(r, b).document == plan_to_json(plan));
  // A sequence of no frames: every pattern, each alone, with the bank's array, lasting
  // the longest a stimulus may.
  RenderRequest q = r;
  q.plan_only = false;
  q.sequence = true;
  const RenderResult seq = run_render(q, b);
  CHECK(seq.document.contains("array"));
  CHECK(seq.plan.lit.size() == seq.plan.groups.size());
  CHECK(seq.plan.mix.patterns[0].duration_s() ==
        Approx(q.options.limits.max_duration_s).epsilon(0.01));
  // Nothing lit; an fps out of range; a duration too short.
  r.plan_only = false;
  r.image = dark6();
  CHECK_THROWS_WITH(run_render(r, b), Catch::Contains("two.png: no pixel is lit (all black)"));
  q.frames.emplace(6, 6);
  q.frames->add(dark6(), "frame 1");
  CHECK_THROWS_WITH(run_render(q, b), Catch::Contains("no frame lights a pixel"));
  q.fps = 0;
  CHECK_THROWS_WITH(run_render(q, b), Catch::Contains("--fps: 0 outside [0.1, 1000]"));
  r.image.value[14] = {1.0, 0, 0};
  r.duration_s = 0.01;
  CHECK_THROWS_WITH(run_render(r, b), Catch::Contains("shorter than one period of RA"));
}
