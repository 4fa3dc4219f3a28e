#pragma once
// render-tactile's work (docs/rendering.md), for the program and any other front end, in
// the manner of PulseRequest (requests/pulse.hpp): a bank, the image or a sequence's frames,
// and a person's profile (or none: the fibre model's) become a still's or a sequence's
// stimulus, or its plan, and what to say about it.  The front end reads the files and
// writes the output; the request holds values.

#include <optional>
#include <string>

#include "render/model_profile.hpp"
#include "render/render.hpp"

namespace tp {

struct RenderRequest {
  RenderOptions options;   // its duration_s: render_duration_s's
  bool sequence = false;   // a sequence's stimulus (for stimctl --live), not a still's
  bool plan_only = false;  // the plan (for arrays larger than a stimulator), not the stimulus
  // [a still: 1 s; a sequence: its frames and one frame period more at fps; without
  // frames: the longest a stimulus may last]
  std::optional<double> duration_s;
  double fps = 30;  // a sequence's frames per second, 0.1 to 1000
  // [the fibre model's thresholds at the centre pixel, comfort_factor x them, said so]
  std::optional<Profile> profile;
  double comfort_factor = kDefaultComfortFactor;  // 1.1 to 10, without a profile
  PadIntensities image;                           // a still's
  std::string image_name = "image";               // for messages: its file
  std::optional<SequenceFrames> frames;           // a sequence's (none: every pattern)
};

// The request's duration: as given, else a still's 1 s, a sequence's `frames` and one
// frame period more at r.fps (sequence_duration_s), or, without frames, the longest a
// stimulus may last.
double render_duration_s(const RenderRequest& r, std::size_t frames);

// The request fitted to the bank: its current limit at most the bank's.  Bad input for a
// bank of more pads than a stimulator drives, unless r.plan_only.
void fit_to_bank(RenderRequest& r, const PixelBank& bank);

// The profile the request renders with: its own, or (none given) the fibre model's for
// the request's pulse, with a warning that says so and gives each primary's range.
struct RenderProfile {
  Profile profile;
  std::string warning;  // empty with the request's own profile
};
RenderProfile render_profile(const RenderRequest& r, const PixelBank& bank);

struct RenderResult {
  RenderPlan plan;
  // The still's mix, the sequence's stimulus with the bank's array, or (plan_only) the plan.
  Json document;
  std::string warning;  // render_profile's
  std::string lowered;  // why rates were lowered (lowered_text; empty when not)
  double plan_ms = 0;   // the time the plan took
};
// Fits the request to the bank, checks its options (bad input naming them as
// render-tactile's flags), plans it and checks the mix as a device would (unless it is
// only a plan for more pads than a stimulator drives).  Bad input, too, when nothing is lit.
RenderResult run_render(const RenderRequest& r, const PixelBank& bank);

}  // namespace tp
