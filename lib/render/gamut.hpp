#pragma once
// The tactile gamut (issue 40, item 4): each mode's colour is the fractions of RA, SAI and
// PC afferents it recruits.  The plan drives a mode off (intensity 0) or from the person's
// threshold up (v in (0, 1] is threshold + v (comfort - threshold)), so a mode's predicted
// colour is affine in v where it is on: onset_M + v (full_M - onset_M), with onset_M its
// colour at threshold and full_M at full intensity; off, it is nothing.  A mix of modes is
// predicted as the sum of theirs.  A requested colour (R, G, B) = (RA, SAI, PC) maps to the
// intensities whose prediction is nearest in the least-squares sense.  A colour inside the
// gamut (a mix some intensities make) is met exactly; one outside it, as nearly as any
// intensities can.  With every onset zero this is non-negative least squares bounded by
// full intensity.
//
// Solved exactly by enumeration: each set of modes that is on (8), and within it each face
// of the cube of their intensities (each at 0, at 1 or free), an unconstrained least-squares
// problem on the free modes; within one set of modes the problem is convex, so the feasible
// face solution of least residual is that set's optimum, and the least over the sets is the
// answer.  64 small problems in all (all off, and 63 faces).  Deterministic: ties go to the
// first set in bitmask order (every subset before its supersets), then the first face.

#include <array>
#include <cstddef>

namespace tp {

inline constexpr std::size_t kGamutModes = 3;    // RA, SAI, PC modes
inline constexpr std::size_t kGamutClasses = 3;  // RA, SAI, PC afferents

// colour[m][k]: the fraction of class k that mode m recruits, in [0, 1].
using GamutColours = std::array<std::array<double, kGamutClasses>, kGamutModes>;
using Rgb = std::array<double, kGamutClasses>;

// Each mode's colour at its threshold (the least the plan drives when it is on) and at full
// intensity.  A mode that cannot be driven has both zero.
struct GamutModes {
  GamutColours onset{};
  GamutColours full{};
};

// The intensity an answer gives a mode that is on at its threshold: more than 0 (the plan's
// off), and within a part in 10^9 of the threshold's current.
inline constexpr double kLeastOn = 1e-9;

struct GamutAnswer {
  std::array<double, kGamutModes> intensity{};  // 0 (off), or in [kLeastOn, 1]
  Rgb predicted{};  // sum over modes on of onset + intensity (full - onset)
  double error = 0;  // |predicted - requested| (Euclidean)
};

// The prediction of intensities (0: off).
Rgb predicted_colour(const GamutModes& modes, const std::array<double, kGamutModes>& intensity);

// The intensities whose predicted recruitment is nearest the requested colour.
GamutAnswer nearest_in_gamut(const GamutModes& modes, const Rgb& requested);

}  // namespace tp
