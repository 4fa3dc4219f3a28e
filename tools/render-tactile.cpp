// render-tactile: a tactile image (R = RA, G = SAI, B = PC) on a 2-D array, at the
// intensities a person's profile gives, as one stimulus of patterns the device interleaves.
//
//   optimize-weights --bank --grid 8x8 --pitch 2 --pad 1x1 --neighbourhood 3 > bank.json
//   render-tactile --bank bank.json --profile profile.json --duration 2 picture.png
//     | stimctl --port emu --emu-channels 64   (one line)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "host/line_reader.hpp"
#include "io/json.hpp"
#include "io/number.hpp"
#include "model/ranges.hpp"
#include "render/model_profile.hpp"
#include "render/render.hpp"

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

// Writes {"amplitudes": [...]} frames, frame k at k / fps s after the first; PNG frames
// given (already checked), or JSON lines read from stdin, each checked before it is
// written.  After the last, holds it one frame period (so the device delivers it) and ends.
// Without --profile: the fibre model's thresholds, said on stderr (after every option and
// the bank are checked).
tp::Profile model_profile(const tp::PixelBank& bank, const tp::RenderOptions& o, double factor,
                          std::string& warning) {
  tp::ModelProfileOptions m;
  m.pulse.width_us = o.width_us;
  m.pulse.interphase_us = o.interphase_us;
  m.pulse.balance_width_us = o.balance_width_us;
  m.max_current_mA = o.limits.max_current_mA;
  m.comfort_factor = factor;
  const tp::ModelProfile mp = tp::model_profile(bank, m);
  std::string ranges;
  for (std::size_t p = 0; p < tp::kPrimaries.size(); ++p) {
    if (!mp.profile.primary[p]) continue;
    const tp::PrimaryRange& r = *mp.profile.primary[p];
    ranges += std::string(ranges.empty() ? "" : ", ") + tp::kPrimaries[p] + " " +
              tp::number_text(std::round(r.threshold_mA * 1e4) / 1e4) + " to " +
              tp::number_text(std::round(r.comfort_mA * 1e4) / 1e4) + " mA" +
              (mp.capped[p] ? " (comfort held at the current limit)" : "") + " at pad " +
              std::to_string(mp.pixel[p]);
  }
  warning =
      "render-tactile: warning: no --profile: intensities span the fibre model's "
      "thresholds (" +
      m.fibre_model + ", " + tp::number_text(m.pulse.width_us) + " us) to " +
      tp::number_text(m.comfort_factor) + " x them, not this person's: " + ranges +
      "; run calibrate\n";
  return mp.profile;
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
  std::string bank_path, profile_path, rates, duration, crosstalk = "0.1", width = "200", balance,
                                                        frames_for, fps_text = "30", comfort_factor;
  std::vector<std::string> images;
  bool resample = false, plan_only = false, sequence = false;
  app.add_option(
         "images", images,
         "The picture: a PNG (any colour type and depth, read as the 8-bit RGB it "
         "shows; transparency composited onto black), - for stdin; with --sequence or "
         "--frames, the frames in order (-: JSON lines {\"rgb\": [[R, G, B], ...]} on stdin)")
      ->type_name("PNG...");
  app.add_option("--bank", bank_path, "Pattern bank (optimize-weights --bank; every pad's pixel)")
      ->required()
      ->type_name("FILE");
  app.add_option("--profile", profile_path,
                 "The person's calibration (calibrate; format tactile-primaries/profile/1) "
                 "[none: the fibre model's thresholds at the centre pixel, comfort "
                 "--comfort-factor times them, with a warning]")
      ->type_name("FILE");
  app.add_option("--comfort-factor", comfort_factor,
                 "Without --profile: comfort = this x the model's threshold, 1.1 to 10 [2]")
      ->type_name("K");
  CLI::Option* rates_option =
      app.add_option("--rates", rates,
                     "Requested rate per primary, each once, Hz, 0.1 to 1000 "
                     "[RA:30,SAI:200,PC:250]")
          ->type_name("P:HZ,...");
  CLI::Option* duration_option =
      app.add_option("--duration", duration,
                     "Seconds, (0, 3600], at least one period of every pattern, never clamped [a "
                     "still image: 1; a sequence: its frames and one more frame period at --fps, "
                     "or 3600 for frames on stdin]")
          ->type_name("S");
  CLI::Option* crosstalk_option =
      app.add_option("--crosstalk", crosstalk,
                     "Largest crosstalk between patterns that fire together, 0 to 1 [0.1]")
          ->type_name("X");
  app.add_option("--width", width, "Main phase, us, whole, 10 to 1000 [200]")->type_name("US");
  app.add_option("--balance-width", balance,
                 "Balancing phase, us, whole, from --width to 8000 [--width]")
      ->type_name("US");
  app.add_flag("--resample", resample,
               "Resample an image of another size to the array's (area-weighted)");
  CLI::Option* plan_option =
      app.add_flag("--plan", plan_only,
                   "Print the plan (groups, slots, rates) as JSON instead of the stimulus; for "
                   "arrays larger than a device");
  app.add_flag("--sequence", sequence,
               "A sequence's stimulus, for stimctl --live: each pixel and primary the frames "
               "light (none given: every one the bank has), uploaded once, starting from the "
               "first frame; pixels every frame lights alike fire together where a still's "
               "would (none given: each alone)");
  app.add_option("--frames", frames_for,
                 "Play the frames (the images, or JSON lines on stdin) as live amplitude "
                 "frames for the sequence's stimulus FILE (made for this bank, under a profile "
                 "of no higher comfort), one every 1/--fps s")
      ->type_name("FILE");
  CLI::Option* fps_option =
      app.add_option("--fps", fps_text,
                     "Frames per second (--sequence, --frames), 0.1 to 1000 [30]")
          ->type_name("FPS");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    tp::RenderOptions o;
    // What would do nothing is refused, not ignored: --fps paces --frames and sets the
    // default duration of --sequence's frames, nothing else; --frames plays a stimulus
    // already made.
    if (fps_option->count() > 0 && frames_for.empty() &&
        (!sequence || !duration.empty() || images.empty()))
      tp::bad_input("--fps: applies to --frames, and to --sequence's frames without --duration");
    for (const CLI::Option* opt : {rates_option, duration_option, crosstalk_option, plan_option})
      if (!frames_for.empty() && opt->count() > 0)
        tp::bad_input(opt->get_name() +
                      ": --frames plays the sequence's stimulus as it was made; give it to "
                      "--sequence");
    // --frames streams: each frame goes to stdout when it is due, for stimctl --live; a file
    // written whole at the end would hold them back until the stream is over.
    if (!frames_for.empty() && app.count("--output") > 0)
      tp::bad_input(
          "--output: --frames writes live frames to stdout as they are due (for "
          "stimctl --live), not a document; pipe them");
    if (!rates.empty()) tp::parse_rates(rates, o.rate_hz);
    const double fps = tp::parse_finite(fps_text, "--fps");
    if (!(fps >= 0.1 && fps <= 1000)) tp::bad_input("--fps: " + fps_text + " outside [0.1, 1000]");
    const bool live_input = images.size() == 1 && images[0] == "-" && !frames_for.empty();
    // The duration as given, never clamped: out of range is refused (check_render_options,
    // and plan_render when it holds no pulse of some pattern).
    o.duration_s = !duration.empty()            ? tp::parse_finite(duration, "--duration")
                   : sequence && images.empty() ? o.limits.max_duration_s
                   : sequence ? tp::sequence_duration_s(images.size(), fps, o.limits)
                              : 1.0;
    o.crosstalk = tp::parse_finite(crosstalk, "--crosstalk");
    o.width_us = tp::parse_finite(width, "--width");
    o.balance_width_us =
        balance.empty() ? o.width_us : tp::parse_finite(balance, "--balance-width");
    tp::check_render_options(o);
    if (sequence && !frames_for.empty()) tp::bad_input("--sequence and --frames: give one");
    if (!sequence && frames_for.empty() && images.size() != 1)
      tp::bad_input(tp::count_text(images.size(), "image") + ": a still image takes one");
    if (!frames_for.empty() && images.empty())
      tp::bad_input("--frames: no frames (images, or - for JSON lines on stdin)");
    int stdin_uses = (bank_path == "-") + (profile_path == "-") + (frames_for == "-");
    for (const std::string& f : images) stdin_uses += f == "-";
    if (stdin_uses > 1) tp::bad_input("- (stdin) given more than once");
    const tp::PixelBank bank = tp::pixel_bank_from_json(tp::read_json(bank_path, "bank"));
    o.limits.max_current_mA = std::min(o.limits.max_current_mA, bank.doc.max_current_mA);
    if (!plan_only && bank.pads() > static_cast<std::size_t>(tp::ranges::max_channels))
      tp::bad_input("bank: " + tp::count_text(bank.pads(), "pad") +
                    ", more than a stimulator drives (" + std::to_string(tp::ranges::max_channels) +
                    "); --plan plans it");
    if (!profile_path.empty() && !comfort_factor.empty())
      tp::bad_input("--comfort-factor: applies without --profile only");
    const double factor = comfort_factor.empty()
                              ? tp::kDefaultComfortFactor
                              : tp::parse_finite(comfort_factor, "--comfort-factor");
    if (!(factor >= 1.1 && factor <= 10))
      tp::bad_input("--comfort-factor: " + comfort_factor + " outside [1.1, 10]");
    std::optional<tp::Profile> given;
    if (!profile_path.empty())
      given = tp::profile_from_json(tp::read_json(profile_path, "profile"), o.limits.max_current_mA,
                                    static_cast<long>(bank.pads()));
    // The images, all read and checked before anything is printed (frames on stdin: as
    // they come, each checked before it is written).  A sequence's frames are kept as
    // SequenceFrames keeps them, so memory does not grow with their number.
    std::vector<tp::PadIntensities> frames;
    tp::SequenceFrames kept(bank.columns, bank.rows);
    std::string note;  // composited transparency, said with the warning
    if (sequence && images.size() == 1 && images[0] == "-") {
      for_each_stdin_frame(
          bank, [&](const tp::PadIntensities& f, const std::string& where) { kept.add(f, where); });
      if (kept.count() == 0) tp::bad_input("--sequence -: no frames on stdin");
    } else if (!live_input) {
      frames = read_images(images, bank, resample, sequence ? &kept : nullptr, note);
    }

    // Without a profile, the model's.
    std::string warning;  // said before the first output, when every input is checked
    const tp::Profile profile = given ? *given : model_profile(bank, o, factor, warning);
    if (sequence && duration.empty() && kept.count() > 0)
      o.duration_s = tp::sequence_duration_s(kept.count(), fps, o.limits);
    if (!frames_for.empty()) {
      const tp::Sequence seq = tp::sequence_from_json(tp::read_json(frames_for, "stimulus"), bank,
                                                      profile, "--frames " + frames_for);
      std::vector<std::vector<double>> out;  // PNG frames: every one checked first
      for (std::size_t k = 0; k < frames.size(); ++k)
        out.push_back(tp::frame_amplitudes(seq, profile, frames[k], images[k]));
      std::fputs((warning + note).c_str(), stderr);
      play_frames(seq, profile, bank, out, live_input, fps);
      return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const tp::RenderPlan plan = sequence ? tp::plan_sequence(bank, profile, kept, o)
                                         : tp::plan_render(bank, profile, frames[0], o);
    const double plan_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (plan.lit.empty())
      tp::bad_input(sequence ? "no frame lights a pixel"
                             : images[0] + ": no pixel is lit (all black)");
    // Before a word is said: every check a device's mix gets (a plan for more pads than a
    // stimulator drives is only a plan, and skips them).
    if (bank.pads() <= static_cast<std::size_t>(tp::ranges::max_channels))
      tp::check_mix(plan.mix, o.limits);
    std::fputs((warning + note).c_str(), stderr);
    const std::string lowered = tp::lowered_text(plan, sequence ? "sequence" : "image");
    if (!lowered.empty()) std::fprintf(stderr, "render-tactile: %s\n", lowered.c_str());
    std::fprintf(stderr, "render-tactile: %s; planned in %s ms\n", tp::plan_summary(plan).c_str(),
                 tp::number_text(std::round(plan_ms * 10) / 10).c_str());
    if (plan_only) {
      tp::cli::write_stdout(tp::dump_json(tp::plan_to_json(plan)));
      return;
    }
    tp::cli::write_stdout(
        tp::dump_json(sequence ? tp::sequence_to_json(plan, bank) : tp::mix_to_json(plan.mix)));
  });
}
