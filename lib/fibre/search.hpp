#pragma once
// The threshold search over any potential (docs/fibres.md, "The threshold search"): for a
// set of potentials along one fibre (mV per compartment, for 1 mA), the lowest lattice
// point at which the fibre fires in each, and the lexicographic minimum (lattice point,
// index) over the set.  It knows nothing of conductors, electrodes or where a fibre lies
// (placements.hpp): receptor_threshold gives it the potentials of its placements,
// fibre_threshold a caller's one potential, the tests closed forms.

#include <atomic>
#include <cstddef>
#include <optional>
#include <vector>

#include "fibre/cable.hpp"
#include "fibre/threshold.hpp"

namespace tp::fibre {

// The lexicographic best (lattice point, potential index) so far.
struct Best {
  bool found = false;
  long j = 0;
  std::size_t index = 0;
  std::size_t node = 0;  // where the run at j of potential `index` crossed detect_mV first
  bool beats(long jj, std::size_t ii) const { return !found || jj < j || (jj == j && ii < index); }
};

// A fibre's largest activating function at its nodes, either sign (a biphasic pulse drives
// both): the second difference of the potential, or at an end node the first.
double largest_af(const Axon& axon, const double* ve);

// How long the passive estimate's runs go on after the waveform (the peak depolarisation
// comes at a phase's end).
inline constexpr double kPassiveAfter_ms = 0.05;

// The depolarisation at the end of a pulse at which an MRG node fires, about (the passive
// estimate, AmplitudeSearch): 4.3 + 5.3 / sqrt(the longest phase in ms) mV; 0 for a waveform
// without a phase.
double passive_k_mV(const Waveform& w);

// The caller's guess (settings.start_mA's first entry), if it is one: positive and finite,
// at most max_mA.
std::optional<double> caller_start(const ThresholdSettings& s);

// The search on the lattice of settings.tolerance, from 2^-50 max_mA to max_mA, of one
// fibre (model, axon) driven by a waveform, with the options' detection nodes, step and stop
// time; settings.threads workers (0: every core) and settings.settle (runs that pause).
class AmplitudeSearch {
 public:
  AmplitudeSearch(const FibreModel& model, const Axon& axon, const Waveform& w, const SimOptions& o,
                const ThresholdSettings& s);

  // The lexicographic minimum of (threshold lattice point, index) over the potentials
  // ve[base..], given `best` over the potentials before them.  A threshold below jmin() is
  // reported as jmin() - 1 (excited even at the floor); none found: best is returned as
  // given.
  //
  // No exception leaves a worker: each is caught there, the potentials with a higher index
  // than the failing one are skipped, and the failure of the lowest index is rethrown here,
  // on the caller's thread, once every worker has joined.
  //
  // The potentials are searched in the order of their activating function, the strongest
  // first (drive()): the answer does not depend on the order, but the work does, since a
  // potential that cannot beat the best so far costs one simulation.
  // guess: where a search starts without a best; close: it is a threshold (of another
  // fibre, or of nearby weights); not close: the passive estimate, if there is one, else
  // guess.
  Best minimum(const std::vector<std::vector<double>>& ve, std::size_t base, Best best, long guess,
               bool close);

  // A potential's largest activating function at the fibre's nodes (largest_af()).
  double drive(const std::vector<double>& ve) const { return largest_af(axon_, ve.data()); }

  const AmplitudeLattice& lattice() const { return lat_; }
  long jmax() const { return jmax_; }
  long jmin() const { return jmin_; }
  std::size_t simulations() const { return simulations_; }

 private:
  struct Probe {
    bool fired, excited;
    std::size_t node;  // the first node to cross, when excited
  };
  struct Excitation;
  Probe probe(Excitation& e, long j);
  bool confirm(Excitation& e, long j);
  std::optional<long> estimate(CableSimulator& sim, const std::vector<double>& ve);
  bool search_one(CableSimulator& sim, const std::vector<double>& ve, std::size_t i,
                  const Best& best, long guess, bool near, long& out, std::size_t& node);
  std::optional<bool> search_from(Excitation& e, std::size_t i, const Best& best, long guess,
                                  bool near, long& out, std::size_t& node);
  long first_step(CableSimulator& sim, const std::vector<double>& ve, const Best& best, bool near,
                  long& guess);
  bool first_firing(Excitation& whole, long hi, long limit, long& out, std::size_t& node);

  const FibreModel& model_;
  const Axon& axon_;
  const Waveform& w_;
  SimOptions o_;         // every run to its end
  SimOptions settling_;  // o_, pausing runs once settled (unless the settings say not to)
  AmplitudeLattice lat_;
  long jmax_, jmin_;
  unsigned threads_;
  std::atomic<std::size_t> simulations_{0};
};

}  // namespace tp::fibre
