#pragma once
// Where a receptor's fibres lie in its threshold search (docs/fibres.md, "Fibre
// placement"): the fibres simulated (one; an afferent's, one per stem direction), the plan
// of the placements tried along each, and their potentials.  The plan is the one count of
// placements: fibre_nodes bounds the unit potentials with it, threshold_work estimates the
// work with it, and receptor_threshold's search runs its rounds.

#include <array>
#include <cstddef>
#include <vector>

#include "fibre/threshold.hpp"

namespace tp::fibre {

// The placements along one fibre, in rounds: the first, then (vertical fibres searched over
// x) refinements around the best placement of the rounds before.
//  - one_horizontal (settings.fixed_offset_mm): one node alignment at the receptor's top
//    depth;
//  - one_vertical (settings.fixed_x_mm): one x (under a 2-D array at through_mm's z);
//  - horizontal: `offsets` node alignments spread evenly over one internode, at each depth
//    (five from a range's top to its bottom, else one);
//  - vertical_across (a 1-D array): every quarter pitch across the array +- one pitch, then
//    twice 9 around the best at a quarter of the step before (to a 64th of a pitch);
//  - vertical_around (a 2-D array): every quarter pitch within half a pitch of through_mm in
//    x and z (5 x 5), then twice 5 x 5 around the best at half the step (to a 16th).
// A placement is a Spot with direction 0 (the search sets the afferent's stem).
class PlacementPlan {
 public:
  enum class Kind { one_horizontal, one_vertical, horizontal, vertical_across, vertical_around };

  // settings.through_mm must be set under a 2-D array (fibre_nodes checks it first).
  PlacementPlan(const Setup& setup, const Receptor& receptor, const ThresholdSettings& settings,
                double internode_mm);

  Kind kind() const { return kind_; }
  bool vertical() const { return kind_ != Kind::one_horizontal && kind_ != Kind::horizontal; }
  std::size_t rounds() const {
    return kind_ == Kind::vertical_across || kind_ == Kind::vertical_around ? 3 : 1;
  }
  std::size_t round_size(std::size_t k) const;
  // Round k < rounds(): round 0 the first; a refinement around `best`, a placement of an
  // earlier round.
  std::vector<Spot> round(std::size_t k, const Spot& best = {}) const;
  // The placements along one fibre when every round runs (the search skips the refinements
  // when the first round finds no threshold): the sum of round_size().
  std::size_t count() const;
  // The fibres searched (an afferent's stem directions, else one), each over count().
  std::size_t fibres() const { return fibres_; }

 private:
  Kind kind_;
  std::size_t fibres_ = 1;
  std::size_t depths_ = 1, offsets_ = 1;
  double internode_mm_ = 0.0, top_mm_ = 0.0, bottom_mm_ = 0.0;
  double left_mm_ = 0.0;                 // horizontal: a node at or before this x
  double fixed_ = 0.0;                   // one_*: the alignment or the x
  double z_mm_ = 0.0;                    // the fibres' z (2-D arrays; else 0)
  double x_mm_ = 0.0;                    // vertical_around: through_mm's x
  double from_mm_ = 0.0, to_mm_ = 0.0;   // vertical_across: the first round's span
  double pitch_mm_ = 1.0;                // vertical: the sampling pitch
  std::size_t across_intervals() const;  // vertical_across: the first round's steps
};

// The step vertical fibres are sampled at: a quarter of it.  A 1-D array's mean pitch (1 mm
// for one electrode); a 2-D grid's smaller pitch, free pads' nearest two centres.
double sampling_pitch_mm(const ElectrodeArray& a);

// How far fibres run (docs/fibres.md, "Cut ends"): the default extension beyond the pads
// (the lateral margin plus five internodes), which settings.reach scales; a horizontal
// fibre's first node lies at or before span[0] and its nodes reach span[1]; a straight
// vertical fibre's internodes below its receptor.
double default_extension_mm(const Setup& setup, double internode_mm);
std::array<double, 2> horizontal_span_mm(const Setup& setup, const Receptor& r,
                                         const ThresholdSettings& s, double internode_mm);
std::size_t below_internodes(const ThresholdSettings& s);

// Whether a receptor's fibre is an afferent (Geometry::afferent, a vertical receptor), the
// stem directions its search tries in order (ties go to the first), and its fibre with the
// stem toward `direction`.
bool is_afferent(const Receptor& r, const ThresholdSettings& s);
std::vector<int> afferent_directions(const ThresholdSettings& s);
Axon afferent_for(const FibreModel& model, const Setup& setup, const Receptor& r,
                  const ThresholdSettings& s, int direction);

// The fibres a receptor's search simulates (one; an afferent's, one per stem direction,
// with the directions), and the simulation's end.  Bad input as fibre_nodes.
struct FibreRun {
  std::size_t nodes;
  double internode_mm, tstop_ms;
  std::vector<Axon> axons;
  std::vector<int> directions;
};
FibreRun fibre_run(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                   const Receptor& r, const Waveform& waveform, const ThresholdSettings& s);

// The potential (mV per compartment) along a fibre with its first node at (x0, y0), for the
// weights at 1 mA: the unit potentials (the cache's) weighted.
std::vector<double> potentials_mV(const Conductor& c, const std::vector<double>& weights,
                                  const Axon& axon, double x0, double y0, bool vertical, double z0,
                                  bool three_d, PotentialCache& cache);

}  // namespace tp::fibre
