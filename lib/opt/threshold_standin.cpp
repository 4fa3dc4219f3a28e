// The linear stand-in for a receptor's threshold (threshold_standin.hpp).

#include "opt/threshold_standin.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fibre/cable.hpp"
#include "fibre/placements.hpp"
#include "fibre/search.hpp"

namespace tp::fibre {

namespace {

// The stand-in's runs: the settings' step, to kPassiveAfter_ms after the waveform (at most
// the search's end), no detection.
SimOptions passive_options(const FibreRun& f, const Waveform& w, const ThresholdSettings& s) {
  SimOptions o;
  o.dt_ms = s.dt_ms;
  o.tstop_ms = std::min(f.tstop_ms, w.end_ms() + kPassiveAfter_ms);
  return o;
}

// The steps of a run, at most: dt's, and each short phase's window at its finer step
// (CableSimulator::run's schedule).
double steps_at_most(const SimOptions& o, const Waveform& w) {
  double steps = std::ceil(o.tstop_ms / o.dt_ms) + 2.0;
  for (const Waveform::Phase& ph : w.phases)
    if (ph.duration_ms < o.short_phase_ms && ph.level != 0.0 && ph.duration_ms > 0.0)
      steps += std::ceil((ph.duration_ms + 0.1) /
                         std::max(o.min_dt_ms, std::min(o.dt_ms, ph.duration_ms / 10.0))) +
               1.0;
  return steps;
}

// The nodes' potentials of one run, every other step (the peak moves little between
// them): (time, node), without the times.
std::vector<double> record(CableSimulator& sim, const double* ve, double amplitude,
                           const Waveform& w, const SimOptions& o, double steps) {
  const std::size_t nodes = sim.axon().nodes.size();
  std::vector<double> trace;
  trace.reserve(static_cast<std::size_t>(steps / 2.0 + 2.0) * (nodes + 1));
  sim.record(&trace, 2);
  sim.run(ve, amplitude, w, o);
  sim.record(nullptr, 2);
  std::vector<double> v;
  for (std::size_t t = 0; t + nodes + 1 <= trace.size(); t += nodes + 1)
    v.insert(v.end(), trace.begin() + static_cast<long>(t + 1),
             trace.begin() + static_cast<long>(t + 1 + nodes));
  return v;
}

}  // namespace

LinearStandIn::LinearStandIn(const FibreModel& model, const Setup& setup,
                             const Conductor& conductor, const Receptor& receptor,
                             const Waveform& waveform, const ThresholdSettings& settings)
    : model_(model),
      setup_(setup),
      conductor_(conductor),
      receptor_(receptor),
      waveform_(waveform),
      settings_(settings),
      k_mV_(passive_k_mV(waveform)) {}

void LinearStandIn::add(const std::vector<Spot>& spots, PotentialCache& cache) {
  const FibreRun f = fibre_run(model_, setup_, conductor_, receptor_, waveform_, settings_);
  const bool vertical = receptor_.fibre.orientation == Orientation::vertical;
  const bool two_d = setup_.array.two_d();
  const std::size_t n = setup_.array.size();
  const SimOptions o = passive_options(f, waveform_, settings_);
  const double steps = steps_at_most(o, waveform_);
  std::vector<double> unit(n, 0.0);
  // A run at zero amplitude: where the nodes drift without a field (the resting state is
  // not exactly steady), taken off every response before it is scaled.
  std::vector<std::vector<double>> rest(f.axons.size());
  for (const Spot& at : spots) {
    if (std::find(spots_.begin(), spots_.end(), at) != spots_.end()) continue;
    const auto fi = static_cast<std::size_t>(
        std::find(f.directions.begin(), f.directions.end(), at.direction) - f.directions.begin());
    if (fi >= f.axons.size()) continue;
    const Axon& axon = f.axons[fi];
    const std::size_t nodes = axon.nodes.size();
    // Bounded: past kMaxStandIn values the stand-in takes no more placements (it guides,
    // the whole searches decide).
    if (static_cast<double>(stored_) + (steps / 2.0 + 2.0) * static_cast<double>(nodes * n) >
        kMaxStandIn)
      break;
    CableSimulator sim(model_, axon);
    if (rest[fi].empty()) {
      const std::vector<double> zero(axon.compartments.size(), 0.0);
      rest[fi] = record(sim, zero.data(), 0.0, waveform_, o, steps);
    }
    std::vector<std::vector<double>> per_electrode(n);
    std::size_t samples = 0;
    for (std::size_t e = 0; e < n; ++e) {
      std::fill(unit.begin(), unit.end(), 0.0);
      unit[e] = 1.0;
      const std::vector<double> ve = potentials_mV(conductor_, unit, axon, at.x0_mm, at.y0_mm,
                                                   vertical, at.z0_mm, two_d, cache);
      const double most = largest_af(axon, ve.data());
      if (!(most > 0.0) || !std::isfinite(most)) continue;  // no field: no response
      const double a0 = 1.0 / most;                         // 1 mV of activating function: linear
      std::vector<double> r = record(sim, ve.data(), a0, waveform_, o, steps);
      const std::vector<double>& r0 = rest[fi];
      for (std::size_t q = 0; q < r.size(); ++q) r[q] = (r[q] - (q < r0.size() ? r0[q] : 0.0)) / a0;
      samples = std::max(samples, r.size());
      per_electrode[e] = std::move(r);
    }
    std::vector<double> response(samples * n, 0.0);  // samples x electrodes
    for (std::size_t e = 0; e < n; ++e)
      for (std::size_t q = 0; q < per_electrode[e].size(); ++q)
        response[q * n + e] = per_electrode[e][q];
    stored_ += response.size();
    spots_.push_back(at);
    scale_.push_back(0.0);
    response_.push_back(std::move(response));
  }
}

double LinearStandIn::raw_mA(std::size_t i, const std::vector<double>& w) const {
  const std::size_t n = w.size();
  const std::vector<double>& r = response_[i];
  double most = 0.0;
  for (std::size_t q = 0; q + n <= r.size(); q += n) {
    double v = 0.0;
    for (std::size_t e = 0; e < n; ++e) v += w[e] * r[q + e];
    most = std::max(most, v);
  }
  return most > 0.0 ? k_mV_ / most : std::numeric_limits<double>::infinity();
}

double LinearStandIn::threshold_mA(const std::vector<double>& w) const {
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < response_.size(); ++i)
    least = std::min(least, (scale_[i] > 0.0 ? scale_[i] : default_scale_) * raw_mA(i, w));
  return least;
}

void LinearStandIn::calibrate(const ReceptorThreshold& exact, const std::vector<double>& w,
                              PotentialCache& cache) {
  add(exact.tried, cache);
  if (!exact.threshold_mA) return;
  add({exact.spot}, cache);
  const auto i = static_cast<std::size_t>(std::find(spots_.begin(), spots_.end(), exact.spot) -
                                          spots_.begin());
  if (i >= spots_.size()) return;
  const double raw = raw_mA(i, w);
  if (!(raw > 0.0) || !std::isfinite(raw)) return;
  scale_[i] = default_scale_ = *exact.threshold_mA / raw;
}

}  // namespace tp::fibre
