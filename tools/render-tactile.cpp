// render-tactile: a tactile image (R = RA, G = SAI, B = PC) on a 2-D array, at the
// intensities a person's profile gives, as one stimulus of patterns the device interleaves.
//
//   optimize-weights --bank --grid 8x8 --pitch 2 --pad 1x1 --neighbourhood 3 > bank.json
//   render-tactile --bank bank.json --profile profile.json --duration 2 picture.png
//     | stimctl --port emu --emu-channels 64   (one line)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "host/line_reader.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "render/request.hpp"

namespace {

// Each JSON-line frame on stdin ({"rgb": [...]}, blank lines skipped), checked, in order,
// with its name ("frame N") for messages.
template <class F>
void for_each_stdin_frame(const tp::PixelBank& bank, F&& f) {
  tp::host::LineReader in(0);
  std::string line;
  for (;;) {
    if (in.next(line)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      const std::string where = "frame " + std::to_string(in.lines());
      f(tp::frame_from_json(tp::parse_json_text(line, where, "its line"), bank.columns, bank.rows,
                            where),
        where);
      continue;
    }
    if (in.at_end()) return;
    in.fill(1000);
  }
}

// "render-tactile: warning: ...", a line, for a warning (none for none).
std::string warning_text(const std::string& warning) {
  return warning.empty() ? "" : "render-tactile: warning: " + warning + "\n";
}

// The PNG images on the bank's pads, each read and checked; a sequence's kept as
// SequenceFrames keeps them (not returned, so memory does not grow with their number).
// `note`: one line when some pixel was not opaque (composited onto black), else empty.
std::vector<tp::PadIntensities> read_images(const std::vector<std::string>& paths,
                                            const tp::PixelBank& bank, bool resample,
                                            tp::SequenceFrames* kept, std::string& note) {
  std::vector<tp::PadIntensities> out;
  std::size_t translucent = 0;  // images with a pixel not opaque
  for (const std::string& f : paths) {
    const tp::RgbImage im = tp::read_png(f);
    if (im.translucent > 0 && translucent++ == 0)
      note = "image '" + f + "': " + tp::count_text(im.translucent, "pixel") + " of " +
             std::to_string(im.rgb.size() / 3) + " not opaque";
    tp::PadIntensities p = tp::pad_intensities(im, bank.columns, bank.rows, resample);
    if (kept) {
      kept->add(p, f);
    } else {
      out.push_back(std::move(p));
    }
  }
  if (translucent > 0)
    note = "render-tactile: note: " + note +
           (translucent > 1 ? " (and " + tp::count_text(translucent - 1, "image") + " more)" : "") +
           ": composited onto black (transparent is 0)\n";
  return out;
}

// Writes {"amplitudes": [...]} frames, frame k at k / fps s after the first; PNG frames
// given (already checked), or JSON lines read from stdin, each checked before it is
// written.  After the last, holds it one frame period (so the device delivers it) and ends.
void play_frames(const tp::Sequence& seq, const tp::Profile& profile, const tp::PixelBank& bank,
                 const std::vector<std::vector<double>>& given, bool from_stdin, double fps) {
  using clock = std::chrono::steady_clock;
  const auto period =
      std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1.0 / fps));
  const clock::time_point t0 = clock::now();
  std::size_t k = 0;
  auto emit = [&](const std::vector<double>& a) {
    std::this_thread::sleep_until(t0 + static_cast<long>(k) * period);
    std::string text = "{\"amplitudes\": [";
    // Every digit (the shortest text that reads back as the same double): a frame at full
    // intensity asks exactly the pattern's configured amplitude, never 1e-11 above it.
    for (std::size_t i = 0; i < a.size(); ++i) text += (i ? ", " : "") + tp::Json(a[i]).dump();
    tp::cli::write_stdout(text + "]}\n");
    ++k;
  };
  if (!from_stdin) {
    for (const auto& a : given) emit(a);
  } else {
    for_each_stdin_frame(bank, [&](const tp::PadIntensities& f, const std::string& where) {
      emit(tp::frame_amplitudes(seq, profile, f, where));
    });
  }
  if (k > 0) std::this_thread::sleep_until(t0 + static_cast<long>(k) * period);
  std::fprintf(stderr, "render-tactile: %s at %s fps\n", tp::count_text(k, "frame").c_str(),
               tp::number_text(fps).c_str());
}

