#pragma once
// Thresholds in mA: the smallest amplitude at which a receptor's fibre fires, for a
// weighted electrode array, a conductor model and a stimulus waveform.
//
// A threshold is searched on a fixed lattice of amplitudes, 2^(j/K) mA with K the smallest
// integer for which one step is at most the tolerance, so the answer is the lattice point
// and does not depend on how the search was bracketed or on which thread found it: the same
// input gives the same bytes.  Doubling every weight halves the threshold exactly.
//
// Where a fibre lies (docs/fibres.md, "Fibre placement"):
//  - horizontal fibres run along x at the receptor's depth (every depth of a range: five
//    depths from its top to its bottom), over the array +- the lateral margin plus five
//    internodes each side; the threshold is the minimum over `offsets` node alignments
//    spread evenly over one internode;
//  - vertical fibres start in a sealed terminal node at the receptor's top depth and run
//    straight down through its depth range and `extra_internodes` internodes beyond; the
//    threshold is the minimum over x, sampled every quarter pitch across the array +- one
//    pitch and refined twice around the best sample (to a 64th of a pitch);
//  - afferents (Geometry::afferent, vertical receptors) are placed as vertical fibres are,
//    by their ending's x, once with the stem toward -x and once toward +x: the stem reaches
//    past the far side of the array plus the lateral margin by five internodes.
// Under a 2-D array the fibres pass through one point (x, z) of the surface, a pixel's
// (`through_mm`): horizontal fibres run along x at that z, over the pads plus the lateral
// margin; vertical fibres are sampled every quarter pitch within half a pitch of it in x
// and z, and refined twice around the best sample.
// An action potential counts when it reaches the sixth node from each end of a horizontal
// fibre, or the sixth node from the deep end of a vertical one or of an afferent's stem
// (above -20 mV).  When the winner's started within five nodes of a cut end, the fibre is
// doubled beyond the pads there and searched again, until it starts inside (docs/fibres.md,
// "Cut ends"; settings.reach and lengthen).
//
// The parts: the search over any potential (search.hpp: AmplitudeSearch), the placements
// (placements.hpp: the fibres, one plan that counts and generates the placements, their
// potentials), and here the receptor's threshold that joins them.  The optimiser's
// stand-in for a threshold is opt/threshold_standin.hpp.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "fibre/cable.hpp"
#include "fibre/geometry.hpp"
#include "fibre/models.hpp"
#include "model/field.hpp"

namespace tp::fibre {

// Where a fibre lay in a search: its direction, first node and node alignment.
struct Spot {
  int direction = 0;                // an afferent's stem, -1 or +1; else 0
  double x0_mm = 0.0, y0_mm = 0.0;  // the first node (a vertical fibre's top)
  double z0_mm = 0.0;               // 2-D arrays: the fibre's z
  double offset_mm = 0.0;           // horizontal: the node alignment
  bool operator==(const Spot& o) const;
};

struct ThresholdSettings {
  double tolerance = 1e-3;            // relative lattice step, 1e-4 to 0.1
  double max_mA = 100.0;              // no threshold below this: the fibre "does not fire"
  double dt_ms = 0.005;               // time step, at most 5 us
  std::size_t offsets = 8;            // horizontal fibres: node alignments per internode, 1 to 64
  std::size_t extra_internodes = 10;  // vertical fibres: below the receptor's range
  // How far each fibre runs beyond the pads, in units of the default extension
  // (docs/fibres.md, "Cut ends"): a horizontal fibre's on each side (the lateral margin
  // plus five internodes), an afferent's stem toward -x and toward +x (the same), a straight
  // vertical fibre's internodes below its receptor (extra_internodes).  receptor_threshold
  // doubles the one at which the winner fired, when it fired at a cut end.
  struct Reach {
    double minus_x = 1.0, plus_x = 1.0, below = 1.0;
  };
  Reach reach;
  // Lengthen a fibre whose action potential started at a cut end and search it again,
  // until it starts inside (docs/fibres.md, "Cut ends"); false: report it (at_cut_end).
  bool lengthen = true;
  double delay_ms = 0.1;  // rest before the pulse
  double after_ms = 0;    // simulated after the pulse (0: enough to propagate)
  unsigned threads = 0;   // 0: every core
  // 2-D arrays: the point (x, z) in mm the fibres pass through (required there; a pixel's
  // place); 1-D arrays: not used.
  std::optional<std::array<double, 2>> through_mm;
  // One fibre instead of a search over placements (a population's afferent): a vertical
  // fibre at this x (under a 2-D array at through_mm's z), a horizontal one with its nodes
  // at this alignment (mm from the lattice x = m internodes, [0, internode)) at the
  // receptor's top depth.
  std::optional<double> fixed_x_mm, fixed_offset_mm;
  // Vertical receptors' fibres: straight (the paper's) or afferents (geometry.hpp), whose
  // stems are tried toward -x and +x (fixed_direction: one of them, -1 or +1).
  Geometry geometry = Geometry::straight;
  AfferentShape shape;
  std::optional<int> fixed_direction;
  // Where the first search starts, per receptor in the setup's order (a guess, such as the
  // thresholds of nearby weights: the answer does not depend on it, only the work does).
  // Missing or not positive: the passive estimate (docs/fibres.md, "The threshold search").
  std::vector<double> start_mA;
  // Runs below threshold pause once settled and only the last is finished (docs/fibres.md,
  // "The threshold search"); false: every run to its end.  The same answers either way,
  // as excitation grows with the amplitude (which the search assumes in any case).
  bool settle = true;
};

// Where and whether a receptor fired at its threshold.
struct ReceptorThreshold {
  std::string receptor;
  std::optional<double> threshold_mA;  // empty: no threshold below max_mA
  std::string reason;                  // why there is none
  double x_mm = 0.0, depth_mm = 0.0;   // the node where the action potential started
  double z_mm = 0.0;                   // 2-D arrays: its z
  std::size_t node = 0;                // its number along the fibre (0: the first node)
  double offset_mm = 0.0;              // horizontal: the alignment that gave the minimum
  int direction = 0;                   // an afferent's stem: toward -x (-1) or +x (+1)
  // The action potential started within five nodes of a cut end of the simulated fibre (a
  // horizontal fibre's ends, a vertical fibre's deep end, an afferent's stem end; not a
  // vertical fibre's terminal nor an afferent's ending): the threshold then depends on
  // where the fibre was cut, not on the field alone (docs/fibres.md, "Cut ends").  With
  // settings.lengthen only when the fibre could not be lengthened further (cut_end_reason).
  bool at_cut_end = false;
  std::string cut_end_reason;  // at_cut_end: why the fibre was not lengthened further
  // The fibre's reach at the threshold reported (settings.reach, lengthened by the search),
  // and the searches it took (1: the fibre as asked).
  ThresholdSettings::Reach reach;
  std::size_t searches = 0;
  Spot spot;                   // the placement that gave the threshold
  std::vector<Spot> tried;     // every placement tried
  std::size_t placements = 0;  // fibre positions tried
  std::size_t simulations = 0;
};

// The lattice: amplitude of point j, and the number of points per octave.
struct AmplitudeLattice {
  explicit AmplitudeLattice(double tolerance);
  double amplitude(long j) const;
  long at_or_above(double amplitude_mA) const;  // the smallest j with amplitude(j) >= a
  long per_octave;
};

// The stimulus waveform of a pulse (lib/pulse's shape): main phase at +1, the gap, the
// balancing phase at -width/balance_width; monophasic: the main phase only.
Waveform pulse_waveform(double width_us, double interphase_us, double balance_width_us,
                        bool monophasic, double delay_ms = 0.1);

// The unit potentials (one per electrode) at the compartments of fibre placements, kept
// between calls for the same conductor: an optimiser changes the weights, not the fibres.
class PotentialCache {
 public:
  // psi[k * electrodes + i]: electrode i's potential (V per mA) at compartment k.  A 1-D
  // array's fibres lie in its conductor's plane (z0 is not used); a 2-D array's
  // (`three_d`) at z = z0_mm.
  const std::vector<double>& unit(const Conductor& c, const Axon& axon, double x0_mm, double y0_mm,
                                  bool vertical, double z0_mm = 0.0, bool three_d = false);

