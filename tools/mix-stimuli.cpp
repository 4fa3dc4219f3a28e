// mix-stimuli: several stimulus documents (make-pulse's) as one, whose patterns the device
// interleaves, each at its own rate and amplitude.
//
//   optimize-weights --mode RA | make-pulse --amplitude 0.8 --frequency 30 > ra-stimulus.json
//   optimize-weights --mode SAI | make-pulse --amplitude 1.2 --frequency 200 > sai-stimulus.json
//   mix-stimuli ra-stimulus.json sai-stimulus.json | stimctl --port emu --duration 2

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "core/number.hpp"
#include "core/text.hpp"
#include "pulse/mix.hpp"
#include "psych/profile.hpp"
#include "requests/mix.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Reads stimulus documents (make-pulse's JSON; - for stdin, at most once) and prints one "
      "stimulus of their patterns, which the device interleaves: pulses in the order of their "
      "slots, never overlapping, each deferred at most 1 ms behind another's.  Checked as a "
      "whole before anything is printed: every pattern as a stimulus, one channel count, and "
      "per electrode the RMS and mean currents summed over the patterns (docs/safety.md), "
      "the time the pulses and gaps need, and the longest deferral (docs/protocol.md).",
      "mix-stimuli"};
  std::vector<std::string> inputs;
  std::string gap = "100", phases, intensities, profile_path;
  app.add_option("inputs", inputs, "Stimulus documents, in pattern order (1 to 256)")
      ->required()
      ->type_name("FILE");
  app.add_option("--gap", gap,
                 "Least time between pulses of different patterns, us, 100 to 1000 [100]")
      ->type_name("US");
  app.add_option("--intensities", intensities,
                 "Instead of each input's amplitude: 0 to 1 of the person's range for its mode, "
                 "comma-separated, one per input (needs --profile)")
      ->type_name("V,...");
  app.add_option("--profile", profile_path,
                 "The person's calibration (calibrate): intensity v is threshold + v (comfort "
                 "- threshold) mA")
      ->type_name("FILE");
  app.add_option("--phase", phases,
                 "Each pattern's first pulse after the start, us, comma-separated, each below "
                 "its period [staggered: each after the previous patterns' pulses and gaps]")
      ->type_name("US,...");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    tp::check_mix_inputs(inputs);
    tp::MixRequest r;
    r.gap_us = tp::parse_finite(gap, "--gap");
    for (const std::string& f : inputs)
      tp::add_mix_input(r, f, tp::mix_from_json(tp::read_json(f, "stimulus")));
    const auto check_intensities = [&] {
      tp::check_mix_intensities(r, !intensities.empty(), !profile_path.empty(),
                                profile_path == "-");
    };
    check_intensities();
    if (!intensities.empty()) {
      r.intensities = tp::parse_list(intensities, "--intensities");
      check_intensities();  // one per input
      r.profile = tp::profile_from_json(tp::read_json(profile_path, "profile"),
                                        tp::StimulusLimits{}.max_current_mA,
                                        std::numeric_limits<long>::max());
    }
    if (!phases.empty()) r.phases_us = tp::parse_list(phases, "--phase");
    const tp::Mix mix = tp::run_mix(r);
    const tp::MixFigures f = tp::mix_figures(mix);
    double rms = 0, mean = 0;
    for (double v : f.rms_current_mA) rms = std::max(rms, v);
    for (double v : f.mean_current_mA) mean = std::max(mean, v);
    std::fprintf(stderr,
                 "mix-stimuli: %s on %zu channels, %s s; per electrode at most RMS %s "
                 "mA, mean %s mA; pulses and gaps %s %% of the time, deferral at most %s us\n",
                 tp::count_text(mix.patterns.size(), "pattern").c_str(),
                 mix.patterns[0].currents_mA.size(),
                 tp::number_text(mix.duration_s()).c_str(), tp::number_text(rms).c_str(),
                 tp::number_text(mean).c_str(),
                 tp::number_text(std::round(f.utilisation * 1000) / 10).c_str(),
                 tp::number_text(f.worst_slip_us).c_str());
    tp::cli::write_stdout(tp::dump_json(tp::mix_to_json(mix)));
  });
}
