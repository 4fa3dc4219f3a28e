#pragma once
// make-pulse's work, for the program and the Python module alike: a weights document and a
// pulse become a checked stimulus (docs/programs.md, make-pulse).

#include <optional>
#include <string>
#include <vector>

#include "io/csv.hpp"
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
  // The pulse: the shorthand's widths, or phases (not both).  With none of them, the weights
  // document's `pulse` when it carries one, else 200 us symmetric.
  std::optional<double> width_us;          // [200]
  std::optional<double> balance_width_us;  // [width_us]
  std::optional<double> interphase_us;     // [0]
  std::vector<Phase> phases;
  // The length: a pulse count, or a duration (s; [1]); not both.
  std::optional<long> count;
  std::optional<double> duration_s;
};

// The pulse a weights document carries (its "pulse": phases, or the shorthand's widths), if
// any; bad input when it is malformed.
std::optional<PulseShape> document_pulse(const Document& doc);

// Bad input, naming the option as make-pulse's flag (--amplitude, --frequency, ...), when
// the document has no weights or more channels than a stimulator drives, when the request
// is not one of amplitude or intensity-with-profile, or when the stimulus breaks a limit
// (check_stimulus).  Carries the document's mode and thresholds.
Stimulus make_stimulus(const Document& doc, const PulseRequest& r);

// make-pulse's options, the texts of its flags as given (empty: not given); each is parsed
// by plan_make_pulse(), in the program's order, so that a bad one is named by its flag.
struct MakePulseOptions {
  std::string input = "-";  // --input: the weights document (- for stdin)
  std::string amplitude, intensity;
  std::string profile;  // --profile FILE (- for stdin): the person's calibration
  std::string frequency = "200", width, balance_width, interphase;
  std::string phases;  // --phases D:L,...
  std::string duration, count;
  bool csv = false;              // --format csv: the waveform's corners (else the JSON)
  std::string csv_pulses = "3";  // --csv-pulses: the pulses drawn by --format csv
};

// The person's profile (FILE, - for stdin) for --intensity with `doc`'s weights, read
// against the document's current limit.
Profile pulse_profile(const Document& doc, const std::string& path);

// The options as a PulseRequest for `doc` (read from options.input): --profile - refused
// when stdin carries the weights, the profile read (against the document's current limit)
// only with --intensity and without --amplitude, --profile refused beside --amplitude or
// without --intensity, then the pulse's numbers parsed.
PulseRequest pulse_request_of(const Document& doc, const MakePulseOptions& o);

// What make-pulse prints, every check done first: the stimulus, the CSV's pulses (with
// --format csv, 1 to 100000), and the lines for stderr (after "make-pulse: "): the safety
// figures, which pulse was used when the document carries another, then the amplitude
// against the document's thresholds when it carries them.
struct MakePulsePlan {
  Stimulus stimulus;
  bool csv = false;
  long csv_pulses = 0;
  std::vector<std::string> notes;
};
MakePulsePlan plan_make_pulse(const Document& doc, const MakePulseOptions& o);

// The stimulus document (JSON, one call) or the waveform's corners (CSV: t_us, then a
// column a channel, chI_mA) through `out`.
void write_make_pulse(const MakePulsePlan& plan, const ByteSink& out);

}  // namespace tp
