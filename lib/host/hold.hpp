#pragma once
// stimctl --hold-sensation (issue 41, item 6; docs/skin.md, "Sensation held"): each
// pattern's pulse energy, sum over its pads of Z I^2 T, held at what it was when the
// person's threshold was measured, as the skin's impedance changes (Tachi, Tanie and Abe,
// Jpn. J. Med. Electron. Biol. Eng. 15(5):315-320, 1977: pulses of equal I^2 T feel
// equally strong for T < 1 ms, and the sensation follows the pulse's energy, the integral
// of Z I^2).  The device (protocol 7, set_hold) scales each pulse by sqrt(E_ref / E_now)
// from its last readings; the host uploads each pattern at a checked ceiling above its
// amplitude, so that the law can raise the current (sweat) as well as lower it (a pad
// peeling), and never beyond what was checked.

#include <cstdint>
#include <vector>

#include "pulse/mix.hpp"

namespace tp::host {

// The most the law may raise a pattern's current: twice its amplitude (a fourfold fall of
// the impedance), less where the limits leave less room.
inline constexpr double kHoldHeadroom = 2.0;

// The mix to upload: each pattern's currents and amplitude raised by the largest factor in
// [1, kHoldHeadroom] that passes check_mix against lim (every pattern by the same factor),
// and the starting amplitudes the original ones.  Bad input naming the pattern and channel
// when a driven channel has no reference impedance.
Mix hold_ceiling(const Mix& m, const StimulusLimits& lim, double* headroom = nullptr);

// set_hold's energy_ref for a pattern's codes as uploaded and its reference impedances
// (kOhm): sum over its channels of min(Z, kHoldMaxOhm) / kHoldOhmUnit x code^2.
std::uint64_t hold_energy(const std::vector<std::int16_t>& codes,
                          const std::vector<double>& reference_kohm);

}  // namespace tp::host
