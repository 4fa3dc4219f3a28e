// A receptor's threshold: the search (search.hpp) over the placements of its fibres
// (placements.hpp), and where the winner fired (threshold.hpp).

#include "fibre/threshold.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "fibre/placements.hpp"
#include "fibre/search.hpp"
#include "core/number.hpp"

namespace tp::fibre {

Waveform pulse_waveform(double width_us, double interphase_us, double balance_width_us,
                        bool monophasic, double delay_ms) {
  Waveform w;
  w.delay_ms = delay_ms;
  w.phases.push_back({width_us * 1e-3, 1.0});
  if (!monophasic) {
    if (interphase_us > 0) w.phases.push_back({interphase_us * 1e-3, 0.0});
    w.phases.push_back({balance_width_us * 1e-3, -width_us / balance_width_us});
  }
  return w;
}

bool Spot::operator==(const Spot& o) const {
  return direction == o.direction && x0_mm == o.x0_mm && y0_mm == o.y0_mm && z0_mm == o.z0_mm &&
         offset_mm == o.offset_mm;
}

double threshold_work(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                      const Receptor& r, const Waveform& waveform, const ThresholdSettings& s) {
  const FibreRun f = fibre_run(model, setup, conductor, r, waveform, s);
  // Time steps: dt throughout, and a tenth of each short phase over it and 0.1 ms after it
  // (SimOptions).
  const SimOptions o;
  double steps = f.tstop_ms / s.dt_ms;
  for (const Waveform::Phase& ph : waveform.phases)
    if (ph.duration_ms < o.short_phase_ms && ph.level != 0.0 && ph.duration_ms > 0.0)
      steps += (ph.duration_ms + 0.1) / std::max(o.min_dt_ms, ph.duration_ms / 10.0);
  // Along each fibre (an afferent's directions: their compartments summed below).
  const double placements = static_cast<double>(PlacementPlan(setup, r, s, f.internode_mm).count());
  const double probes =
      std::ceil(std::log2(static_cast<double>(AmplitudeLattice(s.tolerance).per_octave))) + 4.0;
  double compartments = 0.0;  // over the fibres (an afferent's two directions)
  for (const Axon& a : f.axons) compartments += static_cast<double>(a.compartments.size());
  return compartments * steps * placements * probes;
}

void check_threshold_work(double work, double bound, const std::string& what,
                          const std::string& remedy) {
  if (!(work <= bound)) {
    char estimate[32];
    std::snprintf(estimate, sizeof estimate, "%.2g", work);
    bad_input(what + ": an estimated " + estimate +
              " compartment-steps of fibre simulation, more than the bound of " +
              number_text(bound) + " (" + remedy + ")");
  }
}

namespace {

// The runs of a fibre's search: the settings' step, to the fibre run's end, detecting at the
// sixth node from each end of a horizontal fibre, or from the deep end of a vertical one.
SimOptions detection_options(const Axon& axon, const FibreRun& f, const ThresholdSettings& s,
                             bool vertical) {
  SimOptions o;
  o.dt_ms = s.dt_ms;
  o.tstop_ms = f.tstop_ms;
  const std::size_t last = axon.nodes.size() - 1;
  o.detect = vertical ? std::vector<std::size_t>{last - 5} : std::vector<std::size_t>{5, last - 5};
  return o;
}

// One fibre's search over the plan's rounds: every placement tried, in order, and the best.
struct FibreBest {
  Best best;
  std::vector<Spot> spots;  // direction 0
  std::vector<double> ve;   // the best placement's potential
  std::size_t simulations = 0;
};

// Each round is searched after the rounds before it (whose placements win ties); a
// refinement only once a round has found a threshold, around the best so far.
template <class Potential>
FibreBest search_placements(AmplitudeSearch& search, const PlacementPlan& plan, Potential&& potential,
                            long guess, bool near) {
  FibreBest out;
  std::vector<std::vector<double>> ves;
  for (std::size_t k = 0; k < plan.rounds() && (k == 0 || out.best.found); ++k) {
    const std::vector<Spot> spots =
        plan.round(k, out.best.found ? out.spots[out.best.index] : Spot{});
    const std::size_t base = ves.size();
    for (const Spot& at : spots) {
      ves.push_back(potential(at));
      out.spots.push_back(at);
    }
    out.best = search.minimum(ves, base, out.best, guess, out.best.found || near);
  }
  out.simulations = search.simulations();
  if (out.best.found) out.ve = std::move(ves[out.best.index]);
  return out;
}

// The best over a receptor's fibres (an afferent's two directions): the lowest lattice
// point, the first fibre on ties.
struct Winner {
  std::size_t fibre = 0;
  Spot spot;
  std::vector<double> ve;
  long j = 0;
  bool found = false;
  std::size_t node = 0;  // the search's run at j: the node that crossed first
};

// Where the winner fired: the node its search's run at the threshold crossed at first (the
// run is a function of the potential, amplitude and options alone: the same as a new one).
void where_it_fired(const Axon& axon, const Winner& winner, double amplitude_mA, bool vertical,
                    ReceptorThreshold& out) {
  const Spot& p = winner.spot;
  out.threshold_mA = amplitude_mA;
  out.offset_mm = p.offset_mm;
  out.direction = p.direction;
  out.spot = p;
  out.node = winner.node;
  const std::size_t last = axon.nodes.size() - 1;
  out.at_cut_end = winner.node + 5 > last || (!vertical && winner.node < 5);
  const std::size_t k = axon.nodes[winner.node];
  const double s_mm = axon.centre_um[k] * 1e-3;
  if (!axon.path.empty()) {
    out.x_mm = p.x0_mm + axon.path_x_mm[k];
    out.depth_mm = p.y0_mm + axon.path_y_mm[k];
  } else {
    out.x_mm = vertical ? p.x0_mm : p.x0_mm + s_mm;
    out.depth_mm = vertical ? p.y0_mm + s_mm : p.y0_mm;
  }
  out.z_mm = p.z0_mm;
}

// One search over the placements of the receptor's fibres as the settings lay them (their
// reach): the lowest lattice point, and where it fired.
ReceptorThreshold search_receptor(const FibreModel& model, const Setup& setup,
                                  const Conductor& conductor, const std::vector<double>& weights,
                                  const Receptor& r, const Waveform& waveform,
                                  const ThresholdSettings& s, PotentialCache& cache) {
  const FibreRun f = fibre_run(model, setup, conductor, r, waveform, s);
  const PlacementPlan plan(setup, r, s, f.internode_mm);
  const bool vertical = plan.vertical();
  const bool two_d = setup.array.two_d();
  const std::optional<double> start = caller_start(s);

  ReceptorThreshold out;
  out.receptor = r.name;
  Winner winner;
  long jmin = 0;
  for (std::size_t fi = 0; fi < f.axons.size(); ++fi) {
    const Axon& axon = f.axons[fi];
    AmplitudeSearch search(model, axon, waveform, detection_options(axon, f, s, vertical), s);
    jmin = search.jmin();
    // Where to start: the best so far (another direction's), else the caller's guess, else
    // the passive estimate (AmplitudeSearch; 1 mA without one).
    const long guess = winner.found ? winner.j : search.lattice().at_or_above(start.value_or(1.0));
    auto potential = [&](const Spot& at) {
      return potentials_mV(conductor, weights, axon, at.x0_mm, at.y0_mm, vertical, at.z0_mm, two_d,
                           cache);
    };
    FibreBest b =
        search_placements(search, plan, potential, guess, winner.found || start.has_value());
    out.placements += b.spots.size();
    for (Spot at : b.spots) {
      at.direction = f.directions[fi];
      out.tried.push_back(at);
    }
    out.simulations += b.simulations;
    if (b.best.found && (!winner.found || b.best.j < winner.j)) {
      winner = {fi, b.spots[b.best.index], std::move(b.ve), b.best.j, true, b.best.node};
      winner.spot.direction = f.directions[fi];
    }
  }
  const AmplitudeLattice lattice(s.tolerance);
  if (!winner.found) {
    out.reason = "does not fire below " + number_text(s.max_mA) + " mA";
    return out;
  }
  if (winner.j < jmin) {
    out.reason = "fires even at " + number_text(lattice.amplitude(jmin)) +
                 " mA, the bottom of the search range";
    return out;
  }
  const Axon& axon = f.axons[winner.fibre];
  where_it_fired(axon, winner, lattice.amplitude(winner.j), vertical, out);
  return out;
}

// A fibre's reach at most (64 default extensions: 0.6 m beyond the pads for the default
// margin; the bounds on nodes and potentials stop it sooner).
constexpr double kMaxReach = 64.0;

// The reach one doubling further where the threshold's action potential started: an
// afferent's stem on its side, a straight vertical fibre's deep end, a horizontal fibre's
// end it fired at.
ThresholdSettings::Reach doubled_reach(const ReceptorThreshold& t, const Receptor& r,
                                       const ThresholdSettings& s, bool afferent) {
  ThresholdSettings::Reach reach = s.reach;
  if (afferent)
    (t.direction < 0 ? reach.minus_x : reach.plus_x) *= 2.0;
  else if (r.fibre.orientation == Orientation::vertical)
    reach.below *= 2.0;
  else
    (t.node < 5 ? reach.minus_x : reach.plus_x) *= 2.0;
  return reach;
}

// Why a fibre of the settings' reach cannot be searched (its nodes, potentials or reach
// beyond the bounds fibre_nodes checks, or its work beyond one search's), or empty.
std::string why_not_searched(const FibreModel& model, const Setup& setup,
                             const Conductor& conductor, const Receptor& r,
                             const Waveform& waveform, const ThresholdSettings& s) {
  try {
    const double work = threshold_work(model, setup, conductor, r, waveform, s);
    if (!(work <= kMaxThresholdWork)) return "its search would be more than the work bound";
  } catch (const Error& e) {
    if (e.code() != ExitCode::bad_input) throw;
    return e.what();
  }
  return {};
}

}  // namespace

ReceptorThreshold receptor_threshold(const FibreModel& model, const Setup& setup,
                                     const Conductor& conductor, const std::vector<double>& weights,
                                     const Receptor& r, const Waveform& waveform,
                                     const ThresholdSettings& s, PotentialCache* shared_cache) {
  PotentialCache local_cache;
  PotentialCache& cache = shared_cache ? *shared_cache : local_cache;
  ReceptorThreshold out = search_receptor(model, setup, conductor, weights, r, waveform, s, cache);
  out.reach = s.reach;
  out.searches = 1;
  // A cut end: the fibre doubled beyond the pads where it fired and searched again, from
  // the threshold found, until the action potential starts inside (docs/fibres.md, "Cut
  // ends").  Only such receptors search again.
  ThresholdSettings longer = s;
  const bool afferent = is_afferent(r, s);
  while (s.lengthen && out.threshold_mA && out.at_cut_end) {
    if (r.fibre.orientation == Orientation::vertical && !afferent && s.extra_internodes == 0) {
      out.cut_end_reason = "its deep end cannot be moved (no internodes asked below the receptor)";
      break;
    }
    longer.reach = doubled_reach(out, r, longer, afferent);
    if (std::max({longer.reach.minus_x, longer.reach.plus_x, longer.reach.below}) > kMaxReach) {
      out.cut_end_reason = "still at a cut end " + number_text(kMaxReach) +
                           " times as far beyond the pads as by default";
      break;
    }
    const std::string why = why_not_searched(model, setup, conductor, r, waveform, longer);
    if (!why.empty()) {
      out.cut_end_reason = "cannot be lengthened further: " + why;
      break;
    }
    longer.start_mA = {*out.threshold_mA};
    ReceptorThreshold again =
        search_receptor(model, setup, conductor, weights, r, waveform, longer, cache);
    again.simulations += out.simulations;  // placements and tried: the last search's
    again.searches = out.searches + 1;
    again.reach = longer.reach;
    out = std::move(again);
  }
  return out;
}

}  // namespace tp::fibre
