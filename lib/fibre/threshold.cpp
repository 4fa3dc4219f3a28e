// Threshold search over fibre placements, on a fixed amplitude lattice (threshold.hpp).

#include "fibre/threshold.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <tuple>

#include "core/error.hpp"
#include "io/number.hpp"

namespace tp::fibre {

Lattice::Lattice(double tolerance)
    : per_octave(static_cast<long>(std::ceil(std::log(2.0) / std::log1p(tolerance)))) {}

double Lattice::amplitude(long j) const {
  // j = q K + r with 0 <= r < K: 2^q exactly times 2^(r/K), so amplitude(j + K) is exactly
  // twice amplitude(j).
  long q = j / per_octave, r = j % per_octave;
  if (r < 0) {
    r += per_octave;
    --q;
  }
  return std::ldexp(std::exp2(static_cast<double>(r) / static_cast<double>(per_octave)),
                    static_cast<int>(q));
}

long Lattice::at_or_above(double a) const {
  long j = static_cast<long>(std::ceil(std::log2(a) * static_cast<double>(per_octave)));
  while (amplitude(j - 1) >= a) --j;
  while (amplitude(j) < a) ++j;
  return j;
}

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

namespace {

constexpr std::size_t kMaxNodes = 2000;  // a 2 um MRG fibre 400 mm long
constexpr double kMaxPotentials = 3e7;   // 240 MB of unit potentials

// One fibre position: the potential along it for amplitude 1, and where its first node is.
struct Placement {
  std::vector<double> ve_mV;
  double x0_mm = 0.0, y0_mm = 0.0;  // the first node
  double z0_mm = 0.0;               // 2-D arrays: the fibre's z
  bool vertical = false;
  double offset_mm = 0.0;
};

// The lexicographic best (lattice point, placement index) so far.
struct Best {
  bool found = false;
  long j = 0;
  std::size_t index = 0;
  bool beats(long jj, std::size_t ii) const { return !found || jj < j || (jj == j && ii < index); }
};

// A fibre's largest activating function at its nodes, either sign (a biphasic pulse drives
// both): the second difference of the potential, or at an end node the first.
double largest_af(const Axon& axon, const double* ve) {
  const std::vector<std::size_t>& n = axon.nodes;
  double most = 0.0;
  for (std::size_t j = 0; j < n.size(); ++j) {
    double af;
    if (j == 0)
      af = n.size() > 1 ? ve[n[1]] - ve[n[0]] : 0.0;
    else if (j + 1 == n.size())
      af = ve[n[j - 1]] - ve[n[j]];
    else
      af = ve[n[j - 1]] - 2.0 * ve[n[j]] + ve[n[j + 1]];
    most = std::max(most, std::fabs(af));
  }
  return most;
}

// How long the passive estimate's runs go on after the waveform (the peak depolarisation
// comes at a phase's end).
constexpr double kPassiveAfter_ms = 0.05;

// The depolarisation at the end of a pulse at which an MRG node fires, about (the passive
// estimate, Search::estimate): 4.3 + 5.3 / sqrt(the longest phase in ms) mV; 0 for a
// waveform without a phase.
double passive_k_mV(const Waveform& w) {
  double longest = 0.0;
  for (const Waveform::Phase& ph : w.phases)
    if (ph.level != 0.0) longest = std::max(longest, ph.duration_ms);
  return longest > 0.0 ? 4.3 + 5.3 / std::sqrt(longest) : 0.0;
}

class Search {
 public:
  Search(const FibreModel& model, const Axon& axon, const Waveform& w, const SimOptions& o,
         const ThresholdSettings& s)
      : model_(model),
        axon_(axon),
        w_(w),
        o_(o),
        settling_(o),
        lat_(s.tolerance),
        jmax_(lat_.at_or_above(s.max_mA)),
        jmin_(jmax_ - 50 * lat_.per_octave),
        threads_(s.threads ? s.threads : std::max(1u, std::thread::hardware_concurrency())) {
    o_.stop_when_settled = false;
    settling_.stop_when_settled = s.settle;
  }

  // The lexicographic minimum of (threshold lattice point, index) over placements
  // ps[base..], given `best` over the placements before them.
  //
  // No exception leaves a worker: each is caught there, the placements with a higher index
  // than the failing one are skipped, and the failure of the lowest placement index is
  // rethrown here, on the caller's thread, once every worker has joined.
  //
  // The placements are searched in the order of their activating function, the strongest
  // first (drive()): the answer does not depend on the order, but the work does, since a
  // placement that cannot beat the best so far costs one simulation.
  // guess: where a search starts without a best; close: it is a threshold (of another
  // fibre, or of nearby weights); not close: the passive estimate, if there is one, else
  // guess (1 mA).
  Best minimum(const std::vector<Placement>& ps, std::size_t base, Best best, long guess,
               bool close) {
    std::vector<std::size_t> order(ps.size() - base);
    std::vector<double> key(ps.size() - base);
    for (std::size_t i = base; i < ps.size(); ++i) {
      order[i - base] = i;
      key[i - base] = drive(ps[i]);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return key[a - base] > key[b - base]; });
    std::atomic<std::size_t> next{0};
    std::mutex m;
    std::exception_ptr error;
    std::size_t error_index = ps.size();
    auto work = [&] {
      try {
        CableSimulator sim(model_, axon_);
        for (;;) {
          const std::size_t position = next.fetch_add(1);
          if (position >= order.size()) return;
          const std::size_t i = order[position];
          Best snap;
          long g;
          bool near;
          {
            std::lock_guard<std::mutex> lock(m);
            if (i > error_index) continue;  // after a failure: skipped
            snap = best;
            g = best.found ? best.j : guess;
            near = close || best.found;
          }
          long j;
          bool found;
          try {
            found = search_one(sim, ps[i], i, snap, g, near, j);
          } catch (...) {
            std::lock_guard<std::mutex> lock(m);
            if (i < error_index) {
              error_index = i;
              error = std::current_exception();
            }
            continue;  // a lower index may fail too: its failure is the one reported
          }
          if (!found) continue;
          std::lock_guard<std::mutex> lock(m);
          if (best.beats(j, i)) best = {true, j, i};
        }
      } catch (...) {  // the simulator's construction: before any placement
        std::lock_guard<std::mutex> lock(m);
        if (!error) error = std::current_exception();
      }
    };
    const unsigned n = static_cast<unsigned>(std::min<std::size_t>(threads_, ps.size() - base));
    if (n <= 1) {
      work();
    } else {
      std::vector<std::thread> pool;
      try {
        for (unsigned t = 0; t < n; ++t) pool.emplace_back(work);
      } catch (...) {  // no thread to be had: join those started, then report
        next = order.size();
        for (auto& t : pool) t.join();
        throw;
      }
      for (auto& t : pool) t.join();
    }
    if (error) std::rethrow_exception(error);
    return best;
  }

