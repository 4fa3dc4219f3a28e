#pragma once
// A rendering's options (render-tactile's flags, docs/rendering.md): the rates requested
// per primary, the pulse, the crosstalk bound, the duration and the limits; their parsers
// and checks, whose messages name the flags.

#include <array>
#include <string>
#include <vector>

#include "pulse/stimulus.hpp"

namespace tp {

struct RenderOptions {
  std::array<double, 3> rate_hz = {30.0, 200.0, 250.0};  // requested, per primary
  double width_us = 200.0, interphase_us = 0.0, balance_width_us = 200.0;
  double crosstalk = 0.1;  // the bound for firing together, [0, 1]
  double duration_s = 1.0;
  double gap_us = device::hard::min_gap_us;
  StimulusLimits limits;
  // Each electrode's RMS and mean current are planned to this share of their limits,
  // leaving room for the DAC's rounding.
  double load_margin = 0.99;
  unsigned threads = 0;  // for the fields and the conflicts, 0: every core
};
// "RA:30,SAI:200,PC:250" (any of them, each once; the others keep theirs) into rate_hz, by
// kPrimaries' index; bad input naming --rates.
void parse_rates(const std::string& text, std::array<double, 3>& rate_hz);
// "RA,PC": kPrimaries' indices in that order; bad input naming `what`.
std::vector<int> parse_primaries(const std::string& text, const std::string& what);

// Checks each option's range (docs/rendering.md); bad input naming it.  A duration is
// also checked against the plan: it must hold one pulse of every pattern (plan_render).
void check_render_options(const RenderOptions& o);

// One slot of the frame: the pulse's phases and the gap after it, us.
inline double slot_us(const RenderOptions& o) {
  return o.width_us + o.interphase_us + o.balance_width_us + o.gap_us;
}

}  // namespace tp
