#include "requests/mix.hpp"

#include "core/error.hpp"
#include "core/text.hpp"

namespace tp {

void check_mix_inputs(const std::vector<std::string>& names) {
  if (names.size() > device::kMaxPatterns)
    bad_input(std::to_string(names.size()) + " inputs, more than a device holds (" +
              std::to_string(device::kMaxPatterns) + " patterns)");
  int stdin_uses = 0;
  for (const std::string& f : names) stdin_uses += f == "-";
  if (stdin_uses > 1) bad_input("- (stdin) given more than once");
}

void add_mix_input(MixRequest& r, const std::string& name, const Mix& document) {
  if (!document.single()) bad_input(name + ": already a mix; give its parts");
  r.names.push_back(name);
  r.patterns.push_back(document.patterns[0]);
}

void check_mix_intensities(const MixRequest& r, bool intensities_given, bool profile_given,
                           bool profile_on_stdin) {
  if (intensities_given != profile_given)
    bad_input("--intensities and --profile: give both, or neither");
  if (!intensities_given) return;
  bool stdin_input = false;
  for (const std::string& f : r.names) stdin_input = stdin_input || f == "-";
  if (profile_on_stdin && stdin_input) bad_input("--profile -: stdin is an input");
  if (r.intensities && r.intensities->size() != r.patterns.size())
    bad_input("--intensities: " + std::to_string(r.intensities->size()) + " for " +
              std::to_string(r.patterns.size()) + " inputs");
}

namespace {

// Each pattern at its intensity of the person's range for its mode.
void rescale(std::vector<Stimulus>& patterns, const MixRequest& r) {
  const std::vector<double>& v = *r.intensities;
  for (std::size_t i = 0; i < v.size(); ++i) {
    Stimulus& s = patterns[i];
    const std::string& what = r.names[i];
    if (!s.carried.contains("mode") || !s.carried["mode"].is_string())
      bad_input(what + ": names no mode (make-pulse carries optimize-weights' mode)");
    if (!(s.amplitude_mA > 0)) bad_input(what + ": no amplitude_mA to rescale");
    check_profile_fits(*r.profile, s.currents_mA.size(), std::nullopt,
                       what + "'s is " + count_text(s.currents_mA.size(), "channel"));
    const double a = profile_amplitude_mA(*r.profile, s.carried["mode"].get<std::string>(), v[i],
                                          what + ": --intensities");
    for (double& c : s.currents_mA) c *= a / s.amplitude_mA;
    s.amplitude_mA = a;
  }
}

// The phases given, or staggered: no two first pulses fall due together.
void place(Mix& mix, const std::optional<std::vector<double>>& phases_us) {
  if (phases_us) {
    const std::vector<double>& p = *phases_us;
    if (p.size() != mix.patterns.size())
      bad_input("--phase: " + std::to_string(p.size()) + " phases for " +
                std::to_string(mix.patterns.size()) + " patterns");
    for (std::size_t i = 0; i < p.size(); ++i) mix.patterns[i].phase_us = p[i];
    return;
  }
  double t = 0;
  for (Stimulus& s : mix.patterns) {
    s.phase_us = t < s.shape.period_us() ? t : 0;
    t += s.shape.length_us() + mix.gap_us;
  }
}

}  // namespace

Mix run_mix(const MixRequest& r) {
  check_mix_inputs(r.names);
  if (r.names.size() != r.patterns.size())
    bad_input(std::to_string(r.names.size()) + " names for " + std::to_string(r.patterns.size()) +
              " inputs");
  check_mix_intensities(r, r.intensities.has_value(), r.profile.has_value(), false);
  Mix mix;
  mix.gap_us = r.gap_us;
  mix.patterns = r.patterns;
  if (r.intensities) rescale(mix.patterns, r);
  place(mix, r.phases_us);
  check_mix(mix, StimulusLimits{});
  return mix;
}

}  // namespace tp