  // A placement's largest activating function at its nodes (largest_af()).
  double drive(const Placement& p) const { return largest_af(axon_, p.ve_mV.data()); }

  const Lattice& lattice() const { return lat_; }
  long jmax() const { return jmax_; }
  long jmin() const { return jmin_; }
  std::size_t simulations() const { return simulations_; }

 private:
  struct Probe {
    bool fired, excited;
  };
  // The probes of the search for excitation.  A run that excites no node may pause once it
  // has settled (SimOptions::stop_when_settled): the search goes on as if it had not
  // excited the fibre, and before any decision rests on that, confirm() runs the last such
  // run to its end.  Excitation grows with the amplitude, so if the highest point taken
  // as not exciting does not excite at the end of its run, neither do those below it, and
  // the answer is that of runs to their ends.  If it does, the search is repeated with
  // every run to its end (search_one).
  static constexpr long kNone = std::numeric_limits<long>::min();
  struct Excitation {
    CableSimulator& sim;
    const Placement& p;
    bool settle;
    long paused = kNone;  // the point whose run paused, if it is the last that did not excite
  };
  Probe probe(Excitation& e, long j) {
    ++simulations_;
    const SimResult r =
        e.sim.run(e.p.ve_mV.data(), lat_.amplitude(j), w_, e.settle ? settling_ : o_);
    const bool excited = r.first_time_ms >= 0.0;
    if (!excited) e.paused = r.settled ? j : kNone;
    return {r.fired, excited};
  }
  // Whether the runs taken as not exciting at j and below are so to their ends.
  bool confirm(Excitation& e, long j) {
    if (e.paused != j) return true;  // j's run went to its end
    if (e.sim.paused_amplitude() != lat_.amplitude(j))
      failure("fibre: the paused run is not the one to confirm");
    e.paused = kNone;
    return e.sim.resume(e.p.ve_mV.data(), lat_.amplitude(j), w_, o_).first_time_ms < 0.0;
  }

  // Where a search without a guess starts: the passive estimate.  Below threshold the
  // membrane responds nearly in proportion to the amplitude; a node fires when it is
  // depolarised by about K mV at the end of the pulse, K falling with the pulse's length
  // (MRG, 4 to 16 um, 0.05 to 1 ms, either polarity, mono- or biphasic: K = 4.3 +
  // 5.3 / sqrt(longest phase in ms) mV within about 25 %).  One short run at an amplitude
  // that drives the nodes by 1 mV of activating function, to 0.05 ms after the waveform,
  // gives the peak depolarisation dv; the estimate is that amplitude times K / dv.  Only
  // the work depends on it, not the answer.  None when the field does not depolarise.
  std::optional<long> estimate(CableSimulator& sim, const Placement& p) {
    const double a0 = 1.0 / drive(p);
    if (!std::isfinite(a0) || !(a0 > 0.0)) return std::nullopt;
    const double k_mV = passive_k_mV(w_);
    if (!(k_mV > 0.0)) return std::nullopt;
    SimOptions o = o_;
    o.tstop_ms = std::min(o_.tstop_ms, w_.end_ms() + kPassiveAfter_ms);
    o.detect.clear();
    ++simulations_;
    sim.run(p.ve_mV.data(), a0, w_, o);
    double dv = 0.0;
    for (double v : sim.peak_node_mV()) dv = std::max(dv, v - model_.initial_mV());
    if (!(dv > 1e-9)) return std::nullopt;
    const double a = a0 * k_mV / dv;
    if (!std::isfinite(a) || a > lat_.amplitude(jmax_)) return jmax_;
    if (a < lat_.amplitude(jmin_)) return jmin_;
    return lat_.at_or_above(a);
  }

  // This placement's threshold j, if it can beat `best`; false when it cannot.
  //
  // Firing is not monotone in the amplitude: far above threshold the hyperpolarised
  // neighbours of an excited node block the action potential.  Excitation (some node above
  // detect_mV) is: it only grows with the amplitude.  So the search first finds e, the lowest
  // lattice point that excites the fibre anywhere, by bracketing and bisection on
  // excitation; the threshold is the first point from e up that fires (nearly always e
  // itself).  Both depend on this placement alone, not on the bracket the search started
  // from: the answer is the same whichever thread searched it, and in whatever order.
  bool search_one(CableSimulator& sim, const Placement& p, std::size_t i, const Best& best,
                  long guess, bool near, long& out) {
    Excitation settling{sim, p, settling_.stop_when_settled};
    if (const std::optional<bool> r = search_from(settling, i, best, guess, near, out)) return *r;
    Excitation to_end{sim, p, false};  // a paused run excited after all (rare)
    return *search_from(to_end, i, best, guess, near, out);
  }