 private:
  struct Key {
    std::string model, path;
    double diameter_um, x0_mm, y0_mm, z0_mm;
    std::size_t compartments;
    bool vertical, three_d;
    bool operator<(const Key& o) const;
  };
  std::vector<std::pair<Key, std::vector<double>>> entries_;  // kept sorted by key
  std::size_t stored_ = 0;                                    // values in entries_
  static constexpr std::size_t kMaxCached = 40'000'000;       // 320 MB
};

// The number of nodes of a receptor's fibre; bad input when the model cannot represent it
// (unmyelinated, diameter out of range), when its work would be unbounded (at most 2000
// nodes, and 3e7 unit potentials over the plan's placements, placements.hpp), when a buried
// point source (Conductor::buried_source_depth_mm, point3d's) lies less than one internode
// from any depth the fibre occupies (a vertical fibre's internodes below the receptor
// included), or when the conductor cannot evaluate the potential at every compartment of
// every placement (Conductor::check_reach: the layered model far from the electrodes).
std::size_t fibre_nodes(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                        const Receptor& receptor, const ThresholdSettings& settings);

// The work of a receptor's threshold search, in compartment-steps (one compartment advanced
// one time step): compartments x time steps of one simulation x simulations, the last
// estimated as placements (the plan's count, placements.hpp) x (bisection steps over an
// octave of the lattice + 4 bracketing probes).  An estimate, not a bound on the search;
// fibre_nodes() must accept the receptor.
double threshold_work(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                      const Receptor& receptor, const Waveform& waveform,
                      const ThresholdSettings& settings);

// The bounds on estimated work (docs/fibres.md, "Bounded work"), at roughly 1e8
// compartment-steps per second of one core: one set of thresholds, or a strength-duration
// table (5e10: minutes); a threshold optimisation, all its evaluations (1e12: 10000
// evaluations of the paper's array).  Bad input beyond, naming `what`, the estimate, the
// bound and `remedy` (the settings to change, in parentheses).
inline constexpr double kMaxThresholdWork = 5e10;
inline constexpr double kMaxSearchWork = 1e12;
void check_threshold_work(double work, double bound, const std::string& what,
                          const std::string& remedy =
                              "a larger --tolerance, fewer --offsets, a shorter array, margin "
                              "or pulse");

ReceptorThreshold receptor_threshold(const FibreModel& model, const Setup& setup,
                                     const Conductor& conductor, const std::vector<double>& weights,
                                     const Receptor& receptor, const Waveform& waveform,
                                     const ThresholdSettings& settings,
                                     PotentialCache* cache = nullptr);

// One fibre in a given potential (ve_unit_mV: per compartment, for 1 mA): its threshold by
// receptor_threshold's search (search.hpp), on the lattice of settings.tolerance, with the
// options' detection nodes, step and stop time, on one core; settings.start_mA (its first
// entry) is where the search starts.  Empty: no threshold up to settings.max_mA, or
// excitation even at the bottom of the search range.
std::optional<double> fibre_threshold(const FibreModel& model, const Axon& axon,
                                      const std::vector<double>& ve_unit_mV,
                                      const Waveform& waveform, const SimOptions& options,
                                      const ThresholdSettings& settings);

}  // namespace tp::fibre