// The flags as given (text, parsed in the request's order), and the options whose use is
// checked against one another.
struct Flags {
  std::string bank_path, profile_path, rates, duration, crosstalk = "0.1", width = "200", balance,
                                                        frames_for, fps_text = "30", comfort_factor;
  std::vector<std::string> images;
  bool resample = false, plan_only = false, sequence = false;
  CLI::Option *rates_option = nullptr, *duration_option = nullptr, *crosstalk_option = nullptr,
              *plan_option = nullptr, *fps_option = nullptr;
};

void declare_flags(CLI::App& app, Flags& f) {
  app.add_option(
         "images", f.images,
         "The picture: a PNG (any colour type and depth, read as the 8-bit RGB it "
         "shows; transparency composited onto black), - for stdin; with --sequence or "
         "--frames, the frames in order (-: JSON lines {\"rgb\": [[R, G, B], ...]} on stdin)")
      ->type_name("PNG...");
  app.add_option("--bank", f.bank_path, "Pattern bank (optimize-weights --bank; every pad's pixel)")
      ->required()
      ->type_name("FILE");
  app.add_option("--profile", f.profile_path,
                 "The person's calibration (calibrate; format tactile-primaries/profile/1) "
                 "[none: the fibre model's thresholds at the centre pixel, comfort "
                 "--comfort-factor times them, with a warning]")
      ->type_name("FILE");
  app.add_option("--comfort-factor", f.comfort_factor,
                 "Without --profile: comfort = this x the model's threshold, 1.1 to 10 [2]")
      ->type_name("K");
  f.rates_option = app.add_option("--rates", f.rates,
                                  "Requested rate per primary, each once, Hz, 0.1 to 1000 "
                                  "[RA:30,SAI:200,PC:250]")
                       ->type_name("P:HZ,...");
  f.duration_option =
      app.add_option("--duration", f.duration,
                     "Seconds, (0, 3600], at least one period of every pattern, never clamped [a "
                     "still image: 1; a sequence: its frames and one more frame period at --fps, "
                     "or 3600 for frames on stdin]")
          ->type_name("S");
  f.crosstalk_option =
      app.add_option("--crosstalk", f.crosstalk,
                     "Largest crosstalk between patterns that fire together, 0 to 1 [0.1]")
          ->type_name("X");
  app.add_option("--width", f.width, "Main phase, us, whole, 10 to 1000 [200]")->type_name("US");
  app.add_option("--balance-width", f.balance,
                 "Balancing phase, us, whole, from --width to 8000 [--width]")
      ->type_name("US");
  app.add_flag("--resample", f.resample,
               "Resample an image of another size to the array's (area-weighted)");
  f.plan_option =
      app.add_flag("--plan", f.plan_only,
                   "Print the plan (groups, slots, rates) as JSON instead of the stimulus; for "
                   "arrays larger than a device");
  app.add_flag("--sequence", f.sequence,
               "A sequence's stimulus, for stimctl --live: each pixel and primary the frames "
               "light (none given: every one the bank has), uploaded once, starting from the "
               "first frame; pixels every frame lights alike fire together where a still's "
               "would (none given: each alone)");
  app.add_option("--frames", f.frames_for,
                 "Play the frames (the images, or JSON lines on stdin) as live amplitude "
                 "frames for the sequence's stimulus FILE (made for this bank, under a profile "
                 "of no higher comfort), one every 1/--fps s")
      ->type_name("FILE");
  f.fps_option = app.add_option("--fps", f.fps_text,
                                "Frames per second (--sequence, --frames), 0.1 to 1000 [30]")
                     ->type_name("FPS");
  tp::cli::add_output_option(app);
}