  // search_one with the probes of e; none when a run taken as not exciting excited the
  // fibre after all.
  std::optional<bool> search_from(Excitation& e, std::size_t i, const Best& best, long guess,
                                  bool near, long& out) {
    CableSimulator& sim = e.sim;
    const Placement& p = e.p;
    // The largest lattice point at which firing would still beat the best.
    const long limit = !best.found ? jmax_ : (i < best.index ? best.j : best.j - 1);
    if (limit < jmin_) return false;
    long lo, hi;  // lo does not excite, hi excites
    bool hi_fired;
    // Galloping from g, by steps that double: from 1/32 octave (2.2 %) when g is near (a
    // threshold: the best so far, another fibre's, nearby weights'), so that a close guess
    // costs a few probes; from 1/8 octave from the passive estimate (within about 1/3
    // octave); else from an octave.
    long first_step = lat_.per_octave;
    if (near || best.found) {
      first_step = std::max(1L, lat_.per_octave / 32);
    } else if (const std::optional<long> est = estimate(sim, p)) {
      guess = *est;
      first_step = std::max(1L, lat_.per_octave / 8);
    }
    const long g = best.found ? limit : std::min(std::max(guess, jmin_), limit);
    Probe pg = probe(e, g);
    if (pg.excited) {
      hi = g;
      hi_fired = pg.fired;
      for (long step = first_step;; step *= 2) {
        lo = std::max(hi - step, jmin_);
        const Probe q = probe(e, lo);
        if (!q.excited) break;
        hi = lo;
        hi_fired = q.fired;
        if (lo == jmin_) {  // excited at the floor: below the search range
          out = jmin_ - 1;
          return true;
        }
      }
    } else {
      if (g == limit) {  // not even excited at the limit
        if (!confirm(e, g)) return std::nullopt;
        return false;
      }
      lo = g;
      for (long step = first_step;; step *= 2) {
        hi = std::min(lo + step, limit);
        const Probe q = probe(e, hi);
        if (q.excited) {
          hi_fired = q.fired;
          break;
        }
        if (hi == limit) {
          if (!confirm(e, hi)) return std::nullopt;
          return false;
        }
        lo = hi;
      }
    }
    while (hi - lo > 1) {
      const long mid = lo + (hi - lo) / 2;
      const Probe q = probe(e, mid);
      if (q.excited) {
        hi = mid;
        hi_fired = q.fired;
      } else {
        lo = mid;
      }
    }
    if (!confirm(e, lo)) return std::nullopt;
    if (hi_fired) {
      out = hi;
      return true;
    }
    Excitation to_end{sim, p, false};
    return first_firing(to_end, hi, limit, out);
  }

  // Excited at e = hi without an action potential reaching the detection nodes: gallop up
  // to a point that fires, then bisect back.  Firing need not be monotone above e, so the
  // gallop runs to the top of the search range whatever `limit` is, and the point it finds
  // depends on e alone (not on the best so far, nor on the order of the placements); it
  // counts only if it is at most `limit`.  Its probes (`whole`) run to their ends.
  bool first_firing(Excitation& whole, long hi, long limit, long& out) {
    long f_lo = hi, f_hi = hi;
    for (long step = 1;; step *= 2) {
      f_hi = hi + step;
      if (f_hi > jmax_) {
        if (f_lo == jmax_) return false;
        f_hi = jmax_;
      }
      if (probe(whole, f_hi).fired) break;
      if (f_hi == jmax_) return false;
      f_lo = f_hi;
    }
    while (f_hi - f_lo > 1) {
      const long mid = f_lo + (f_hi - f_lo) / 2;
      (probe(whole, mid).fired ? f_hi : f_lo) = mid;
    }
    if (f_hi > limit) return false;
    out = f_hi;
    return true;
  }

  const FibreModel& model_;
  const Axon& axon_;
  const Waveform& w_;
  SimOptions o_;         // every run to its end
  SimOptions settling_;  // o_, pausing runs once settled (unless the settings say not to)
  Lattice lat_;
  long jmax_, jmin_;
  unsigned threads_;
  std::atomic<std::size_t> simulations_{0};
};

std::vector<double> potentials_mV(const Conductor& c, const std::vector<double>& weights,
                                  const Axon& axon, double x0, double y0, bool vertical, double z0,
                                  bool three_d, PotentialCache& cache) {
  const std::vector<double>& psi = cache.unit(c, axon, x0, y0, vertical, z0, three_d);
  const std::size_t n = weights.size();
  std::vector<double> ve(axon.centre_um.size());
  for (std::size_t k = 0; k < ve.size(); ++k) {
    double v = 0.0;
    for (std::size_t i = 0; i < n; ++i) v += weights[i] * psi[k * n + i];
    ve[k] = 1e3 * v;  // V -> mV
  }
  return ve;
}

}  // namespace

bool Spot::operator==(const Spot& o) const {
  return direction == o.direction && x0_mm == o.x0_mm && y0_mm == o.y0_mm && z0_mm == o.z0_mm &&
         offset_mm == o.offset_mm;
}

