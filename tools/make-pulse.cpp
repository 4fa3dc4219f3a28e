// make-pulse: turn a weights document into a checked, charge-balanced biphasic stimulus.
//
//   optimize-weights --mode SAI | make-pulse --amplitude 1 --frequency 200 --duration 1 | stimctl
//   --port emu optimize-weights --mode SAI | make-pulse --amplitude 1 --format csv |
//   scripts/plot-pulse -o pulse.png

#include <cstdio>
#include <string>

#include "cli/entry.hpp"
#include "io/document.hpp"
#include "requests/pulse.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Reads a weights document (optimize-weights' JSON) on stdin and prints a stimulus "
      "document for stimctl: every channel gets the same pulse times its weight "
      "(positive = cathodic main phase), balanced to zero net charge: biphasic, or shaped "
      "(--phases, or the document's pulse).  Every limit is checked first: peak current, zero "
      "sum at every instant, charge balance, phase widths, rate.",
      "make-pulse"};
  tp::MakePulseOptions o;
  std::string format = "json";
  app.add_option("--input", o.input, "Weights document, - for stdin [-]")->type_name("FILE");
  auto* o_amp =
      app.add_option("--amplitude", o.amplitude,
                     "Current of a channel with |weight| = 1, mA, at most 2 (and the document's "
                     "limit)")
          ->type_name("MA");
  auto* o_int = app.add_option("--intensity", o.intensity,
                               "Instead of --amplitude: 0 to 1 of the person's range for the "
                               "document's mode (needs --profile)")
                    ->type_name("V");
  app.add_option("--profile", o.profile,
                 "The person's calibration (calibrate): --intensity v is threshold + v (comfort "
                 "- threshold) mA")
      ->type_name("FILE");
  o_amp->excludes(o_int);
  app.add_option("--frequency", o.frequency,
                 "Pulse rate, Hz, 0.1 to 1000 [200; the paper: 200 for SAI, < 100 for RA]")
      ->type_name("HZ");
  auto* o_w = app.add_option("--width", o.width, "Main phase width, us, 10 to 1000 [200]")
                  ->type_name("US");
  auto* o_b = app.add_option("--balance-width", o.balance_width,
                 "Balancing phase width, us; longer than --width makes it lower, same charge "
                 "[= --width: symmetric]")
      ->type_name("US");
  auto* o_g =
      app.add_option("--interphase", o.interphase, "Gap between the phases, us [0]")->type_name("US");
  auto* o_ph = app.add_option("--phases", o.phases,
                              "Instead of the widths: a shaped pulse of up to 16 phases "
                              "DURATION_US:LEVEL, level x the amplitude (+1: cathodic), charge "
                              "balanced, levels in steps of 1/U (U <= 64): 500:0.1,200:1,500:-0.5 "
                              "[the document's pulse, else --width]")
                   ->type_name("D:L,...");
  o_ph->excludes(o_w)->excludes(o_b)->excludes(o_g);
  auto* o_d = app.add_option("--duration", o.duration, "Stimulus length, s, at most 3600 [1]")
                  ->type_name("S");
  auto* o_c = app.add_option("--count", o.count, "Number of pulses (instead of --duration)")
                  ->type_name("N");
  o_d->excludes(o_c);
  app.add_option("--format", format, "json (stimulus document) or csv (waveform corners) [json]")
      ->check(CLI::IsMember({"json", "csv"}));
  app.add_option("--csv-pulses", o.csv_pulses, "Pulses drawn by --format csv [3]")->type_name("N");
  tp::cli::add_output_option(app);

  return tp::cli::run(app, argc, argv, [&] {
    const tp::Document doc = tp::document_from_json(tp::read_json(o.input, "weights document"));
    o.csv = format == "csv";
    const tp::MakePulsePlan plan = tp::plan_make_pulse(doc, o);
    for (const std::string& line : plan.notes)
      std::fprintf(stderr, "make-pulse: %s\n", line.c_str());
    tp::write_make_pulse(plan, tp::cli::write_stdout);
  });
}
