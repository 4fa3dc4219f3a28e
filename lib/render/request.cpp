#include "render/request.hpp"

#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "render/options.hpp"

namespace tp {

double render_duration_s(const RenderRequest& r, std::size_t frames) {
  if (r.duration_s) return *r.duration_s;
  if (!r.sequence) return 1.0;
  if (frames == 0) return r.options.limits.max_duration_s;
  return sequence_duration_s(frames, r.fps, r.options.limits);
}

void fit_to_bank(RenderRequest& r, const PixelBank& bank) {
  r.options.limits.max_current_mA =
      std::min(r.options.limits.max_current_mA, bank.doc.max_current_mA);
  if (!r.plan_only && bank.pads() > static_cast<std::size_t>(ranges::max_channels))
    bad_input("bank: " + count_text(bank.pads(), "pad") + ", more than a stimulator drives (" +
              std::to_string(ranges::max_channels) + "); --plan plans it");
}

PulseSpec render_pulse(const RenderOptions& o) {
  PulseSpec p;
  p.width_us = o.width_us;
  p.interphase_us = o.interphase_us;
  p.balance_width_us = o.balance_width_us;
  return p;
}

RenderProfile render_profile(const RenderRequest& r, const PixelBank& bank) {
  if (r.profile) return {*r.profile, ""};
  if (r.model_profile) return *r.model_profile;
  const RenderOptions& o = r.options;
  ModelProfileOptions m;
  m.pulse = render_pulse(o);
  m.max_current_mA = o.limits.max_current_mA;
  m.comfort_factor = r.comfort_factor;
  const ModelProfile mp = model_profile(bank, m);
  std::string ranges;
  for (std::size_t p = 0; p < kPrimaries.size(); ++p) {
    if (!mp.profile.primary[p]) continue;
    const PrimaryRange& range = *mp.profile.primary[p];
    ranges += std::string(ranges.empty() ? "" : ", ") + kPrimaries[p] + " " +
              number_text(std::round(range.threshold_mA * 1e4) / 1e4) + " to " +
              number_text(std::round(range.comfort_mA * 1e4) / 1e4) + " mA" +
              (mp.capped[p] ? " (comfort held at the current limit)" : "") + " at pad " +
              std::to_string(mp.pixel[p]);
  }
  return {mp.profile, "no --profile: intensities span the fibre model's thresholds (" +
                          m.fibre_model + ", " + number_text(m.pulse.width_us) + " us) to " +
                          number_text(m.comfort_factor) + " x them, not this person's: " + ranges +
                          "; run calibrate"};
}

namespace {

// Why the bank's channels drive their modes as given, or that its recruitment's pulse is not
// the render's ("" when it is).
std::string gamut_note(const PixelBank& bank, const RenderOptions& o) {
  if (!bank.recruitment)
    return "the bank carries no recruitment (optimize-weights --bank --population N): each "
           "channel drives its mode as given, whatever else the mode recruits";
  return recruitment_pulse_note(*bank.recruitment, render_pulse(o));
}

// A still's requested colours into the intensities nearest them in the modes' gamut, or a
// sequence's mapping (render_images'), when the bank carries the modes' recruitment
// (docs/rendering.md, "The gamut").
void map_image(RenderRequest& r, const PixelBank& bank, const Profile& profile, RenderResult& out) {
  out.gamut_note = gamut_note(bank, r.options);
  if (!bank.recruitment) return;
  if (r.sequence) {  // mapped as read (render_images); without frames, nothing to map
    if (r.frames_gamut && r.frames_gamut->frames > 0) out.gamut = r.frames_gamut;
    out.gamut_ms = r.frames_gamut_ms;
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  out.gamut = map_to_gamut(bank, profile, r.image);
  out.gamut_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

RenderResult run_render(const RenderRequest& request, const PixelBank& bank) {
  RenderRequest r = request;
  fit_to_bank(r, bank);
  if (!(r.fps >= 0.1 && r.fps <= 1000))
    bad_input("--fps: " + number_beside(r.fps, 0.1, 1000) + " outside [0.1, 1000]");
  RenderResult out;
  const RenderProfile profile = render_profile(r, bank);
  out.warning = profile.warning;
  RenderOptions& o = r.options;
  o.duration_s = render_duration_s(r, r.frames ? r.frames->count() : 0);
  check_render_options(o);
  map_image(r, bank, profile.profile, out);
  const auto t0 = std::chrono::steady_clock::now();
  out.plan = !r.sequence ? plan_render(bank, profile.profile, r.image, o)
             : r.frames
                 ? plan_sequence(bank, profile.profile, *r.frames, o)
                 : plan_sequence(bank, profile.profile, SequenceFrames(bank.columns, bank.rows), o);
  out.plan_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (out.plan.lit.empty() && out.gamut && out.gamut->requested > 0)
    bad_input((r.sequence ? std::string("the sequence's frames") : r.image_name) + ": " +
              unlit_by_gamut(bank, profile.profile, *out.gamut));
  if (out.plan.lit.empty())
    bad_input(r.sequence ? "no frame lights a pixel"
                         : r.image_name + ": no pixel is lit (all black)");
  // Every check a device's mix gets (a plan for more pads than a stimulator drives is only
  // a plan, and skips them).
  if (bank.pads() <= static_cast<std::size_t>(ranges::max_channels))
    check_mix(out.plan.mix, o.limits);
  out.lowered = lowered_text(out.plan, r.sequence ? "sequence" : "image");
  out.document = r.plan_only  ? plan_to_json(out.plan)
                 : r.sequence ? sequence_to_json(out.plan, bank)
                              : mix_to_json(out.plan.mix);
  if (out.gamut) out.document["gamut"] = gamut_to_json(*out.gamut);
  return out;
}

namespace {

// What would do nothing is refused, not ignored: --fps paces --frames and sets the default
// duration of --sequence's frames, nothing else; --frames plays a stimulus already made,
// and streams (each frame to stdout when it is due, for stimctl --live; a file written
// whole at the end would hold them back until the stream is over).
void check_flag_use(const RenderSpec& s) {
  if (s.fps_given && s.frames_for.empty() &&
      (!s.sequence || !s.duration.empty() || s.images.empty()))
    bad_input("--fps: applies to --frames, and to --sequence's frames without --duration");
  const std::pair<const char*, bool> given[] = {{"--rates", s.rates_given},
                                                {"--duration", s.duration_given},
                                                {"--crosstalk", s.crosstalk_given},
                                                {"--plan", s.plan_given}};
  for (const auto& [name, is_given] : given)
    if (!s.frames_for.empty() && is_given)
      bad_input(std::string(name) +
                ": --frames plays the sequence's stimulus as it was made; give it to "
                "--sequence");
  if (!s.frames_for.empty() && s.output_given)
    bad_input(
        "--output: --frames writes live frames to stdout as they are due (for "
        "stimctl --live), not a document; pipe them");
}

// The request's options from the spec, each parsed and checked; the duration as given,
// never clamped (out of range is refused here, and by the plan when it holds no pulse of
// some pattern).
RenderRequest request_from_spec(const RenderSpec& s) {
  RenderRequest r;
  r.sequence = s.sequence;
  r.plan_only = s.plan_only;
  RenderOptions& o = r.options;
  if (!s.rates.empty()) parse_rates(s.rates, o.rate_hz);
  r.fps = parse_finite(s.fps, "--fps");
  if (!(r.fps >= 0.1 && r.fps <= 1000)) bad_input("--fps: " + s.fps + " outside [0.1, 1000]");
  if (!s.duration.empty()) r.duration_s = parse_finite(s.duration, "--duration");
  o.duration_s = render_duration_s(r, s.images.size());
  o.crosstalk = parse_finite(s.crosstalk, "--crosstalk");
  o.width_us = parse_finite(s.width, "--width");
  o.balance_width_us = s.balance.empty() ? o.width_us : parse_finite(s.balance, "--balance-width");
  check_render_options(o);
  return r;
}

// The images and stdin as the kind of output asks them.
void check_inputs_given(const RenderSpec& s) {
  if (s.sequence && !s.frames_for.empty()) bad_input("--sequence and --frames: give one");
  if (!s.sequence && s.frames_for.empty() && s.images.size() != 1)
    bad_input(count_text(s.images.size(), "image") + ": a still image takes one");
  if (!s.frames_for.empty() && s.images.empty())
    bad_input("--frames: no frames (images, or - for JSON lines on stdin)");
  int stdin_uses = (s.bank_path == "-") + (s.profile_path == "-") + (s.frames_for == "-");
  for (const std::string& image : s.images) stdin_uses += image == "-";
  if (stdin_uses > 1) bad_input("- (stdin) given more than once");
}

// The PNG images on the bank's pads, each read and checked; a sequence's given to `keep`
// (not returned).  `note` as render_images says.
std::vector<PadIntensities> read_images(const std::vector<std::string>& paths,
                                        const PixelBank& bank, bool resample,
                                        const FrameSink& keep, std::string& note) {
  std::vector<PadIntensities> out;
  std::size_t translucent = 0;  // images with a pixel not opaque
  for (const std::string& f : paths) {
    const RgbImage im = read_png(f);
    if (im.translucent > 0 && translucent++ == 0)
      note = "image '" + f + "': " + count_text(im.translucent, "pixel") + " of " +
             std::to_string(im.rgb.size() / 3) + " not opaque";
    PadIntensities p = pad_intensities(im, bank.columns, bank.rows, resample);
    if (keep) {
      keep(p, f);
    } else {
      out.push_back(std::move(p));
    }
  }
  if (translucent > 0)
    note += (translucent > 1 ? " (and " + count_text(translucent - 1, "image") + " more)" : "") +
            ": composited onto black (transparent is 0)";
  return out;
}

}  // namespace

RenderRequest render_request(const RenderSpec& s) {
  check_flag_use(s);
  RenderRequest r = request_from_spec(s);
  check_inputs_given(s);
  return r;
}

void fit_spec_to_bank(const RenderSpec& s, const PixelBank& bank, RenderRequest& r) {
  fit_to_bank(r, bank);
  if (!s.profile_path.empty() && !s.comfort_factor.empty())
    bad_input("--comfort-factor: applies without --profile only");
  if (!s.comfort_factor.empty())
    r.comfort_factor = parse_finite(s.comfort_factor, "--comfort-factor");
  if (!(r.comfort_factor >= 1.1 && r.comfort_factor <= 10))
    bad_input("--comfort-factor: " + s.comfort_factor + " outside [1.1, 10]");
  if (!s.profile_path.empty())
    r.profile = profile_from_json(read_json(s.profile_path, "profile"),
                                  r.options.limits.max_current_mA, static_cast<long>(bank.pads()));
}

bool images_from_stdin(const RenderSpec& s) { return s.images.size() == 1 && s.images[0] == "-"; }

namespace {

// A sequence's frames into r.frames, each mapped into the gamut first when the bank carries
// recruitment (with the profile run_render will plan with, computed here once).
FrameSink sequence_sink(const PixelBank& bank, RenderRequest& r) {
  r.frames.emplace(bank.columns, bank.rows);
  if (!bank.recruitment) return [&r](const PadIntensities& im, const std::string& where) {
    r.frames->add(im, where);
  };
  if (!r.profile) r.model_profile = render_profile(r, bank);
  r.frames_gamut.emplace();
  // The profile run_render plans with, taken once (not copied for every frame).
  const Profile& profile = r.profile ? *r.profile : r.model_profile->profile;
  return [&r, &bank, &profile](const PadIntensities& im, const std::string& where) {
    PadIntensities mapped = im;
    const auto t0 = std::chrono::steady_clock::now();
    map_frame(bank, profile, mapped, *r.frames_gamut);
    r.frames_gamut_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    r.frames->add(mapped, where);
  };
}

}  // namespace

RenderImages render_images(const RenderSpec& s, const PixelBank& bank, RenderRequest& r,
                           const StdinFrames& read_stdin) {
  RenderImages out;
  const bool from_stdin = images_from_stdin(s);
  const FrameSink keep = s.sequence ? sequence_sink(bank, r) : FrameSink();
  if (s.sequence && from_stdin) {
    read_stdin(keep);
    if (r.frames->count() == 0) bad_input("--sequence -: no frames on stdin");
  } else if (!(from_stdin && !s.frames_for.empty())) {
    out.frames = read_images(s.images, bank, s.resample, keep, out.note);
  }
  if (!s.sequence && s.frames_for.empty()) {
    r.image = out.frames[0];
    r.image_name = s.images[0];
  }
  return out;
}

FramesToPlay frames_to_play(const RenderSpec& s, const RenderRequest& r, const PixelBank& bank,
                            const std::vector<PadIntensities>& frames) {
  RenderProfile p = render_profile(r, bank);
  Sequence seq = sequence_from_json(read_json(s.frames_for, "stimulus"), bank, p.profile,
                                    "--frames " + s.frames_for);
  std::vector<std::vector<double>> out;
  std::optional<GamutReport> gamut;
  if (bank.recruitment) gamut.emplace();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    PadIntensities frame = frames[k];
    if (gamut) map_frame(bank, p.profile, frame, *gamut);
    out.push_back(frame_amplitudes(seq, p.profile, frame, s.images[k]));
  }
  std::string note = gamut_note(bank, r.options);
  return {std::move(p), std::move(seq), std::move(out), std::move(gamut), std::move(note)};
}

}  // namespace tp