bool PotentialCache::Key::operator<(const Key& o) const {
  return std::tie(model, path, diameter_um, x0_mm, y0_mm, z0_mm, compartments, vertical, three_d) <
         std::tie(o.model, o.path, o.diameter_um, o.x0_mm, o.y0_mm, o.z0_mm, o.compartments,
                  o.vertical, o.three_d);
}

const std::vector<double>& PotentialCache::unit(const Conductor& c, const Axon& axon, double x0,
                                                double y0, bool vertical, double z0, bool three_d) {
  if (!three_d) z0 = 0.0;
  Key key{axon.model, axon.path, axon.diameter_um, x0, y0, z0, axon.centre_um.size(),
          vertical,   three_d};
  auto it = std::lower_bound(entries_.begin(), entries_.end(), key,
                             [](const auto& e, const Key& k) { return e.first < k; });
  if (it != entries_.end() && !(key < it->first)) return it->second;
  const std::size_t n = c.size();
  std::vector<double> psi(axon.centre_um.size() * n);
  // Bounded: past kMaxCached values the cache starts again (callers hold no references).
  stored_ += psi.size();
  if (stored_ > kMaxCached) {
    entries_.clear();
    stored_ = psi.size();
    it = entries_.end();
  }
  for (std::size_t k = 0; k < axon.centre_um.size(); ++k) {
    const double s = axon.centre_um[k] * 1e-3;
    double x = vertical ? x0 : x0 + s, y = vertical ? y0 + s : y0;
    if (!axon.path.empty()) {  // laid along a path from (x0, y0)
      x = x0 + axon.path_x_mm[k];
      y = y0 + axon.path_y_mm[k];
    }
    if (three_d)
      c.unit_potentials_3d(x, y, z0, &psi[k * n]);
    else
      c.unit_potentials(x, y, &psi[k * n]);
  }
  return entries_.insert(it, {std::move(key), std::move(psi)})->second;
}

namespace {
// The step vertical fibres are sampled at: a quarter of it.  A 1-D array's mean pitch (1 mm
// for one electrode); a 2-D grid's smaller pitch, free pads' nearest two centres.
double sampling_pitch_mm(const ElectrodeArray& a) {
  if (!a.two_d())
    return a.size() > 1 ? (a.x_max_mm() - a.x_min_mm()) / static_cast<double>(a.size() - 1) : 1.0;
  if (a.grid() && a.pitch_mm) {
    double p = *a.pitch_mm;
    if (a.rows > 1 && a.row_pitch_mm > 0) p = std::min(p, a.row_pitch_mm);
    if (a.columns == 1 && a.rows > 1) p = a.row_pitch_mm;
    return p;
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j)
      best =
          std::min(best, std::hypot(a.positions_mm[i] - a.positions_mm[j], a.z_mm[i] - a.z_mm[j]));
  return std::isfinite(best) ? best : 1.0;
}
// Vertical fibres under a 2-D array: every quarter pitch within half a pitch of the point
// in x and z (5 x 5), then twice 5 x 5 at half the step around the best.
constexpr double kVertical2dPlacements = 75.0;

bool is_afferent(const Receptor& r, const ThresholdSettings& s) {
  return s.geometry == Geometry::afferent && r.fibre.orientation == Orientation::vertical;
}
// The x of every ending an afferent search tries: a population's one; under a 2-D array
// within a pitch of the point; else across the pads, a pitch and a half beyond each side
// (the search's first round reaches one pitch, its refinements a third of one more).
std::array<double, 2> ending_range_mm(const Setup& setup, const ThresholdSettings& s) {
  if (s.fixed_x_mm) return {*s.fixed_x_mm, *s.fixed_x_mm};
  const double p = sampling_pitch_mm(setup.array);
  if (setup.array.two_d()) return {(*s.through_mm)[0] - p, (*s.through_mm)[0] + p};
  return {setup.array.x_min_mm() - 1.5 * p, setup.array.x_max_mm() + 1.5 * p};
}
// An afferent's stem, from the bend: from the farthest ending it serves, past the far side
// of the pads plus the lateral margin (where horizontal fibres end) by five internodes.
double afferent_stem_mm(const Setup& setup, const ThresholdSettings& s, double L_mm,
                        int direction) {
  const auto [lo, hi] = ending_range_mm(setup, s);
  const double m = setup.lateral_margin_mm;
  const double span =
      direction < 0 ? hi - (setup.array.x_min_mm() - m) : (setup.array.x_max_mm() + m) - lo;
  return std::max(span, 0.0) + 5.0 * L_mm;
}
Axon afferent_for(const FibreModel& model, const Setup& setup, const Receptor& r,
                  const ThresholdSettings& s, int direction) {
  const double d = r.fibre.diameter_um;
  return afferent_axon(model, d, r.depth_max_mm - r.depth_min_mm, direction,
                       afferent_stem_mm(setup, s, model.internode_um(d) * 1e-3, direction),
                       s.shape);
}
// The stem directions an afferent's search tries, in order (ties go to the first).
std::vector<int> afferent_directions(const ThresholdSettings& s) {
  if (s.fixed_direction) return {*s.fixed_direction};
  return {-1, 1};
}
}  // namespace

