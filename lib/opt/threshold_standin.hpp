#pragma once
// A stand-in for one receptor's threshold, cheap to evaluate for any weights
// (threshold_objective.cpp): the passive estimate (docs/fibres.md, "The threshold search")
// over a set of placements.  Far below threshold a fibre responds linearly, so its response
// to each electrode alone, recorded at its nodes from the pulse's start to 0.05 ms after the
// waveform, gives its response to any weights by superposition; the stand-in is K / the
// largest depolarisation over the placements, nodes and times, per mA.  Within tens of per
// cent of the threshold, not on its lattice: a guide for a search, never an answer.

#include <cstddef>
#include <vector>

#include "fibre/threshold.hpp"

namespace tp::fibre {

class LinearStandIn {
 public:
  LinearStandIn(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                const Receptor& receptor, const Waveform& waveform,
                const ThresholdSettings& settings);
  // Adds the placements not yet held.
  void add(const std::vector<Spot>& spots, PotentialCache& cache);
  // In mA; +infinity when nothing depolarises.
  double threshold_mA(const std::vector<double>& weights) const;
  // A whole search's answer at weights: its placement's estimate is scaled to it from now
  // on, and so are the placements that never gave one (adding it first if needed).
  void calibrate(const ReceptorThreshold& exact, const std::vector<double>& weights,
                 PotentialCache& cache);
  std::size_t placements() const { return spots_.size(); }

 private:
  const FibreModel& model_;
  const Setup& setup_;
  const Conductor& conductor_;
  const Receptor& receptor_;
  const Waveform& waveform_;
  ThresholdSettings settings_;
  double k_mV_;
  std::vector<Spot> spots_;
  std::vector<double> scale_;  // per placement; 0: default_scale_
  std::size_t stored_ = 0;     // values in response_
  // At most 1e7 values (80 MB) per stand-in: an evaluation is at most as many
  // multiply-adds.
  static constexpr double kMaxStandIn = 1e7;
  double default_scale_ = 1.0;
  double raw_mA(std::size_t placement, const std::vector<double>& weights) const;
  // Per placement: samples (node, time) x electrodes, the depolarisation (mV per mA).
  std::vector<std::vector<double>> response_;
};

}  // namespace tp::fibre
