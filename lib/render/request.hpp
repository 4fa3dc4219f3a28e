#pragma once
// render-tactile's work (docs/rendering.md), for the program and any other front end, in
// the manner of PulseRequest (requests/pulse.hpp): a bank, the image or a sequence's frames,
// and a person's profile (or none: the fibre model's) become a still's or a sequence's
// stimulus, or its plan, and what to say about it.  The front end reads the files and
// writes the output; the request holds values.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "render/model_profile.hpp"
#include "render/recruitment.hpp"
#include "render/render.hpp"

namespace tp {

// The profile a request renders with (render_profile).
struct RenderProfile {
  Profile profile;
  std::string warning;  // empty with the request's own profile
};

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
  // render_images' work for run_render: the profile it mapped a sequence's frames with (the
  // fibre model's, computed once), and how near the frames came to the gamut.
  std::optional<RenderProfile> model_profile;
  std::optional<GamutReport> frames_gamut;
  double frames_gamut_ms = 0;
};

// The request's duration: as given, else a still's 1 s, a sequence's `frames` and one
// frame period more at r.fps (sequence_duration_s), or, without frames, the longest a
// stimulus may last.
double render_duration_s(const RenderRequest& r, std::size_t frames);

// The request fitted to the bank: its current limit at most the bank's.  Bad input for a
// bank of more pads than a stimulator drives, unless r.plan_only.
void fit_to_bank(RenderRequest& r, const PixelBank& bank);

// The profile the request renders with: its own, or (none given) the fibre model's for
// the request's pulse (r.model_profile when render_images computed it), with a warning that
// says so and gives each primary's range.
RenderProfile render_profile(const RenderRequest& r, const PixelBank& bank);
// The pulse the render delivers (--width, --interphase, --balance-width).
PulseSpec render_pulse(const RenderOptions& o);

struct RenderResult {
  RenderPlan plan;
  // The still's mix, the sequence's stimulus with the bank's array, or (plan_only) the plan.
  Json document;
  std::string warning;  // render_profile's
  std::string lowered;  // why rates were lowered (lowered_text; empty when not)
  double plan_ms = 0;   // the time the plan took
  // A still's image or a sequence's frames mapped into the modes' gamut (the bank carries
  // their recruitment, render/recruitment.hpp), in the document as "gamut"; none without it
  // or for a sequence without frames.
  std::optional<GamutReport> gamut;
  double gamut_ms = 0;  // the time the mapping took
  // Why the channels were rendered as given (the bank carries no recruitment), or that the
  // recruitment's pulse is not the render's; empty: nothing to say.
  std::string gamut_note;
};
// Fits the request to the bank, checks its options (bad input naming them as
// render-tactile's flags), plans it and checks the mix as a device would (unless it is
// only a plan for more pads than a stimulator drives).  Bad input, too, when nothing is lit.
RenderResult run_render(const RenderRequest& r, const PixelBank& bank);

// render-tactile's flags as given: their text (parsed in the request's order), and which
// were given at all (counted as given even at their defaults), for the combinations that
// would do nothing and are refused.
struct RenderSpec {
  std::vector<std::string> images;  // PNGs, - for stdin (JSON-line frames with a sequence)
  std::string bank_path, profile_path, comfort_factor, rates, duration, crosstalk = "0.1",
              width = "200", balance, frames_for, fps = "30";
  bool resample = false, plan_only = false, sequence = false;
  bool rates_given = false, duration_given = false, crosstalk_given = false,
       plan_given = false, fps_given = false, output_given = false;
};

// The request from the spec, before any file is read: the flags' combinations (what would
// do nothing is refused, not ignored), each option parsed and checked, then the images
// and stdin as the kind of output asks them; bad input naming the flag.
RenderRequest render_request(const RenderSpec& s);

// The request fitted to the bank (fit_to_bank), then the person's profile (--profile,
// read under the bank's current limit) or the comfort factor for the model's.
void fit_spec_to_bank(const RenderSpec& s, const PixelBank& bank, RenderRequest& r);

// Whether the frames (or the one image) come from stdin: the images are just "-".
bool images_from_stdin(const RenderSpec& s);

// The frames on stdin (JSON lines, read by the front end): `frame` is called with each,
// checked, and its name for messages ("frame N"), in order.
using FrameSink = std::function<void(const PadIntensities&, const std::string&)>;
using StdinFrames = std::function<void(const FrameSink& frame)>;

// The images the request renders, read and checked before anything is written: a still's
// into r.image; a sequence's into r.frames (as SequenceFrames keeps them, so memory does
// not grow with their number; from stdin through `read_stdin`), each mapped into the gamut
// first when the bank carries recruitment (r.frames_gamut); --frames' PNGs returned, their
// amplitudes to be played (from stdin: none, read as they come).  `note`: when some pixel
// was not opaque, what was composited onto black, else empty.
struct RenderImages {
  std::vector<PadIntensities> frames;  // --frames' PNG frames
  std::string note;
};
RenderImages render_images(const RenderSpec& s, const PixelBank& bank, RenderRequest& r,
                           const StdinFrames& read_stdin);

// --frames: the sequence's stimulus (its file) read and checked against the bank and the
// profile, and each PNG frame's amplitudes (mapped into the gamut first, as --sequence
// mapped its frames, when the bank carries recruitment), all checked before the first is
// played.
struct FramesToPlay {
  RenderProfile profile;
  Sequence sequence;
  std::vector<std::vector<double>> amplitudes;  // the PNG frames'
  std::optional<GamutReport> gamut;             // the frames' mapping (stdin's: as played)
  std::string gamut_note;                       // as RenderResult's
};
FramesToPlay frames_to_play(const RenderSpec& s, const RenderRequest& r, const PixelBank& bank,
                            const std::vector<PadIntensities>& frames);

}  // namespace tp
