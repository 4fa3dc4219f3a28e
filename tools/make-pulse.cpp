// make-pulse: turn a weights document into a checked, charge-balanced biphasic stimulus.
//
//   optimize-weights --mode SAI | make-pulse --amplitude 1 --frequency 200 --duration 1 | stimctl
//   --port emu optimize-weights --mode SAI | make-pulse --amplitude 1 --format csv |
//   scripts/plot-pulse -o pulse.png

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "cli/entry.hpp"
#include "core/error.hpp"
#include "fibre/report.hpp"
#include "io/csv.hpp"
#include "io/document.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "requests/pulse.hpp"
#include "pulse/stimulus.hpp"
#include "psych/profile.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Reads a weights document (optimize-weights' JSON) on stdin and prints a stimulus "
      "document for stimctl: every channel gets the same biphasic pulse times its weight "
      "(positive = cathodic main phase), balanced to zero net charge.  Every limit is "
      "checked first: peak current, zero sum at every instant, charge balance, width, rate.",
      "make-pulse"};
  std::string input = "-", amplitude, frequency = "200", width = "200", balance_width,
              interphase = "0", duration, count, format = "json", csv_pulses = "3", intensity,
              profile;
  app.add_option("--input", input, "Weights document, - for stdin [-]")->type_name("FILE");
  auto* o_amp =
      app.add_option("--amplitude", amplitude,
                     "Current of a channel with |weight| = 1, mA, at most 2 (and the document's "
                     "limit)")
          ->type_name("MA");
  auto* o_int = app.add_option("--intensity", intensity,
                               "Instead of --amplitude: 0 to 1 of the person's range for the "
                               "document's mode (needs --profile)")
                    ->type_name("V");
  app.add_option("--profile", profile,
                 "The person's calibration (calibrate): --intensity v is threshold + v (comfort "
                 "- threshold) mA")
      ->type_name("FILE");
  o_amp->excludes(o_int);
  app.add_option("--frequency", frequency,
                 "Pulse rate, Hz, 0.1 to 1000 [200; the paper: 200 for SAI, < 100 for RA]")
      ->type_name("HZ");
  app.add_option("--width", width, "Main phase width, us, 10 to 1000 [200]")->type_name("US");
  app.add_option("--balance-width", balance_width,
                 "Balancing phase width, us; longer than --width makes it lower, same charge "
                 "[= --width: symmetric]")
      ->type_name("US");
  app.add_option("--interphase", interphase, "Gap between the phases, us [0]")->type_name("US");
  auto* o_d = app.add_option("--duration", duration, "Stimulus length, s, at most 3600 [1]")
                  ->type_name("S");
  auto* o_c =
      app.add_option("--count", count, "Number of pulses (instead of --duration)")->type_name("N");
  o_d->excludes(o_c);
  app.add_option("--format", format, "json (stimulus document) or csv (waveform corners) [json]")
      ->check(CLI::IsMember({"json", "csv"}));
  app.add_option("--csv-pulses", csv_pulses, "Pulses drawn by --format csv [3]")->type_name("N");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    const tp::Document doc = tp::document_from_json(tp::read_json(input, "weights document"));
    tp::PulseRequest r;
    if (input == "-" && profile == "-") tp::bad_input("--profile -: stdin carries the weights");
    if (!amplitude.empty()) r.amplitude_mA = tp::parse_finite(amplitude, "--amplitude");
    if (!intensity.empty()) r.intensity = tp::parse_finite(intensity, "--intensity");
    if (!profile.empty() && r.intensity && !r.amplitude_mA && doc.weights)
      r.profile = tp::profile_from_json(tp::read_json(profile, "profile"), doc.max_current_mA,
                                        std::numeric_limits<long>::max());
    else if (!profile.empty() && r.amplitude_mA)
      tp::bad_input("give --amplitude MA, or --intensity V with --profile");
    else if (!profile.empty() && !r.intensity)
      tp::bad_input("--profile: needs --intensity");
    r.frequency_hz = tp::parse_finite(frequency, "--frequency");
    r.width_us = tp::parse_finite(width, "--width");
    if (!balance_width.empty())
      r.balance_width_us = tp::parse_finite(balance_width, "--balance-width");
    r.interphase_us = tp::parse_finite(interphase, "--interphase");
    if (!count.empty()) r.count = tp::parse_integer(count, "--count");
    if (!duration.empty()) r.duration_s = tp::parse_finite(duration, "--duration");
    const tp::Stimulus s = tp::make_stimulus(doc, r);
    // The amplitude against the thresholds the document carries (fiber-threshold's).
    const auto against = tp::stimulus_against_thresholds(s);
    // Every option is checked before anything is printed, on stderr or stdout.
    long pulses = 0;
    if (format == "csv") {
      pulses = tp::parse_integer(csv_pulses, "--csv-pulses");
      if (pulses < 1 || pulses > 100000)
        tp::bad_input("--csv-pulses: " + csv_pulses + " outside [1, 100000]");
    }

    const tp::SafetyFigures f = tp::safety_figures(s);
    std::fprintf(stderr,
                 "make-pulse: %zu channels, %ld pulses at %s Hz; peak %s mA, charge/phase %s nC, "
                 "%s uC/cm2, RMS %s mA, net charge %s nC\n",
                 s.currents_mA.size(), s.count, tp::number_text(s.shape.frequency_hz).c_str(),
                 tp::number_text(f.peak_current_mA).c_str(),
                 tp::number_text(f.max_charge_per_phase_nC).c_str(),
                 tp::number_text(f.max_charge_density_uC_per_cm2).c_str(),
                 tp::number_text(f.max_rms_current_mA).c_str(),
                 tp::number_text(f.max_net_charge_nC).c_str());
    if (against) std::fprintf(stderr, "make-pulse: %s\n", against->c_str());
    if (format == "csv") {
      std::vector<std::string> header{"t_us"};
      for (std::size_t i = 0; i < s.currents_mA.size(); ++i)
        header.push_back("ch" + std::to_string(i) + "_mA");
      tp::CsvWriter csv(tp::cli::write_stdout);
      csv.header(header);
      for (const auto& row : tp::waveform_points(s, pulses)) csv.row(row);
      csv.flush();
    } else {
      tp::cli::write_stdout(tp::dump_json(tp::stimulus_to_json(s)));
    }
  });
}
