// render-tactile's request (lib/render/request.hpp): the duration's defaults, the bank's
// limits, and run_render's document, the same as the plan's own steps give; the flags as
// given (RenderSpec): their combinations, defaults and refusals, and the inputs each output
// asks (render_images).
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

namespace {

// A 6 x 6 bank's shape without its patterns (for what reads only its size and limit).
PixelBank bank_of_6x6() {
  PixelBank b;
  b.columns = b.rows = 6;
  b.entry.resize(36);
  return b;
}

}  // namespace

TEST_CASE("request: render-tactile's flags, their combinations, defaults and inputs",
          "[render][request]") {
  using Catch::Contains;
  RenderSpec s;
  s.images = {"a.png"};
  // The defaults: a still of 1 s, crosstalk 0.1, both phases 200 us, 30 fps.
  const RenderRequest d = render_request(s);
  CHECK(!d.sequence);
  CHECK(d.options.duration_s == 1.0);
  CHECK(d.options.crosstalk == 0.1);
  CHECK(d.options.width_us == 200.0);
  CHECK(d.options.balance_width_us == 200.0);
  CHECK(d.fps == 30.0);
  // What would do nothing is refused, naming the flag, before any number is read.
  RenderSpec f = s;
  f.fps_given = true;
  f.fps = "x";
  CHECK_THROWS_WITH(render_request(f), Contains("--fps: applies to --frames"));
  f.sequence = true;  // a sequence's frames without --duration: --fps sets their duration
  CHECK_THROWS_WITH(render_request(f), Contains("--fps: not a number 'x'"));
  f.fps = "2000";
  CHECK_THROWS_WITH(render_request(f), Contains("--fps: 2000 outside [0.1, 1000]"));
  f.fps = "10";
  f.images = {"a.png", "b.png", "c.png", "d.png"};
  CHECK(render_request(f).options.duration_s == 0.5);  // 4 frames and one period at 10 fps
  RenderSpec frames = s;
  frames.frames_for = "seq.json";
  frames.crosstalk_given = true;
  CHECK_THROWS_WITH(render_request(frames),
                    Contains("--crosstalk: --frames plays the sequence's stimulus as it was made"));
  frames.crosstalk_given = false;
  frames.output_given = true;
  CHECK_THROWS_WITH(render_request(frames), Contains("--output: --frames writes live frames"));
  frames.output_given = false;
  frames.sequence = true;
  CHECK_THROWS_WITH(render_request(frames), Contains("--sequence and --frames: give one"));
  // The inputs the output asks: a still one image, stdin once.
  RenderSpec two = s;
  two.images = {"a.png", "b.png"};
  CHECK_THROWS_WITH(render_request(two), Contains("2 images: a still image takes one"));
  RenderSpec twice = s;
  twice.images = {"-"};
  twice.bank_path = "-";
  CHECK_THROWS_WITH(render_request(twice), Contains("- (stdin) given more than once"));
  CHECK(images_from_stdin(twice));
  CHECK(!images_from_stdin(s));
  RenderSpec balance = s;
  balance.width = "100";
  CHECK(render_request(balance).options.balance_width_us == 100.0);
  // After the bank: the comfort factor only without a profile, and in range.
  const PixelBank b = bank_of_6x6();
  RenderSpec c = s;
  c.comfort_factor = "20";
  RenderRequest r = render_request(c);
  CHECK_THROWS_WITH(fit_spec_to_bank(c, b, r), Contains("--comfort-factor: 20 outside [1.1, 10]"));
  c.comfort_factor = "3";
  fit_spec_to_bank(c, b, r);
  CHECK(r.comfort_factor == 3.0);
  CHECK(!r.profile);
  c.profile_path = "profile.json";
  CHECK_THROWS_WITH(fit_spec_to_bank(c, b, r),
                    Contains("--comfort-factor: applies without --profile only"));
}

TEST_CASE("request: the images as the output asks them", "[render][request]") {
  const PixelBank b = bank_of_6x6();
  RenderSpec s;
  s.sequence = true;
  s.images = {"-"};
  RenderRequest r = render_request(s);
  // A sequence's frames on stdin, through the front end's reader, kept as frames.
  const RenderImages in = render_images(s, b, r, [&](const FrameSink& sink) {
    sink(dark6(), "frame 1");
    sink(dark6(), "frame 2");
  });
  REQUIRE(r.frames);
  CHECK(r.frames->count() == 2);
  CHECK(in.frames.empty());
  CHECK(in.note.empty());
  RenderRequest none = render_request(s);
  CHECK_THROWS_WITH(render_images(s, b, none, [](const FrameSink&) {}),
                    Catch::Contains("--sequence -: no frames on stdin"));
  // --frames from stdin: nothing read now (each frame as it comes, while playing).
  RenderSpec play = s;
  play.sequence = false;
  play.frames_for = "seq.json";
  RenderRequest p = render_request(play);
  bool read = false;
  CHECK(render_images(play, b, p, [&](const FrameSink&) { read = true; }).frames.empty());
  CHECK(!read);
  CHECK(!p.frames);
}
