#pragma once
// A person's calibration (issue 23): per primary, the detection threshold and the comfort
// limit (mA) that `calibrate` found, and optionally per pixel (`--per-pixel`).  An intensity
// v in [0, 1] of a primary becomes the current I = threshold + v x (comfort - threshold);
// v = 0 delivers nothing (docs/calibration.md, "The profile").

#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/json.hpp"
#include "model/primaries.hpp"

namespace tp {

struct PrimaryRange {
  double threshold_mA = 0, comfort_mA = 0;
  // What calibrate measured (0: not known): its trials, and each level's spread (mA).
  int trials = 0;
  double threshold_spread_mA = 0, comfort_spread_mA = 0;
  // The fibre model's threshold for the same primary's pattern (calibrate writes it beside
  // the person's, render/model_profile.hpp's pattern at the centre pixel; 0: not known).
  double model_threshold_mA = 0;
  // The fractions of RA, SAI and PC afferents the primary's mode recruits at this comfort
  // limit, by the bank's recruitment (calibrate writes it when the bank has one;
  // render/recruitment.hpp): the mode's colour for this person.  Each in [0, 1].
  std::optional<std::array<double, 3>> colour{};
  // Each pad's impedance (kOhm; 0 where it carried no current) at the threshold's trials,
  // their mean, when calibrate ran on a device that measures (protocol 7); empty: not
  // known.  make-pulse --profile carries it into the stimulus for --hold-sensation.
  std::vector<double> impedance_kohm{};
};

struct Profile {
  std::array<std::optional<PrimaryRange>, 3> primary;  // by kPrimaries' index
  // Per pixel (a pad index), where calibrate measured it: overrides the primary's range.
  std::map<long, std::array<std::optional<PrimaryRange>, 3>> pixel;
  Json carried = Json::object();  // every other key (e.g. the device, the date)
  // The range for a primary at a pixel; bad input naming the primary when it has none.
  const PrimaryRange& range(int primary, long pixel) const;
  // I = threshold + v (comfort - threshold) for v in (0, 1]; 0 for v = 0.
  double current_mA(int primary, long pixel, double v) const;
};

// The current for intensity v in (0, 1] of a stimulus of `mode` (make-pulse --profile,
// mix-stimuli --profile: the profile's range for that primary); bad input naming `what`
// when v is outside (0, 1], the mode is not a primary or the profile has no range for it.
double profile_amplitude_mA(const Profile& p, const std::string& mode, double v,
                            const std::string& what);

// The least threshold a profile may give (calibrate's floor, psych/staircase.hpp: 1 uA,
// about one DAC step).
inline constexpr double kMinProfile_mA = 0.001;

inline constexpr const char* kProfileFormat = "tactile-primaries/profile/1";

// Reads and checks a profile: the format, each range's threshold in [0.001, max_current_mA]
// and comfort in [threshold, max_current_mA], the counts and spreads not negative, pixels
// as pad indices below `pads`.  Bad input naming the field at fault.
Profile profile_from_json(const Json& j, double max_current_mA, long pads);

// A profile calibrated on an array carries its columns and rows (calibrate writes them):
// it fits only an array of as many pads, and of that grid where the other side has one
// (grid: its columns and rows; nullopt: a count of pads alone).  Bad input
// "profile: calibrated on an array of {...}, " + theirs ("the bank's is 8 x 8").  A
// profile that carries no array fits any.
void check_profile_fits(const Profile& p, std::size_t pads,
                        const std::optional<std::pair<int, int>>& grid, const std::string& theirs);
Json profile_to_json(const Profile& p);

}  // namespace tp
