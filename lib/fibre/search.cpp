// The threshold search over any potential, on a fixed amplitude lattice (search.hpp).

#include "fibre/search.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>

#include "core/error.hpp"

namespace tp::fibre {

AmplitudeLattice::AmplitudeLattice(double tolerance)
    : per_octave(static_cast<long>(std::ceil(std::log(2.0) / std::log1p(tolerance)))) {}

double AmplitudeLattice::amplitude(long j) const {
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

long AmplitudeLattice::at_or_above(double a) const {
  long j = static_cast<long>(std::ceil(std::log2(a) * static_cast<double>(per_octave)));
  while (amplitude(j - 1) >= a) --j;
  while (amplitude(j) < a) ++j;
  return j;
}

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

double passive_k_mV(const Waveform& w) {
  double longest = 0.0;
  for (const Waveform::Phase& ph : w.phases)
    if (ph.level != 0.0) longest = std::max(longest, ph.duration_ms);
  return longest > 0.0 ? 4.3 + 5.3 / std::sqrt(longest) : 0.0;
}

std::optional<double> caller_start(const ThresholdSettings& s) {
  if (s.start_mA.empty() || !(s.start_mA.front() > 0.0) || !std::isfinite(s.start_mA.front()))
    return std::nullopt;
  return std::min(s.start_mA.front(), s.max_mA);
}

namespace {

// The indices base.. of ve in the order of their drive, the strongest first (ties: the
// lower index first).
std::vector<std::size_t> strongest_first(const AmplitudeSearch& search,
                                         const std::vector<std::vector<double>>& ve,
                                         std::size_t base) {
  std::vector<std::size_t> order(ve.size() - base);
  std::vector<double> key(ve.size() - base);
  for (std::size_t i = base; i < ve.size(); ++i) {
    order[i - base] = i;
    key[i - base] = search.drive(ve[i]);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key[a - base] > key[b - base]; });
  return order;
}

// work() on n threads (on this one when n <= 1), joined before the return.  When a thread
// cannot be had, stop() ends the work of those started, they are joined, and the failure is
// rethrown.
template <class Work, class Stop>
void on_threads(unsigned n, Work& work, Stop stop) {
  if (n <= 1) {
    work();
    return;
  }
  std::vector<std::thread> pool;
  try {
    for (unsigned t = 0; t < n; ++t) pool.emplace_back(work);
  } catch (...) {  // no thread to be had: join those started, then report
    stop();
    for (auto& t : pool) t.join();
    throw;
  }
  for (auto& t : pool) t.join();
}

}  // namespace

AmplitudeSearch::AmplitudeSearch(const FibreModel& model, const Axon& axon, const Waveform& w,
                             const SimOptions& o, const ThresholdSettings& s)
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

Best AmplitudeSearch::minimum(const std::vector<std::vector<double>>& ve, std::size_t base, Best best,
                            long guess, bool close) {
  const std::vector<std::size_t> order = strongest_first(*this, ve, base);
  std::atomic<std::size_t> next{0};
  std::mutex m;
  std::exception_ptr error;
  std::size_t error_index = ve.size();
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
        std::size_t node = 0;
        bool found;
        try {
          found = search_one(sim, ve[i], i, snap, g, near, j, node);
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
        if (best.beats(j, i)) best = {true, j, i, node};
      }
    } catch (...) {  // the simulator's construction: before any potential
      std::lock_guard<std::mutex> lock(m);
      if (!error) error = std::current_exception();
    }
  };
  const unsigned n = static_cast<unsigned>(std::min<std::size_t>(threads_, ve.size() - base));
  on_threads(n, work, [&] { next = order.size(); });
  if (error) std::rethrow_exception(error);
  return best;
}

// The probes of the search for excitation.  A run that excites no node may pause once it
// has settled (SimOptions::stop_when_settled): the search goes on as if it had not excited
// the fibre, and before any decision rests on that, confirm() runs the last such run to its
// end.  Excitation grows with the amplitude, so if the highest point taken as not exciting
// does not excite at the end of its run, neither do those below it, and the answer is that
// of runs to their ends.  If it does, the search is repeated with every run to its end
// (search_one).
namespace {
constexpr long kNone = std::numeric_limits<long>::min();
}  // namespace

