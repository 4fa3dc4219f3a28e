#pragma once
// Weights and pulse shape designed for selectivity (issue 40, item 3; docs/fibres.md,
// "Designed for selectivity"): the design whose target class of afferents is recruited
// before the others, scored on a sampled population (population.hpp) by the selectivity at
// half recruitment (selectivity_at_half: SI50 = 1 - 2 max over the other classes of the
// fraction recruited where half the target is), with a margin to break its ties.
//
// The search, bounded by a number of populations scored (not by time: the same result on
// any machine): the starts (the AF optimum, and the threshold optimum where there is one),
// then in turn a pass over the pulse's shape, one parameter at a time over a grid (the
// polarity, the main phase's width, the recovery phase's asymmetry, a prepulse's level,
// sign and length), and Nelder-Mead over the zero-sum weights, until a turn finds nothing
// better or the budget ends.  Every design is scored on the same afferents (one seed), and
// it counts only where it can be delivered at its I50 (every limit a stimulus is checked
// against, and a comfort bound on the charge per phase).  The best, and the starts, are
// scored again on a population drawn with another seed (held out of the design).  The
// result is never worse than a start on the design's population: a start is a candidate.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "fibre/population.hpp"
#include "pulse/shape.hpp"
#include "pulse/stimulus.hpp"

namespace tp::fibre {

// Weights (Sum 0, max |w| = 1) and the pulse's phases (level x the amplitude).
struct SelectivityDesign {
  std::vector<double> weights;
  std::vector<Phase> phases;
};

// A design's score on one population.
struct SelectivityScore {
  bool fires = false;     // at least half of the target class fires below max_mA
  HalfSelectivity half;   // I50, each class's fraction there, the index (when it fires)
  // ln(the least threshold of another class's afferent / I50) (max_mA where none fires):
  // how far half the target is from the first other afferent to fire, which orders
  // designs of one index (positive: the index is 1).
  double margin = 0;
  double charge_nC = 0;   // the largest charge per phase at I50 (on an electrode of |w| 1)
  std::string refused;    // why it cannot be delivered at I50; empty: it can
  bool usable() const { return fires && refused.empty(); }
};
// a is better than b: usable first, then the index, then the margin.
bool better(const SelectivityScore& a, const SelectivityScore& b);

struct SelectivityOptions {
  std::size_t per_class = 30;         // afferents of each class, 1 to 1000
  std::uint64_t seed = 1;             // the design's population
  std::uint64_t held_out_seed = 2;    // the check's (not the design's)
  std::size_t max_evaluations = 40;   // populations scored by the search, 4 to 1000
  // The comfort bound on the charge per phase at I50, nC; 0: twice the first start's (the
  // AF optimum's, with the pulse asked).
  double max_charge_nC = 0;
  // The limits every stimulus is checked against (pulse/stimulus.hpp), applied to the
  // design at its I50 on pads of this area at this rate.
  StimulusLimits limits;
  double electrode_area_mm2 = 5.0;
  double frequency_hz = 200.0;
  std::vector<AfferentClass> classes;  // empty: default_afferent_classes()
  unsigned threads = 0;                // 0: every core
  // Called after each population scored (search and check), with the count so far and
  // the stage ("starts", "shape", "weights", "held-out check").
  std::function<void(std::size_t scored, const std::string& stage)> progress;
};

struct ScoredDesign {
  std::string name;  // "af optimum", "threshold optimum", "designed"
  SelectivityDesign design;
  SelectivityScore score;     // on the design's population
  SelectivityScore held_out;  // on the held-out population
};

// One point of the front of selectivity against charge per phase: a usable design no
// design of less charge beats.
struct FrontPoint {
  double charge_nC = 0;
  double index = 0;
  double i50_mA = 0;
  std::vector<Phase> phases;
};

struct SelectivityResult {
  ScoredDesign best;                 // "designed" (a start's design when none beat it)
  std::vector<ScoredDesign> starts;  // as given, scored
  std::vector<FrontPoint> front;     // ascending charge
  std::size_t evaluations = 0;       // populations scored by the search
  std::size_t turns = 0;             // shape and weight passes
  double max_charge_nC = 0;          // the comfort bound applied
  bool improved = false;             // the best is not a start
};

// target: a class of o.classes (its receptor name); starts: at least one, the first the AF
// optimum (its charge sets the default comfort bound).  Bad input, before any work, for an
// option out of range or a population the work bound refuses.
SelectivityResult design_for_selectivity(const Setup& setup, const std::string& target,
                                         const std::vector<ScoredDesign>& starts,
                                         const FibreModel& model, const ThresholdSettings& settings,
                                         const SelectivityOptions& o);

// The checks design_for_selectivity() makes before any work (the options' ranges, the
// target, the whole design's estimated work at the family's longest pulse): bad input.
void check_selectivity(const Setup& setup, const std::string& target, const FibreModel& model,
                       const ThresholdSettings& settings, const SelectivityOptions& o);

// "SAI selectivity 1 at I50 0.73 mA (AF optimum: 1; held out: 0.93)".
std::string selectivity_summary(const SelectivityResult& r, const std::string& target);

}  // namespace tp::fibre
