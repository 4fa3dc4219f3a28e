#pragma once
// The pulse train a person is given per primary (render-tactile's and calibrate's --rates,
// --width, --interphase and --balance-width): its checks, whose messages name those flags.

#include <array>

#include "pulse/stimulus.hpp"

namespace tp {

// Each primary's rate within the limits' frequencies, and whole-microsecond phases: width
// [min_width_us, max_width_us], interphase [0, 1000], balance [width, max_balance_width_us]
// (docs/rendering.md).  Bad input naming the flag.
void check_pulse_train(const std::array<double, 3>& rate_hz, double width_us, double interphase_us,
                       double balance_width_us, const StimulusLimits& limits);

// A whole number of microseconds within [lo, hi]; bad input "FLAG: V us is not a whole
// number in [lo, hi] us".
void check_whole_us(double value_us, double lo, double hi, const char* flag);

}  // namespace tp
