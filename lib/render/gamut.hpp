#pragma once
// The tactile gamut (issue 40, item 4): each mode's colour is the fractions of RA, SAI and
// PC afferents it recruits at full intensity, and a mix of modes at intensities x in
// [0, 1] is predicted to recruit sum_M x_M colour_M.  A requested colour (R, G, B) =
// (RA, SAI, PC) maps to the intensities whose predicted recruitment is nearest in the
// least-squares sense: non-negative least squares, bounded above by full intensity.  A
// colour inside the gamut (a mix some intensities make) is met exactly; one outside it, as
// nearly as any intensities can.
//
// With three modes the problem is solved exactly by its active sets: each mode at 0, at 1
// or free, 27 faces of the cube, each an unconstrained least-squares problem on its free
// modes; the problem is convex, so the feasible face solution of least residual is the
// optimum.  Deterministic: ties go to the first face in a fixed order.

#include <array>
#include <cstddef>

namespace tp {

inline constexpr std::size_t kGamutModes = 3;    // RA, SAI, PC modes
inline constexpr std::size_t kGamutClasses = 3;  // RA, SAI, PC afferents

// colour[m][k]: the fraction of class k that mode m recruits at full intensity, in [0, 1].
using GamutColours = std::array<std::array<double, kGamutClasses>, kGamutModes>;
using Rgb = std::array<double, kGamutClasses>;

struct GamutAnswer {
  std::array<double, kGamutModes> intensity{};  // each in [0, 1]
  Rgb predicted{};                              // sum_m intensity[m] colour[m]
  double error = 0;                             // |predicted - requested| (Euclidean)
};

// The intensities whose predicted recruitment is nearest the requested colour.
GamutAnswer nearest_in_gamut(const GamutColours& colours, const Rgb& requested);

}  // namespace tp
