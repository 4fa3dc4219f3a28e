#pragma once
// mix-stimuli's work, for the program and the Python module alike (docs/programs.md,
// mix-stimuli): stimulus documents (make-pulse's) become one mix of their patterns, each
// optionally rescaled to an intensity of the person's range, each given its phase.  Bad
// input names the program's flags.

#include <optional>
#include <string>
#include <vector>

#include "pulse/mix.hpp"
#include "psych/profile.hpp"

namespace tp {

struct MixRequest {
  // The inputs, in pattern order: each one stimulus (a pattern), and its name as the user
  // gave it (a file, or - for stdin), which the messages quote.
  std::vector<std::string> names;
  std::vector<Stimulus> patterns;
  double gap_us = 100.0;  // least time between pulses of different patterns, 100 to 1000
  // Instead of each input's amplitude: 0 to 1 of the person's range for its mode, one per
  // input, with the profile (both, or neither).
  std::optional<std::vector<double>> intensities;
  std::optional<Profile> profile;
  // Each pattern's first pulse after the start, us, one per pattern [staggered].
  std::optional<std::vector<double>> phases_us;
};

// The input names, before any is read: at most a device's patterns, - at most once.
void check_mix_inputs(const std::vector<std::string>& names);

// One input's document, read: a stimulus, not already a mix ("NAME: already a mix").
void add_mix_input(MixRequest& r, const std::string& name, const Mix& document);

// --intensities and --profile, before the profile is read: both or neither, the profile
// not on stdin when an input is, and one intensity per input.
void check_mix_intensities(const MixRequest& r, bool intensities_given, bool profile_given,
                           bool profile_on_stdin);

// The checks, then the mix: rescaled, phased (or staggered: each pattern's first pulse
// after the previous patterns' pulses and gaps) and checked against the limits as a whole.
Mix run_mix(const MixRequest& r);

}  // namespace tp