std::size_t fibre_nodes(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                        const Receptor& r, const ThresholdSettings& s) {
  const bool two_d = setup.array.two_d();
  if (two_d && !s.through_mm)
    bad_input("array: " + setup.array.describe() +
              " is 2-D: give the point the fibres pass through (fiber-threshold --at X,Z; a "
              "pixel's document, optimize-weights --at, carries its focus)");
  if (two_d) {
    const auto [px, pz] = *s.through_mm;
    const double m = setup.lateral_margin_mm;
    if (!(px >= setup.array.x_min_mm() - m && px <= setup.array.x_max_mm() + m &&
          pz >= setup.array.z_min_mm() - m && pz <= setup.array.z_max_mm() + m))
      bad_input("--at: (" + number_text(px) + ", " + number_text(pz) +
                ") mm is outside the pads plus the lateral margin (" + number_text(m) + " mm)");
  }
  const double d = r.fibre.diameter_um;
  if (!r.fibre.myelinated)
    bad_input("receptor " + r.name + ": the fibre models are myelinated (myelinated: false)");
  if (d < model.min_diameter_um() || d > model.max_diameter_um())
    bad_input("receptor " + r.name + ": diameter " +
              number_beside(d, model.min_diameter_um(), model.max_diameter_um()) + " um outside " +
              model.name() + "'s range [" + number_text(model.min_diameter_um()) + ", " +
              number_text(model.max_diameter_um()) + "] um");
  const double L_mm = model.internode_um(d) * 1e-3;
  const bool vertical = r.fibre.orientation == Orientation::vertical;
  const Region reg = fibre_region(setup, r);

  if (s.fixed_direction && *s.fixed_direction != 1 && *s.fixed_direction != -1)
    bad_input("an afferent's stem direction must be -1 or +1");
  const bool afferent = is_afferent(r, s);
  // An afferent's two stems, built once: their node counts and, below, their far ends.
  std::vector<Axon> stems;
  if (afferent)
    for (int dir : {-1, 1}) stems.push_back(afferent_for(model, setup, r, s, dir));
  std::size_t nodes;
  if (afferent) {
    nodes = std::max(stems[0].nodes.size(), stems[1].nodes.size());
  } else if (vertical) {
    nodes = static_cast<std::size_t>(std::ceil((r.depth_max_mm - r.depth_min_mm) / L_mm - 1e-9)) +
            s.extra_internodes + 1;
  } else {
    nodes = static_cast<std::size_t>(std::ceil((reg.x1_mm - reg.x0_mm) / L_mm - 1e-9)) + 12;
  }
  if (nodes < 12) nodes = 12;
  // A buried point source (point3d) on or near a fibre's path: the potential is singular
  // there, and within an internode of the path the compartments do not resolve it.  The
  // fibre occupies the depths [top, bottom] (a vertical one down to its deep end, the
  // internodes below the receptor included) at every x across the array, in the plane
  // z = plane_z_mm; the sources lie at depth d in z = 0.
  if (setup.conductor.model == "point3d" && setup.conductor.source_depth_mm > 0.0) {
    const double src = setup.conductor.source_depth_mm;
    const double top = r.depth_min_mm;
    const double bottom = vertical && !afferent
                              ? r.depth_min_mm + static_cast<double>(nodes - 1) * L_mm
                              : r.depth_max_mm;
    const double gap = src < top ? top - src : src > bottom ? src - bottom : 0.0;
    double dz = setup.conductor.plane_z_mm;
    if (two_d) {  // the nearest pad's source, from the fibres' z
      dz = std::numeric_limits<double>::infinity();
      for (std::size_t e = 0; e < setup.array.size(); ++e)
        dz = std::min(dz, std::fabs((*s.through_mm)[1] - setup.array.z_of(e)));
    }
    const double distance = std::hypot(gap, dz);
    if (!(distance >= L_mm))
      bad_input("model.source_depth_mm: " + number_text(src) + " mm is " +
                number_beside(distance, L_mm) + " mm from receptor " + r.name + "'s " +
                (vertical ? "vertical" : "horizontal") + " fibre (depths " + number_text(top) +
                " to " + number_text(bottom) + " mm), less than one internode (" +
                number_text(L_mm) + " mm): the source would be on or too near its path");
  }
  // Bounded work and memory: a fibre of at most kMaxNodes nodes, and the unit potentials of
  // all its placements (compartments x electrodes x placements) at most kMaxPotentials.
  if (nodes > kMaxNodes)
    bad_input("receptor " + r.name + ": its fibre would need " + std::to_string(nodes) +
              " nodes (at most " + std::to_string(kMaxNodes) + "): the array and margins span " +
              number_text(vertical ? r.depth_max_mm - r.depth_min_mm : reg.x1_mm - reg.x0_mm) +
              " mm at " + number_text(L_mm) + " mm per internode");
  {
    const double compartments =
        static_cast<double>(nodes) * static_cast<double>(model.axon(d, 2).compartments.size() - 1);
    const double per_placement = compartments * static_cast<double>(conductor.size());
    // Vertical: every quarter pitch across the array +- one pitch, then 2 x 9 refinements.
    const double placements =
        (vertical
             ? two_d ? kVertical2dPlacements
                     : 4.0 * static_cast<double>(std::max<std::size_t>(setup.array.size(), 2) - 1) +
                           27.0
             : static_cast<double>(s.offsets) * (r.depth_max_mm > r.depth_min_mm ? 5 : 1)) *
        static_cast<double>(afferent ? afferent_directions(s).size() : 1);
    if (per_placement * (s.fixed_x_mm || s.fixed_offset_mm ? 1.0 : placements) > kMaxPotentials)
      bad_input("receptor " + r.name + ": " + number_text(per_placement * placements) +
                " unit potentials to keep (at most " + number_text(kMaxPotentials) +
                "): fewer electrodes, a shorter array or fewer --offsets");
  }
  // Every compartment's potential can be evaluated (the layered model's Hankel rule is
  // bounded far from the electrodes, for shallow fibres): the farthest any placement's
  // compartment lies from an electrode, over the depths the fibre occupies.  Horizontal: the
  // first node within six internodes before the region, the fibre at most `nodes`
  // internodes long; vertical: across the array +- one pitch, refined by at most a quarter
  // and a sixteenth of a pitch beyond.
  {
    const double x_min = setup.array.x_min_mm(), x_max = setup.array.x_max_mm();
    const double pitch_mm = sampling_pitch_mm(setup.array);
    double reach_mm, bottom_mm;
    if (afferent) {  // either stem's far end, as built, from the farthest pad
      const auto [lo, hi] = ending_range_mm(setup, s);
      reach_mm = std::max(x_max - lo, hi - x_min);
      for (const Axon& a : stems) {
        const double back = a.path_x_mm.back();
        for (double tip : {lo, hi})
          reach_mm =
              std::max({reach_mm, std::fabs(tip + back - x_min), std::fabs(tip + back - x_max)});
      }
      if (two_d) {
        const double pz = (*s.through_mm)[1];
        reach_mm =
            std::hypot(reach_mm, std::max(std::fabs(pz + pitch_mm - setup.array.z_min_mm()),
                                          std::fabs(setup.array.z_max_mm() - (pz - pitch_mm))));
      }
      bottom_mm = r.depth_max_mm;
    } else if (vertical && two_d) {  // within half a pitch of the point, refined a quarter beyond
      const auto [px, pz] = *s.through_mm;
      const double dx =
          std::max(std::fabs(px + pitch_mm - x_min), std::fabs(x_max - (px - pitch_mm)));
      const double dz = std::max(std::fabs(pz + pitch_mm - setup.array.z_min_mm()),
                                 std::fabs(setup.array.z_max_mm() - (pz - pitch_mm)));
      reach_mm = std::hypot(dx, dz);
      bottom_mm = r.depth_min_mm + static_cast<double>(nodes) * L_mm;
    } else if (vertical) {
      reach_mm = x_max - x_min + 1.5 * pitch_mm;
      bottom_mm = r.depth_min_mm + static_cast<double>(nodes) * L_mm;
    } else {
      const double first_mm = reg.x0_mm - 6.0 * L_mm;
      const double last_mm = first_mm + static_cast<double>(nodes + 1) * L_mm;
      reach_mm = std::max(std::fabs(last_mm - x_min), std::fabs(x_max - first_mm));
      if (two_d) {
        const double pz = (*s.through_mm)[1];
        reach_mm = std::hypot(reach_mm, std::max(std::fabs(pz - setup.array.z_min_mm()),
                                                 std::fabs(setup.array.z_max_mm() - pz)));
      }
      bottom_mm = r.depth_max_mm;
    }
    conductor.check_reach(reach_mm, r.depth_min_mm, bottom_mm,
                          "receptor " + r.name + "'s simulated fibre");
  }
  return nodes;
}