struct AmplitudeSearch::Excitation {
  CableSimulator& sim;
  const std::vector<double>& ve;
  bool settle;
  long paused = kNone;  // the point whose run paused, if it is the last that did not excite
};

AmplitudeSearch::Probe AmplitudeSearch::probe(Excitation& e, long j) {
  ++simulations_;
  const SimResult r = e.sim.run(e.ve.data(), lat_.amplitude(j), w_, e.settle ? settling_ : o_);
  const bool excited = r.first_time_ms >= 0.0;
  if (!excited) e.paused = r.settled ? j : kNone;
  return {r.fired, excited, r.first_node};
}

// Whether the runs taken as not exciting at j and below are so to their ends.
bool AmplitudeSearch::confirm(Excitation& e, long j) {
  if (e.paused != j) return true;  // j's run went to its end
  if (e.sim.paused_amplitude() != lat_.amplitude(j))
    failure("fibre: the paused run is not the one to confirm");
  e.paused = kNone;
  return e.sim.resume(e.ve.data(), lat_.amplitude(j), w_, o_).first_time_ms < 0.0;
}

// Where a search without a guess starts: the passive estimate.  Below threshold the
// membrane responds nearly in proportion to the amplitude; a node fires when it is
// depolarised by about K mV at the end of the pulse, K falling with the pulse's length
// (MRG, 4 to 16 um, 0.05 to 1 ms, either polarity, mono- or biphasic: K = 4.3 +
// 5.3 / sqrt(longest phase in ms) mV within about 25 %).  One short run at an amplitude
// that drives the nodes by 1 mV of activating function, to 0.05 ms after the waveform,
// gives the peak depolarisation dv; the estimate is that amplitude times K / dv.  Only
// the work depends on it, not the answer.  None when the field does not depolarise.
std::optional<long> AmplitudeSearch::estimate(CableSimulator& sim, const std::vector<double>& ve) {
  const double a0 = 1.0 / drive(ve);
  if (!std::isfinite(a0) || !(a0 > 0.0)) return std::nullopt;
  const double k_mV = passive_k_mV(w_);
  if (!(k_mV > 0.0)) return std::nullopt;
  SimOptions o = o_;
  o.tstop_ms = std::min(o_.tstop_ms, w_.end_ms() + kPassiveAfter_ms);
  o.detect.clear();
  ++simulations_;
  sim.run(ve.data(), a0, w_, o);
  double dv = 0.0;
  for (double v : sim.peak_node_mV()) dv = std::max(dv, v - model_.initial_mV());
  if (!(dv > 1e-9)) return std::nullopt;
  const double a = a0 * k_mV / dv;
  if (!std::isfinite(a) || a > lat_.amplitude(jmax_)) return jmax_;
  if (a < lat_.amplitude(jmin_)) return jmin_;
  return lat_.at_or_above(a);
}

// This potential's threshold j, if it can beat `best`; false when it cannot.
//
// Firing is not monotone in the amplitude: far above threshold the hyperpolarised
// neighbours of an excited node block the action potential.  Excitation (some node above
// detect_mV) is: it only grows with the amplitude.  So the search first finds e, the lowest
// lattice point that excites the fibre anywhere, by bracketing and bisection on excitation;
// the threshold is the first point from e up that fires (nearly always e itself).  Both
// depend on this potential alone, not on the bracket the search started from: the answer is
// the same whichever thread searched it, and in whatever order.
bool AmplitudeSearch::search_one(CableSimulator& sim, const std::vector<double>& ve, std::size_t i,
                               const Best& best, long guess, bool near, long& out,
                               std::size_t& node) {
  Excitation settling{sim, ve, settling_.stop_when_settled};
  if (const std::optional<bool> r = search_from(settling, i, best, guess, near, out, node))
    return *r;
  Excitation to_end{sim, ve, false};  // a paused run excited after all (rare)
  return *search_from(to_end, i, best, guess, near, out, node);
}

