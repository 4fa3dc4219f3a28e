#pragma once
// make-pulse's work, for the program and the Python module alike: a weights document and a
// pulse become a checked stimulus (docs/programs.md, make-pulse).

#include <optional>

#include "io/document.hpp"
#include "pulse/stimulus.hpp"
#include "psych/profile.hpp"

namespace tp {

struct PulseRequest {
  // The amplitude (mA on an electrode of |w| = 1), or an intensity (0, 1] of the person's
  // range for the document's mode (with a profile): exactly one.
  std::optional<double> amplitude_mA;
  std::optional<double> intensity;
  std::optional<Profile> profile;
  double frequency_hz = 200.0;
  double width_us = 200.0;
  std::optional<double> balance_width_us;  // [width_us]
  double interphase_us = 0.0;
  // The length: a pulse count, or a duration (s; [1]); not both.
  std::optional<long> count;
  std::optional<double> duration_s;
};

// Bad input, naming the option as make-pulse's flag (--amplitude, --frequency, ...), when
// the document has no weights or more channels than a stimulator drives, when the request
// is not one of amplitude or intensity-with-profile, or when the stimulus breaks a limit
// (check_stimulus).  Carries the document's mode and thresholds.
Stimulus make_stimulus(const Document& doc, const PulseRequest& r);

}  // namespace tp