// What would do nothing is refused, not ignored: --fps paces --frames and sets the default
// duration of --sequence's frames, nothing else; --frames plays a stimulus already made,
// and streams (each frame to stdout when it is due, for stimctl --live; a file written
// whole at the end would hold them back until the stream is over).
void check_flag_use(const CLI::App& app, const Flags& f) {
  if (f.fps_option->count() > 0 && f.frames_for.empty() &&
      (!f.sequence || !f.duration.empty() || f.images.empty()))
    tp::bad_input("--fps: applies to --frames, and to --sequence's frames without --duration");
  for (const CLI::Option* opt :
       {f.rates_option, f.duration_option, f.crosstalk_option, f.plan_option})
    if (!f.frames_for.empty() && opt->count() > 0)
      tp::bad_input(opt->get_name() +
                    ": --frames plays the sequence's stimulus as it was made; give it to "
                    "--sequence");
  if (!f.frames_for.empty() && app.count("--output") > 0)
    tp::bad_input(
        "--output: --frames writes live frames to stdout as they are due (for "
        "stimctl --live), not a document; pipe them");
}

// The request's options from the flags, each parsed and checked; the duration as given,
// never clamped (out of range is refused here, and by the plan when it holds no pulse of
// some pattern).
tp::RenderRequest request_from_flags(const Flags& f) {
  tp::RenderRequest r;
  r.sequence = f.sequence;
  r.plan_only = f.plan_only;
  tp::RenderOptions& o = r.options;
  if (!f.rates.empty()) tp::parse_rates(f.rates, o.rate_hz);
  r.fps = tp::parse_finite(f.fps_text, "--fps");
  if (!(r.fps >= 0.1 && r.fps <= 1000))
    tp::bad_input("--fps: " + f.fps_text + " outside [0.1, 1000]");
  if (!f.duration.empty()) r.duration_s = tp::parse_finite(f.duration, "--duration");
  o.duration_s = tp::render_duration_s(r, f.images.size());
  o.crosstalk = tp::parse_finite(f.crosstalk, "--crosstalk");
  o.width_us = tp::parse_finite(f.width, "--width");
  o.balance_width_us =
      f.balance.empty() ? o.width_us : tp::parse_finite(f.balance, "--balance-width");
  tp::check_render_options(o);
  return r;
}

// The images and stdin as the kind of output asks them.
void check_inputs_given(const Flags& f) {
  if (f.sequence && !f.frames_for.empty()) tp::bad_input("--sequence and --frames: give one");
  if (!f.sequence && f.frames_for.empty() && f.images.size() != 1)
    tp::bad_input(tp::count_text(f.images.size(), "image") + ": a still image takes one");
  if (!f.frames_for.empty() && f.images.empty())
    tp::bad_input("--frames: no frames (images, or - for JSON lines on stdin)");
  int stdin_uses = (f.bank_path == "-") + (f.profile_path == "-") + (f.frames_for == "-");
  for (const std::string& image : f.images) stdin_uses += image == "-";
  if (stdin_uses > 1) tp::bad_input("- (stdin) given more than once");
}

// The person's profile (--profile, read under the bank's current limit), or the comfort
// factor for the model's.
void profile_from_flags(const Flags& f, const tp::PixelBank& bank, tp::RenderRequest& r) {
  if (!f.profile_path.empty() && !f.comfort_factor.empty())
    tp::bad_input("--comfort-factor: applies without --profile only");
  if (!f.comfort_factor.empty())
    r.comfort_factor = tp::parse_finite(f.comfort_factor, "--comfort-factor");
  if (!(r.comfort_factor >= 1.1 && r.comfort_factor <= 10))
    tp::bad_input("--comfort-factor: " + f.comfort_factor + " outside [1.1, 10]");
  if (!f.profile_path.empty())
    r.profile =
        tp::profile_from_json(tp::read_json(f.profile_path, "profile"),
                              r.options.limits.max_current_mA, static_cast<long>(bank.pads()));
}