namespace {
// The fibres a receptor's search simulates (one; an afferent's, one per stem direction,
// with the directions), and the simulation's end.
struct FibreRun {
  std::size_t nodes;
  double internode_mm, tstop_ms;
  std::vector<Axon> axons;
  std::vector<int> directions;
};
FibreRun fibre_run(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                   const Receptor& r, const Waveform& waveform, const ThresholdSettings& s) {
  const double d = r.fibre.diameter_um;
  const std::size_t nodes = fibre_nodes(model, setup, conductor, r, s);
  FibreRun f{nodes, model.internode_um(d) * 1e-3, 0.0, {}, {0}};
  if (is_afferent(r, s)) {
    f.directions = afferent_directions(s);
    for (int dir : f.directions) f.axons.push_back(afferent_for(model, setup, r, s, dir));
  } else {
    f.axons.push_back(model.axon(d, nodes));
  }
  double length_mm = 0.0;  // the longest fibre's: one end time for every direction
  for (const Axon& a : f.axons) length_mm = std::max(length_mm, a.length_um() * 1e-3);
  const double after = s.after_ms > 0 ? s.after_ms : 1.0 + length_mm / (2.0 * d);
  f.tstop_ms = waveform.end_ms() + after;
  return f;
}
}  // namespace

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
  const bool vertical = r.fibre.orientation == Orientation::vertical;
  const double placements =
      (vertical && s.fixed_x_mm) || (!vertical && s.fixed_offset_mm) ? 1.0
      : vertical && setup.array.two_d()                              ? kVertical2dPlacements
      : vertical
          ? 4.0 * static_cast<double>(std::max<std::size_t>(setup.array.size(), 2) + 1) + 1.0 + 18.0
          : static_cast<double>(s.offsets) * (r.depth_max_mm > r.depth_min_mm ? 5 : 1);
  const double probes =
      std::ceil(std::log2(static_cast<double>(Lattice(s.tolerance).per_octave))) + 4.0;
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
// The caller's guess (settings.start_mA's first entry), if it is one: positive and finite,
// at most max_mA.
std::optional<double> caller_start(const ThresholdSettings& s) {
  if (s.start_mA.empty() || !(s.start_mA.front() > 0.0) || !std::isfinite(s.start_mA.front()))
    return std::nullopt;
  return std::min(s.start_mA.front(), s.max_mA);
}
}  // namespace