// The gallop's first step, by steps that double: from 1/32 octave (2.2 %) when the guess is
// near (a threshold: the best so far, another fibre's, nearby weights'), so that a close
// guess costs a few probes; from 1/8 octave from the passive estimate (within about 1/3
// octave), which then becomes the guess; else from an octave.
long AmplitudeSearch::first_step(CableSimulator& sim, const std::vector<double>& ve, const Best& best,
                               bool near, long& guess) {
  if (near || best.found) return std::max(1L, lat_.per_octave / 32);
  if (const std::optional<long> est = estimate(sim, ve)) {
    guess = *est;
    return std::max(1L, lat_.per_octave / 8);
  }
  return lat_.per_octave;
}

// search_one with the probes of e; none when a run taken as not exciting excited the fibre
// after all.
std::optional<bool> AmplitudeSearch::search_from(Excitation& e, std::size_t i, const Best& best,
                                               long guess, bool near, long& out,
                                               std::size_t& node) {
  // The largest lattice point at which firing would still beat the best.
  const long limit = !best.found ? jmax_ : (i < best.index ? best.j : best.j - 1);
  if (limit < jmin_) return false;
  long lo, hi;  // lo does not excite, hi excites
  bool hi_fired;
  std::size_t hi_node = 0;
  const long step0 = first_step(e.sim, e.ve, best, near, guess);
  const long g = best.found ? limit : std::min(std::max(guess, jmin_), limit);
  Probe pg = probe(e, g);
  if (pg.excited) {
    hi = g;
    hi_fired = pg.fired;
    hi_node = pg.node;
    for (long step = step0;; step *= 2) {
      lo = std::max(hi - step, jmin_);
      const Probe q = probe(e, lo);
      if (!q.excited) break;
      hi = lo;
      hi_fired = q.fired;
      hi_node = q.node;
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
    for (long step = step0;; step *= 2) {
      hi = std::min(lo + step, limit);
      const Probe q = probe(e, hi);
      if (q.excited) {
        hi_fired = q.fired;
        hi_node = q.node;
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
      hi_node = q.node;
    } else {
      lo = mid;
    }
  }
  if (!confirm(e, lo)) return std::nullopt;
  if (hi_fired) {
    out = hi;
    node = hi_node;
    return true;
  }
  Excitation to_end{e.sim, e.ve, false};
  return first_firing(to_end, hi, limit, out, node);
}

// Excited at e = hi without an action potential reaching the detection nodes: gallop up to
// a point that fires, then bisect back.  Firing need not be monotone above e, so the gallop
// runs to the top of the search range whatever `limit` is, and the point it finds depends
// on e alone (not on the best so far, nor on the order of the potentials); it counts only
// if it is at most `limit`.  Its probes (`whole`) run to their ends.
bool AmplitudeSearch::first_firing(Excitation& whole, long hi, long limit, long& out,
                                   std::size_t& node) {
  long f_lo = hi, f_hi = hi;
  std::size_t f_node = 0;
  for (long step = 1;; step *= 2) {
    f_hi = hi + step;
    if (f_hi > jmax_) {
      if (f_lo == jmax_) return false;
      f_hi = jmax_;
    }
    const Probe q = probe(whole, f_hi);
    if (q.fired) {
      f_node = q.node;
      break;
    }
    if (f_hi == jmax_) return false;
    f_lo = f_hi;
  }
  while (f_hi - f_lo > 1) {
    const long mid = f_lo + (f_hi - f_lo) / 2;
    const Probe q = probe(whole, mid);
    if (q.fired) {
      f_hi = mid;
      f_node = q.node;
    } else {
      f_lo = mid;
    }
  }
  if (f_hi > limit) return false;
  out = f_hi;
  node = f_node;
  return true;
}

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
  AmplitudeSearch search(model, axon, waveform, options, settings);
  const std::optional<double> start = caller_start(settings);
  const long guess = search.lattice().at_or_above(start.value_or(1.0));
  const bool near = start.has_value();
  const Best best = search.minimum({ve_unit_mV}, 0, Best{}, guess, near);
  if (!best.found || best.j < search.jmin()) return std::nullopt;
  return search.lattice().amplitude(best.j);
}

}  // namespace tp::fibre
