#pragma once
// The tactile gamut's colours (issue 40, item 4; docs/rendering.md, "The gamut"): each
// mode's recruitment, the fractions of RA, SAI and PC afferents its pattern recruits, is the
// mode's true colour.  optimize-weights --bank --population N samples it once per mode (the
// bank carries it); render-tactile reads each mode's colour at the person's threshold and at
// full intensity, and maps every requested (R, G, B) = (RA, SAI, PC) to the mode intensities
// whose predicted recruitment comes nearest (render/gamut.hpp), saying how many pixels fell
// outside.
//
// A person's currents are not the model's: a current I of primary M is read in multiples of
// the person's threshold there, I / threshold_M, at the model's reference (the target's model
// threshold, as the profile without calibration takes it): the colour at I is the fractions
// recruited at reference_M x I / threshold_M.  A mode on is predicted affine in its
// intensity, from its colour at threshold to its colour at full intensity, as the plan's
// current is; a mix of modes as the sum of theirs: approximations the docs state
// (recruitment grows in steps with the current, and two modes may recruit the same fibre).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "io/bank.hpp"
#include "psych/profile.hpp"
#include "pulse/thresholds.hpp"
#include "render/gamut.hpp"
#include "render/image.hpp"

namespace tp {

struct RecruitmentOptions {
  std::size_t per_class = 30;  // afferents of each class, 1 to 1000
  std::uint64_t seed = 1;
  std::string fibre_model = "mrg";
  PulseSpec pulse;             // render-tactile's default pulse: 200 us biphasic
  double max_mA = 10;          // an afferent not firing below this is not recruited
  unsigned threads = 0;        // 0: every core
  // Called as each afferent's search ends (one call at a time): done, total.
  std::function<void(std::size_t done, std::size_t total)> progress;
};

// Each mode's recruitment at its pattern nearest the array's centre (render/model_profile's
// centre_pattern): afferents of each class sampled over the pitch around that pad (x and z),
// each one's threshold.  A mode the bank has with no feasible pattern, or whose target has no
// model threshold below max_mA, is left out, and `omitted` (when given) gains a line saying
// why.  Bad input for a population out of range.
BankRecruitment bank_recruitment(const PixelBank& bank, const RecruitmentOptions& o,
                                 std::vector<std::string>* omitted = nullptr);

// optimize-weights' line on stderr: each mode's fractions at twice its reference (the
// profile without calibration's full intensity), "recruitment, 30 afferents a class about
// each mode's centre pixel, at 2 x its threshold: RA mode RA 0.40 SAI 0.97 PC 0.53; ...".
std::string recruitment_note(const BankRecruitment& r);

// Each primary-wide range of the profile gains its colour (calibrate, with a bank that
// carries recruitment; per-pixel ranges are read at render time).
void add_colours(Profile& profile, const BankRecruitment& r);

// The modes' colours at a pad for a profile: at full intensity, the range's own colour where
// it carries one (calibrate's), else mode M's fractions at reference_M x comfort_M /
// threshold_M (the profile's range for M there); at onset (the person's threshold), its
// fractions at reference_M.  Zero for a mode without recruitment or without a range in the
// profile.
GamutModes gamut_modes(const BankRecruitment& r, const Profile& profile, long pad);

// A requested colour is outside the gamut when the nearest prediction misses it by more
// than half an 8-bit step (the image's resolution).
inline constexpr double kGamutTolerance = 0.5 / 255.0;

struct GamutReport {
  std::size_t frames = 0;     // a sequence's frames mapped (0: a still)
  std::size_t requested = 0;  // pixels asking for anything (over every frame)
  std::size_t outside = 0;    // of them, outside the gamut
  double max_error = 0, mean_error = 0;  // over the requested pixels
  std::vector<double> error;  // per pad (0 where nothing was asked; a sequence's: the most)
  GamutModes centre;          // the colours at the array's centre pad
};

// Replaces each pad's requested colour by the mode intensities nearest it (nearest_in_gamut
// with that pad's colours: gamut_modes, none for a mode with no feasible pattern there),
// and says how near they came.  The bank must carry its recruitment.
GamutReport map_to_gamut(const PixelBank& bank, const Profile& profile, PadIntensities& image);

// Why mapping into the gamut lit no pixel of the image: "3 pixels ask for colour, and the
// nearest the modes come to each is nothing (RA: the bank's recruitment has no RA mode; PC:
// the profile has no range for PC)", naming each mode that cannot be driven, or saying that
// off is nearer than any mix.
std::string unlit_by_gamut(const PixelBank& bank, const Profile& profile, const GamutReport& g);

// A note when the render's pulse is not the one the recruitment was sampled with (the
// colours are that pulse's), else "".
std::string recruitment_pulse_note(const BankRecruitment& r, const PulseSpec& render_pulse);

// A sequence's frame mapped as a still's image (map_to_gamut), its report added to the
// sequence's: counts summed, the errors' maximum per pad and overall, their mean over every
// pixel asked for in every frame.
void map_frame(const PixelBank& bank, const Profile& profile, PadIntensities& frame,
               GamutReport& tally);

// The output's "gamut" field, and the stderr line: "gamut: 3 of 16 pixels asked for outside
// the modes' gamut (error up to 0.41, mean 0.12, in fractions recruited)".
Json gamut_to_json(const GamutReport& g);
std::string gamut_summary(const GamutReport& g);

}  // namespace tp
