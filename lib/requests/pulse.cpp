#include "requests/pulse.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "pulse/thresholds.hpp"

namespace tp {

std::optional<PulseShape> document_pulse(const Document& doc) {
  if (!doc.extra.contains("pulse")) return std::nullopt;
  const PulseSpec p = pulse_spec_from_json(doc.extra["pulse"], "weights document: pulse");
  if (p.monophasic)
    bad_input("weights document: pulse: monophasic, never delivered (not charge balanced)");
  PulseShape shape;
  shape.width_us = p.width_us;
  shape.interphase_us = p.interphase_us;
  shape.balance_width_us = p.balance_width_us;
  shape.phases = p.phases;
  return shape;
}

namespace {

bool widths_given(const PulseRequest& r) {
  return r.width_us || r.balance_width_us || r.interphase_us;
}

// The pulse: the phases or the widths asked, else the document's, else 200 us symmetric.
void set_pulse(PulseShape& shape, const Document& doc, const PulseRequest& r) {
  if (!r.phases.empty() && widths_given(r))
    bad_input("--phases excludes --width, --balance-width and --interphase");
  if (!r.phases.empty()) {
    shape.phases = r.phases;
    return;
  }
  if (!widths_given(r)) {
    if (const auto carried = document_pulse(doc)) {
      shape = *carried;
      return;
    }
  }
  shape.width_us = r.width_us.value_or(200.0);
  shape.balance_width_us = r.balance_width_us.value_or(shape.width_us);
  shape.interphase_us = r.interphase_us.value_or(0.0);
}

}  // namespace

Stimulus make_stimulus(const Document& doc, const PulseRequest& r) {
  if (!doc.weights) bad_input("weights document: no 'weights'");
  if (doc.setup.array.size() > static_cast<std::size_t>(ranges::max_channels))
    bad_input("weights document: " + doc.setup.array.describe() + ", " +
              std::to_string(doc.setup.array.size()) + " channels; a stimulator drives at most " +
              std::to_string(ranges::max_channels));
  Stimulus s;
  if (r.amplitude_mA.has_value() == r.intensity.has_value())
    bad_input("give --amplitude MA, or --intensity V with --profile");
  if (r.intensity && !r.profile) bad_input("--intensity: needs --profile");
  if (r.profile && !r.intensity) bad_input("--profile: needs --intensity");
  double amp = 0;
  if (r.intensity) {
    if (!doc.extra.contains("mode") || !doc.extra["mode"].is_string())
      bad_input(
          "--intensity: the weights document names no mode (optimize-weights "
          "--mode writes it)");
    // A person's range measured on another array is not this array's.
    const ElectrodeArray& a = doc.setup.array;
    check_profile_fits(*r.profile, a.size(),
                       a.grid() ? std::make_optional(std::make_pair(a.columns, a.rows))
                                : std::nullopt,
                       "the weights' array is " + a.describe());
    amp = profile_amplitude_mA(*r.profile, doc.extra["mode"].get<std::string>(), *r.intensity,
                               "--intensity");
    // The pads' impedance when the threshold was measured (calibrate on a device that
    // measures), for stimctl --hold-sensation.
    const int k = primary_index(doc.extra["mode"].get<std::string>(), "--intensity");
    const std::vector<double>& z = r.profile->range(k, -1).impedance_kohm;
    if (z.size() == a.size()) s.reference_impedance_kohm = z;
  } else {
    amp = *r.amplitude_mA;
  }
  if (!(amp > 0.0 && amp <= StimulusLimits{}.max_current_mA))
    bad_input("--amplitude: " + number_beside(amp, 0, StimulusLimits{}.max_current_mA) +
              " mA outside (0, " + number_text(StimulusLimits{}.max_current_mA) + "] mA");
  for (double w : *doc.weights) s.currents_mA.push_back(w * amp);
  s.amplitude_mA = amp;
  s.max_current_mA = doc.max_current_mA;
  set_pulse(s.shape, doc, r);
  s.shape.frequency_hz = r.frequency_hz;
  if (!(s.shape.frequency_hz > 0.0)) bad_input("--frequency: must be > 0 Hz");
  const StimulusLimits limits;
  if (r.count && r.duration_s) bad_input("--count and --duration: give one");
  if (r.count) {
    s.count = *r.count;
    if (s.count < 1) bad_input("--count: must be >= 1");
  } else {
    const double d = r.duration_s ? *r.duration_s : 1.0;
    // The range first, then the conversion: nothing wraps.
    if (!(d > 0.0 && d <= limits.max_duration_s))
      bad_input("--duration: " + number_beside(d, 0, limits.max_duration_s) + " s outside (0, " +
                number_text(limits.max_duration_s) + "] s");
    if (!(d * s.shape.frequency_hz <= 1e9)) bad_input("--duration: too many pulses");
    s.count = std::lround(d * s.shape.frequency_hz);
    if (s.count < 1) bad_input("--duration: shorter than one pulse period");
  }
  s.electrode_area_mm2 = doc.setup.array.width_mm * doc.setup.array.length_mm;
  if (!(s.electrode_area_mm2 > 0.0)) bad_input("array: electrode area must be > 0");
  if (doc.extra.contains("mode")) s.carried["mode"] = doc.extra["mode"];
  for (const char* key : {"thresholds", "threshold_ratio"})
    if (doc.extra.contains(key)) s.carried[key] = doc.extra[key];
  check_stimulus(s, limits);
  return s;
}

Profile pulse_profile(const Document& doc, const std::string& path) {
  return profile_from_json(read_json(path, "profile"), doc.max_current_mA,
                           std::numeric_limits<long>::max());
}

PulseRequest pulse_request_of(const Document& doc, const MakePulseOptions& o) {
  PulseRequest r;
  if (o.input == "-" && o.profile == "-") bad_input("--profile -: stdin carries the weights");
  if (!o.amplitude.empty()) r.amplitude_mA = parse_finite(o.amplitude, "--amplitude");
  if (!o.intensity.empty()) r.intensity = parse_finite(o.intensity, "--intensity");
  if (!o.profile.empty() && r.intensity && !r.amplitude_mA && doc.weights)
    r.profile = pulse_profile(doc, o.profile);
  else if (!o.profile.empty() && r.amplitude_mA)
    bad_input("give --amplitude MA, or --intensity V with --profile");
  else if (!o.profile.empty() && !r.intensity)
    bad_input("--profile: needs --intensity");
  r.frequency_hz = parse_finite(o.frequency, "--frequency");
  if (!o.width.empty()) r.width_us = parse_finite(o.width, "--width");
  if (!o.balance_width.empty())
    r.balance_width_us = parse_finite(o.balance_width, "--balance-width");
  if (!o.interphase.empty()) r.interphase_us = parse_finite(o.interphase, "--interphase");
  if (!o.phases.empty()) r.phases = phases_from_text(o.phases, "--phases");
  if (!o.count.empty()) r.count = parse_integer(o.count, "--count");
  if (!o.duration.empty()) r.duration_s = parse_finite(o.duration, "--duration");
  return r;
}

MakePulsePlan plan_make_pulse(const Document& doc, const MakePulseOptions& o) {
  MakePulsePlan plan;
  plan.stimulus = make_stimulus(doc, pulse_request_of(doc, o));
  const Stimulus& s = plan.stimulus;
  // The amplitude against the thresholds the document carries (fiber-threshold's).
  const auto against = stimulus_against_thresholds(s);
  // Every option is checked before anything is printed, on stderr or stdout.
  plan.csv = o.csv;
  if (o.csv) {
    plan.csv_pulses = parse_integer(o.csv_pulses, "--csv-pulses");
    if (plan.csv_pulses < 1 || plan.csv_pulses > 100000)
      bad_input("--csv-pulses: " + o.csv_pulses + " outside [1, 100000]");
  }
  const SafetyFigures f = safety_figures(s);
  plan.notes.push_back(std::to_string(s.currents_mA.size()) + " channels, " +
                       std::to_string(s.count) + " pulses at " + number_text(s.shape.frequency_hz) +
                       " Hz; peak " + number_text(f.peak_current_mA) + " mA, charge/phase " +
                       number_text(f.max_charge_per_phase_nC) + " nC, " +
                       number_text(f.max_charge_density_uC_per_cm2) + " uC/cm2, RMS " +
                       number_text(f.max_rms_current_mA) + " mA, net charge " +
                       number_text(f.max_net_charge_nC) + " nC");
  const auto carried = document_pulse(doc);
  if (carried && !(pulse_of(*carried) == pulse_of(s.shape)))
    plan.notes.push_back("the document's pulse (" + pulse_of(*carried).describe() +
                         ") replaced by the flags' (" + pulse_of(s.shape).describe() + ")");
  if (against) plan.notes.push_back(*against);
  return plan;
}

void write_make_pulse(const MakePulsePlan& plan, const ByteSink& out) {
  const Stimulus& s = plan.stimulus;
  if (!plan.csv) {
    out(dump_json(stimulus_to_json(s)));
    return;
  }
  std::vector<std::string> header{"t_us"};
  for (std::size_t i = 0; i < s.currents_mA.size(); ++i)
    header.push_back("ch" + std::to_string(i) + "_mA");
  CsvWriter csv(out);
  csv.header(header);
  for (const auto& row : waveform_points(s, plan.csv_pulses)) csv.row(row);
  csv.flush();
}

}  // namespace tp
