// render-tactile: a tactile image (R = RA, G = SAI, B = PC) on a 2-D array, at the
// intensities a person's profile gives, as one stimulus of patterns the device interleaves.
//
//   optimize-weights --bank --grid 8x8 --pitch 2 --pad 1x1 --neighbourhood 3 > bank.json
//   render-tactile --bank bank.json --profile profile.json --duration 2 picture.png
//     | stimctl --port emu --emu-channels 64   (one line)

#include <cmath>
#include <cstdio>
#include <string>

#include "cli/entry.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "render/request.hpp"
#include "runs/frame_playback.hpp"

namespace {

// "render-tactile: warning: ...", a line, for a warning (none for none).
std::string warning_text(const std::string& warning) {
  return warning.empty() ? "" : "render-tactile: warning: " + warning + "\n";
}

// The options whose use is checked against one another: whether each was given.
struct Given {
  CLI::Option *rates = nullptr, *duration = nullptr, *crosstalk = nullptr, *plan = nullptr,
              *fps = nullptr;
};

void declare_flags(CLI::App& app, tp::RenderSpec& f, Given& given) {
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
  given.rates = app.add_option("--rates", f.rates,
                                  "Requested rate per primary, each once, Hz, 0.1 to 1000 "
                                  "[RA:30,SAI:200,PC:250]")
                       ->type_name("P:HZ,...");
  given.duration =
      app.add_option("--duration", f.duration,
                     "Seconds, (0, 3600], at least one period of every pattern, never clamped [a "
                     "still image: 1; a sequence: its frames and one more frame period at --fps, "
                     "or 3600 for frames on stdin]")
          ->type_name("S");
  given.crosstalk =
      app.add_option("--crosstalk", f.crosstalk,
                     "Largest crosstalk between patterns that fire together, 0 to 1 [0.1]")
          ->type_name("X");
  app.add_option("--width", f.width, "Main phase, us, whole, 10 to 1000 [200]")->type_name("US");
  app.add_option("--balance-width", f.balance,
                 "Balancing phase, us, whole, from --width to 8000 [--width]")
      ->type_name("US");
  app.add_flag("--resample", f.resample,
               "Resample an image of another size to the array's (area-weighted)");
  given.plan =
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
  given.fps = app.add_option("--fps", f.fps,
                                "Frames per second (--sequence, --frames), 0.1 to 1000 [30]")
                     ->type_name("FPS");
  tp::cli::add_output_option(app);
}

// "render-tactile: note: ...", a line, for a note (none for none).
std::string note_text(const std::string& note) {
  return note.empty() ? "" : "render-tactile: note: " + note + "\n";
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
  tp::RenderSpec f;
  Given given;
  declare_flags(app, f, given);

  return tp::cli::run(app, argc, argv, [&] {
    f.rates_given = given.rates->count() > 0;
    f.duration_given = given.duration->count() > 0;
    f.crosstalk_given = given.crosstalk->count() > 0;
    f.plan_given = given.plan->count() > 0;
    f.fps_given = given.fps->count() > 0;
    f.output_given = app.count("--output") > 0;
    tp::RenderRequest r = tp::render_request(f);
    const tp::PixelBank bank = tp::pixel_bank_from_json(tp::read_json(f.bank_path, "bank"));
    tp::fit_spec_to_bank(f, bank, r);
    const tp::RenderImages images = tp::render_images(f, bank, r, [&](const tp::FrameSink& sink) {
      tp::runs::for_each_frame_line(0, bank, sink);
    });
    if (!f.frames_for.empty()) {
      tp::FramesToPlay play = tp::frames_to_play(f, r, bank, images.frames);
      std::fputs((warning_text(play.profile.warning) + note_text(images.note)).c_str(), stderr);
      const std::size_t n = tp::runs::play_frames(
          {play.sequence, play.profile.profile, bank, r.fps, play.gamut ? &*play.gamut : nullptr},
          play.amplitudes, tp::images_from_stdin(f) ? 0 : -1,
          [](const std::string& line) { tp::cli::write_stdout(line); });
      // Said once the frames are played (a frame refused on the way gets its one line).
      std::fputs(note_text(play.gamut_note).c_str(), stderr);
      if (play.gamut)
        std::fprintf(stderr, "render-tactile: %s\n", tp::gamut_summary(*play.gamut).c_str());
      std::fprintf(stderr, "render-tactile: %s\n", tp::runs::playback_summary(n, r.fps).c_str());
      return;
    }
    const tp::RenderResult out = tp::run_render(r, bank);
    std::fputs((warning_text(out.warning) + note_text(images.note)).c_str(), stderr);
    std::fputs(note_text(out.gamut_note).c_str(), stderr);
    if (out.gamut)
      std::fprintf(stderr, "render-tactile: %s; mapped in %s ms\n",
                   tp::gamut_summary(*out.gamut).c_str(),
                   tp::number_text(std::round(out.gamut_ms * 100) / 100).c_str());
    if (!out.lowered.empty()) std::fprintf(stderr, "render-tactile: %s\n", out.lowered.c_str());
    std::fprintf(stderr, "render-tactile: %s; planned in %s ms\n",
                 tp::plan_summary(out.plan).c_str(),
                 tp::number_text(std::round(out.plan_ms * 10) / 10).c_str());
    tp::cli::write_stdout(tp::dump_json(out.document));
  });
}