std::optional<double> fibre_threshold(const FibreModel& model, const Axon& axon,
                                      const std::vector<double>& ve_unit_mV,
                                      const Waveform& waveform, const SimOptions& options,
                                      const ThresholdSettings& settings) {
  if (ve_unit_mV.size() != axon.compartments.size())
    bad_input("fibre: one potential per compartment is needed");
  if (!(settings.tolerance >= 1e-4 && settings.tolerance <= 0.1))
    bad_input("fibre: tolerance must be within 1e-4 to 0.1");
  if (!(settings.max_mA > 0.0 && std::isfinite(settings.max_mA)))
    bad_input("fibre: max_mA must be positive and finite");
  Search search(model, axon, waveform, options, settings);
  const std::optional<double> start = caller_start(settings);
  const long guess = search.lattice().at_or_above(start.value_or(1.0));
  const bool near = start.has_value();
  std::vector<Placement> ps(1);
  ps[0].ve_mV = ve_unit_mV;
  const Best best = search.minimum(ps, 0, Best{}, guess, near);
  if (!best.found || best.j < search.jmin()) return std::nullopt;
  return search.lattice().amplitude(best.j);
}

ReceptorThreshold receptor_threshold(const FibreModel& model, const Setup& setup,
                                     const Conductor& conductor, const std::vector<double>& weights,
                                     const Receptor& r, const Waveform& waveform,
                                     const ThresholdSettings& s, PotentialCache* shared_cache) {
  PotentialCache local_cache;
  PotentialCache& cache = shared_cache ? *shared_cache : local_cache;
  const FibreRun f = fibre_run(model, setup, conductor, r, waveform, s);
  const double L_mm = f.internode_mm;
  const bool vertical = r.fibre.orientation == Orientation::vertical;
  const Region reg = fibre_region(setup, r);
  const bool two_d = setup.array.two_d();  // fibre_nodes: then through_mm is set
  const double z_fibre = two_d ? (*s.through_mm)[1] : 0.0;

  ReceptorThreshold out;
  out.receptor = r.name;
  // The best over the fibres (an afferent's two directions): the lowest lattice point, the
  // first fibre on ties.
  struct Winner {
    std::size_t fibre = 0;
    Placement placement;
    long j = 0;
    bool found = false, below_range = false;
  } winner;
  std::size_t simulations = 0;
  long jmin = 0;
  auto options = [&](const Axon& axon) {
    SimOptions o;
    o.dt_ms = s.dt_ms;
    o.tstop_ms = f.tstop_ms;
    const std::size_t last = axon.nodes.size() - 1;
    o.detect =
        vertical ? std::vector<std::size_t>{last - 5} : std::vector<std::size_t>{5, last - 5};
    return o;
  };
  for (std::size_t fi = 0; fi < f.axons.size(); ++fi) {
    const Axon& axon = f.axons[fi];
    const SimOptions o = options(axon);

    Search search(model, axon, waveform, o, s);
    jmin = search.jmin();
    Best best;
    std::vector<Placement> all;
    // Where to start: the best so far (another direction's), else the caller's guess, else
    // the passive estimate (Search::estimate; 1 mA without one).
    const std::optional<double> start = caller_start(s);
    const long guess = winner.found ? winner.j : search.lattice().at_or_above(start.value_or(1.0));
    const bool near_start = winner.found || start.has_value();
    auto evaluate = [&](std::vector<Placement> ps, long from) {
      const bool close = best.found || near_start;
      // A round of placements, indexed after all earlier ones (which win ties).
      const std::size_t base = all.size();
      for (auto& p : ps) all.push_back(std::move(p));
      best = search.minimum(all, base, best, from, close);
    };
    auto vertical_placement = [&](double x, double z) {
      Placement p;
      p.vertical = true;
      p.x0_mm = x;
      p.z0_mm = z;
      p.y0_mm = r.depth_min_mm;
      p.ve_mV = potentials_mV(conductor, weights, axon, x, p.y0_mm, true, z, two_d, cache);
      return p;
    };

    if (!vertical && s.fixed_offset_mm) {
      Placement p;
      p.offset_mm = *s.fixed_offset_mm;
      const double left = reg.x0_mm - 5.0 * L_mm;
      p.x0_mm = p.offset_mm + L_mm * std::floor((left - p.offset_mm) / L_mm);
      p.y0_mm = r.depth_min_mm;
      p.z0_mm = z_fibre;
      p.ve_mV =
          potentials_mV(conductor, weights, axon, p.x0_mm, p.y0_mm, false, z_fibre, two_d, cache);
      evaluate({std::move(p)}, guess);
    } else if (vertical && s.fixed_x_mm) {
      std::vector<Placement> ps;
      ps.push_back(vertical_placement(*s.fixed_x_mm, z_fibre));
      evaluate(std::move(ps), guess);
    } else if (!vertical) {
      const std::size_t depths = r.depth_max_mm > r.depth_min_mm ? 5 : 1;
      std::vector<Placement> ps;
      for (std::size_t k = 0; k < depths; ++k) {
        const double y = depths == 1 ? r.depth_min_mm
                                     : r.depth_min_mm + (r.depth_max_mm - r.depth_min_mm) *
                                                            static_cast<double>(k) /
                                                            static_cast<double>(depths - 1);
        for (std::size_t q = 0; q < s.offsets; ++q) {
          Placement p;
          p.offset_mm = L_mm * static_cast<double>(q) / static_cast<double>(s.offsets);
          // A node at offset + m L; the first at or before x0 - 5 internodes.
          const double left = reg.x0_mm - 5.0 * L_mm;
          p.x0_mm = p.offset_mm + L_mm * std::floor((left - p.offset_mm) / L_mm);
          p.y0_mm = y;
          p.z0_mm = z_fibre;
          p.ve_mV =
              potentials_mV(conductor, weights, axon, p.x0_mm, y, false, z_fibre, two_d, cache);
          ps.push_back(std::move(p));
        }
      }
      evaluate(std::move(ps), guess);
    } else if (two_d) {
      // Every quarter pitch within half a pitch of the point in x and z, then twice 5 x 5
      // around the best at half the step (to a sixteenth of a pitch).
      auto round = [&](double cx, double cz, double step, int half) {
        std::vector<Placement> ps;
        for (int jz = -half; jz <= half; ++jz)
          for (int ix = -half; ix <= half; ++ix)
            ps.push_back(vertical_placement(cx + step * ix, cz + step * jz));
        evaluate(std::move(ps), best.found ? best.j : guess);
      };
      double step = sampling_pitch_mm(setup.array) / 4;
      round((*s.through_mm)[0], (*s.through_mm)[1], step, 2);
      for (int refine = 0; refine < 2 && best.found; ++refine) {
        const Placement c = all[best.index];
        step /= 2;
        round(c.x0_mm, c.z0_mm, step, 2);
      }
    } else {
      const double pitch = sampling_pitch_mm(setup.array);
      auto round = [&](double from, double to, double step) {
        std::vector<Placement> ps;
        const auto count = static_cast<std::size_t>(std::llround((to - from) / step));
        for (std::size_t k = 0; k <= count; ++k)
          ps.push_back(vertical_placement(from + step * static_cast<double>(k), 0.0));
        evaluate(std::move(ps), best.found ? best.j : guess);
      };
      double step = pitch / 4;
      round(setup.array.x_min_mm() - pitch, setup.array.x_max_mm() + pitch, step);
      for (int refine = 0; refine < 2 && best.found; ++refine) {
        const double c = all[best.index].x0_mm;
        round(c - step, c + step, step / 4);
        step /= 4;
      }
    }
    out.placements += all.size();
    for (const Placement& q : all)
      out.tried.push_back({f.directions[fi], q.x0_mm, q.y0_mm, q.z0_mm, q.offset_mm});
    simulations += search.simulations();
    if (best.found && (!winner.found || best.j < winner.j)) {
      winner.found = true;
      winner.fibre = fi;
      winner.j = best.j;
      winner.placement = all[best.index];
    }
  }
  out.simulations = simulations;
  const Lattice lattice(s.tolerance);
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
  const Placement& p = winner.placement;
  CableSimulator sim(model, axon);
  const SimResult res =
      sim.run(p.ve_mV.data(), lattice.amplitude(winner.j), waveform, options(axon));
  ++out.simulations;
  out.threshold_mA = lattice.amplitude(winner.j);
  out.offset_mm = p.offset_mm;
  out.direction = f.directions[winner.fibre];
  out.spot = {out.direction, p.x0_mm, p.y0_mm, p.z0_mm, p.offset_mm};
  out.node = res.first_node;
  {
    const std::size_t last = axon.nodes.size() - 1;
    out.at_cut_end = res.first_node + 5 > last || (!vertical && res.first_node < 5);
  }
  const std::size_t k = axon.nodes[res.first_node];
  const double s_mm = axon.centre_um[k] * 1e-3;
  if (!axon.path.empty()) {
    out.x_mm = p.x0_mm + axon.path_x_mm[k];
    out.depth_mm = p.y0_mm + axon.path_y_mm[k];
  } else {
    out.x_mm = vertical ? p.x0_mm : p.x0_mm + s_mm;
    out.depth_mm = vertical ? p.y0_mm + s_mm : p.y0_mm;
  }
  out.z_mm = p.z0_mm;
  return out;
}

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
  SimOptions o;
  o.dt_ms = settings_.dt_ms;
  o.tstop_ms = std::min(f.tstop_ms, waveform_.end_ms() + kPassiveAfter_ms);
  // The steps of a run, at most: dt's, and each short phase's window at its finer step
  // (CableSimulator::run's schedule).
  double steps = std::ceil(o.tstop_ms / o.dt_ms) + 2.0;
  for (const Waveform::Phase& ph : waveform_.phases)
    if (ph.duration_ms < o.short_phase_ms && ph.level != 0.0 && ph.duration_ms > 0.0)
      steps += std::ceil((ph.duration_ms + 0.1) /
                         std::max(o.min_dt_ms, std::min(o.dt_ms, ph.duration_ms / 10.0))) +
               1.0;
  std::vector<double> unit(n, 0.0);
  // A run at zero amplitude: where the nodes drift without a field (the resting state is
  // not exactly steady), taken off every response before it is scaled.
  std::vector<std::vector<double>> rest(f.axons.size());
  auto record = [&](CableSimulator& sim, const double* ve, double amplitude) {
    const std::size_t nodes = sim.axon().nodes.size();
    std::vector<double> trace;
    trace.reserve(static_cast<std::size_t>(steps / 2.0 + 2.0) * (nodes + 1));
    sim.record(&trace, 2);  // every other step: the peak moves little between them
    sim.run(ve, amplitude, waveform_, o);
    sim.record(nullptr, 2);
    std::vector<double> v;  // (time, node), without the times
    for (std::size_t t = 0; t + nodes + 1 <= trace.size(); t += nodes + 1)
      v.insert(v.end(), trace.begin() + static_cast<long>(t + 1),
               trace.begin() + static_cast<long>(t + 1 + nodes));
    return v;
  };
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
      rest[fi] = record(sim, zero.data(), 0.0);
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
      std::vector<double> r = record(sim, ve.data(), a0);
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
