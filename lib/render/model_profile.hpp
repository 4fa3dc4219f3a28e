#pragma once
// The profile before anyone is calibrated (render-tactile without --profile): each
// primary's threshold from the fibre model (fiber-threshold) for its pattern at the pixel
// nearest the array's centre, and a comfort limit a fixed factor above it
// (docs/rendering.md, "Without a profile").  A stand-in, said so on stderr: people's
// thresholds differ from the model's and from one another's; calibrate measures them.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "fibre/models.hpp"
#include "fibre/report.hpp"
#include "psych/profile.hpp"
#include "io/bank.hpp"

namespace tp {

// Comfort = kDefaultComfortFactor x threshold (at most the current limit).  An assumption,
// not a measurement: electrotactile "dynamic range" (maximal current without discomfort over
// sensation threshold; Kaczmarek, Webster & Radwin 1992) is narrow and varies between people
// and sites; 2 is a conservative choice (docs/rendering.md, "Without a profile").
inline constexpr double kDefaultComfortFactor = 2.0;

struct ModelProfileOptions {
  std::string fibre_model = "mrg";
  tp::PulseSpec pulse;                         // the rendered pulse
  double comfort_factor = kDefaultComfortFactor;  // 1.1 to 10
  double max_current_mA = 2.0;
};

struct ModelProfile {
  Profile profile;                                     // per primary the bank has
  std::array<long, 3> pixel = {-1, -1, -1};            // the pad whose pattern gave each threshold
  std::array<bool, 3> capped = {false, false, false};  // comfort held at the current limit
};

// The feasible pattern of a primary nearest the array's centre pad (the lowest index of a
// tie): its pad; -1 when the bank has the mode but no feasible pattern of it, kNoMode when
// the bank has no such mode.
inline constexpr long kNoMode = -2;
long centre_pattern(const PixelBank& bank, std::size_t primary);

// The model's threshold of a bank pattern's target: the primary's receptor as the setup
// has it, its fibre through the pattern's peak, searched up to max_mA; why none, if none.
struct PatternThreshold {
  std::optional<double> threshold_mA;
  std::string reason;
};
PatternThreshold pattern_threshold(const PixelBank& bank, long pad, std::size_t primary,
                                   const fibre::FibreModel& model, const PulseSpec& pulse,
                                   double max_mA);

// Each primary's model threshold beside the person's (calibrate's profile): its pattern
// nearest the centre (centre_pattern), under the fibre model and pulse, searched up to
// max_mA, in each primary-wide range the profile has (per-pixel ranges are left without).
// Returns a note for each primary the model gives no threshold (none: every one known).
std::vector<std::string> add_model_thresholds(Profile& profile, const PixelBank& bank,
                                              const std::string& fibre_model,
                                              const PulseSpec& pulse, double max_mA);

// Bad input naming the primary when the model gives it no threshold within the current
// limit (or none of its patterns is feasible), or comfort_factor is outside [1.1, 10].
ModelProfile model_profile(const PixelBank& bank, const ModelProfileOptions& o);

}  // namespace tp