// --frames: the sequence's stimulus read and checked against the bank and profile, the
// PNG frames' amplitudes all checked first (frames on stdin: as they come), then played.
void play(const Flags& f, const tp::RenderRequest& r, const tp::PixelBank& bank,
          const std::vector<tp::PadIntensities>& frames, const std::string& note) {
  const tp::RenderProfile p = tp::render_profile(r, bank);
  const tp::Sequence seq = tp::sequence_from_json(tp::read_json(f.frames_for, "stimulus"), bank,
                                                  p.profile, "--frames " + f.frames_for);
  std::vector<std::vector<double>> out;
  for (std::size_t k = 0; k < frames.size(); ++k)
    out.push_back(tp::frame_amplitudes(seq, p.profile, frames[k], f.images[k]));
  std::fputs((warning_text(p.warning) + note).c_str(), stderr);
  const bool live_input = f.images.size() == 1 && f.images[0] == "-";
  play_frames(seq, p.profile, bank, out, live_input, r.fps);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Renders a tactile image on a 2-D array: image pixel (column c, row r, row 0 at the "
      "top) drives the pixel of pad r x columns + c with R = RA, G = SAI, B = PC, each 0 to "
      "255 = 0 to 1 of the person's range (the profile: I = threshold + v (comfort - "
      "threshold); 0 delivers nothing).  Patterns that share no pad and barely reach each "
      "other's targets fire together; the groups take turns in a frame, at the requested "
      "rates or, when the image asks more than the device delivers, lower ones (said on "
      "stderr; no lit pixel is dropped).  Prints one stimulus document of the groups "
      "(stimctl plays it), or with --plan the plan.  docs/rendering.md.",
      "render-tactile"};
  Flags f;
  declare_flags(app, f);

  return tp::cli::run(app, argc, argv, [&] {
    check_flag_use(app, f);
    tp::RenderRequest r = request_from_flags(f);
    check_inputs_given(f);
    const tp::PixelBank bank = tp::pixel_bank_from_json(tp::read_json(f.bank_path, "bank"));
    tp::fit_to_bank(r, bank);
    profile_from_flags(f, bank, r);
    // The images, all read and checked before anything is printed (frames on stdin: as
    // they come, each checked before it is written).  A sequence's frames are kept as
    // SequenceFrames keeps them, so memory does not grow with their number.
    std::vector<tp::PadIntensities> frames;
    std::string note;  // composited transparency, said with the warning
    const bool from_stdin = f.images.size() == 1 && f.images[0] == "-";
    if (f.sequence) r.frames.emplace(bank.columns, bank.rows);
    if (f.sequence && from_stdin) {
      for_each_stdin_frame(bank, [&](const tp::PadIntensities& im, const std::string& where) {
        r.frames->add(im, where);
      });
      if (r.frames->count() == 0) tp::bad_input("--sequence -: no frames on stdin");
    } else if (!(from_stdin && !f.frames_for.empty())) {
      frames = read_images(f.images, bank, f.resample, f.sequence ? &*r.frames : nullptr, note);
    }
    if (!f.frames_for.empty()) {
      play(f, r, bank, frames, note);
      return;
    }
    if (!f.sequence) {
      r.image = frames[0];
      r.image_name = f.images[0];
    }
    const tp::RenderResult out = tp::run_render(r, bank);
    std::fputs((warning_text(out.warning) + note).c_str(), stderr);
    if (!out.lowered.empty()) std::fprintf(stderr, "render-tactile: %s\n", out.lowered.c_str());
    std::fprintf(stderr, "render-tactile: %s; planned in %s ms\n",
                 tp::plan_summary(out.plan).c_str(),
                 tp::number_text(std::round(out.plan_ms * 10) / 10).c_str());
    tp::cli::write_stdout(tp::dump_json(out.document));
  });
}
