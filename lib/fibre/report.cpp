// Thresholds of every receptor, their ratios and their JSON.

#include "fibre/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp::fibre {

double time_step_ms(const PulseSpec& p) {
  double shortest = p.width_us;
  if (!p.monophasic) shortest = std::min(shortest, p.balance_width_us);  // gaps carry nothing
  if (!p.phases.empty()) {
    shortest = HUGE_VAL;
    for (const Phase& ph : p.phases)
      if (ph.level != 0.0) shortest = std::min(shortest, ph.duration_us);
  }
  return std::max(1e-4, std::min(0.005, shortest * 1e-3 / 10.0));
}

Waveform waveform_of(const PulseSpec& p, double delay_ms) {
  if (p.phases.empty())
    return pulse_waveform(p.width_us, p.interphase_us, p.balance_width_us, p.monophasic, delay_ms);
  Waveform w;
  w.delay_ms = delay_ms;
  for (const Phase& ph : p.phases) w.phases.push_back({ph.duration_us * 1e-3, ph.level});
  return w;
}

namespace {
// The work of every receptor's search, on a conductor and waveform already made.
double work_of(const Setup& setup, const FibreModel& model, const Conductor& conductor,
               const Waveform& w, const ThresholdSettings& settings) {
  double work = 0.0;
  for (const Receptor& rec : setup.receptors)
    work += threshold_work(model, setup, conductor, rec, w, settings);
  return work;
}
}  // namespace

double thresholds_work(const Setup& setup, const FibreModel& model, const PulseSpec& pulse,
                       ThresholdSettings settings) {
  check_pulse(pulse);
  settings.dt_ms = 0.005;
  const auto conductor = make_conductor(setup.conductor, setup.array);
  return work_of(setup, model, *conductor, waveform_of(pulse, settings.delay_ms), settings);
}

ThresholdReport compute_thresholds(const Setup& setup, const std::vector<double>& weights,
                                   const FibreModel& model, const PulseSpec& pulse,
                                   ThresholdSettings settings, PotentialCache* cache) {
  check_pulse(pulse);
  settings.dt_ms = 0.005;
  const auto conductor = make_conductor(setup.conductor, setup.array);
  const Waveform w = waveform_of(pulse, settings.delay_ms);
  // Every receptor's fibre first, and the whole work: bad input before any work.
  check_threshold_work(work_of(setup, model, *conductor, w, settings), kMaxThresholdWork,
                       "thresholds");
  ThresholdReport r;
  r.model = model.name();
  r.peak_weight = 0.0;
  for (double x : weights) r.peak_weight = std::max(r.peak_weight, std::fabs(x));
  r.pulse = pulse;
  r.settings = settings;
  r.dt_ms = time_step_ms(pulse);
  for (std::size_t k = 0; k < setup.receptors.size(); ++k) {
    ThresholdSettings one = settings;
    one.start_mA.clear();
    if (k < settings.start_mA.size()) one.start_mA = {settings.start_mA[k]};
    r.receptors.push_back(
        receptor_threshold(model, setup, *conductor, weights, setup.receptors[k], w, one, cache));
  }
  for (std::size_t m = 0; m < r.receptors.size(); ++m) {
    std::optional<double> other;
    for (std::size_t k = 0; k < r.receptors.size(); ++k)
      if (k != m && r.receptors[k].threshold_mA)
        other =
            other ? std::min(*other, *r.receptors[k].threshold_mA) : *r.receptors[k].threshold_mA;
    if (r.receptors[m].threshold_mA && other)
      r.ratios.push_back(*r.receptors[m].threshold_mA / *other);
    else
      r.ratios.emplace_back();
  }
  return r;
}

Json thresholds_to_json(const Setup& setup, const ThresholdReport& r) {
  Json j = Json::object();
  j["fibre_model"] = r.model;
  j["pulse"] = pulse_spec_to_json(r.pulse);
  j["peak_weight"] = r.peak_weight;
  Json s = Json::object();
  s["offsets"] = r.settings.offsets;
  s["tolerance"] = r.settings.tolerance;
  s["max_mA"] = r.settings.max_mA;
  s["dt_us"] = r.dt_ms * 1e3;
  if (r.settings.geometry != Geometry::straight) s["geometry"] = to_string(r.settings.geometry);
  if (r.settings.through_mm)
    s["through_mm"] = Json::array({(*r.settings.through_mm)[0], (*r.settings.through_mm)[1]});
  j["settings"] = s;
  Json recs = Json::object();
  for (std::size_t k = 0; k < r.receptors.size(); ++k) {
    const ReceptorThreshold& t = r.receptors[k];
    const Receptor& rec = setup.receptors[k];
    Json e = Json::object();
    if (t.threshold_mA) {
      e["threshold_mA"] = *t.threshold_mA;
      e["x_mm"] = t.x_mm;
      e["depth_mm"] = t.depth_mm;
      if (setup.array.two_d()) e["z_mm"] = t.z_mm;
      e["node"] = t.node;
      if (rec.fibre.orientation == Orientation::horizontal) e["offset_mm"] = t.offset_mm;
      if (t.direction != 0) e["stem"] = t.direction < 0 ? "-x" : "+x";
      if (t.at_cut_end) e["at_cut_end"] = true;
      if (t.at_cut_end && !t.cut_end_reason.empty()) e["cut_end_reason"] = t.cut_end_reason;
      // A fibre lengthened by the cut-end rule: how far beyond the pads, in default
      // extensions (docs/fibres.md, "Cut ends"); only what differs from the settings'.
      Json reach = Json::object();
      if (t.reach.minus_x != r.settings.reach.minus_x) reach["-x"] = t.reach.minus_x;
      if (t.reach.plus_x != r.settings.reach.plus_x) reach["+x"] = t.reach.plus_x;
      if (t.reach.below != r.settings.reach.below) reach["below"] = t.reach.below;
      if (!reach.empty()) e["lengthened"] = reach;
    } else {
      e["threshold_mA"] = nullptr;
      e["reason"] = t.reason;
    }
    e["orientation"] = to_string(rec.fibre.orientation);
    e["diameter_um"] = rec.fibre.diameter_um;
    if (r.model == "mrg")
      e["geometry"] = mrg_tabulated(rec.fibre.diameter_um) ? "table" : "interpolated";
    e["placements"] = t.placements;
    recs[t.receptor] = e;
  }
  j["receptors"] = recs;
  return j;
}

Json ratios_to_json(const Setup& setup, const ThresholdReport& r) {
  Json j = Json::object();
  for (std::size_t k = 0; k < r.ratios.size(); ++k) {
    if (r.ratios[k])
      j[setup.receptors[k].name] = *r.ratios[k];
    else
      j[setup.receptors[k].name] = nullptr;
  }
  return j;
}

}  // namespace tp::fibre
