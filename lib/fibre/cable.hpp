#pragma once
// Integration of an axon in an extracellular potential: backward Euler on the cable's linear
// network with the ionic conductances taken from the previous step, then the gates advanced
// by exponential Euler at the new potential (NEURON's fixed-step scheme, secondorder = 0).
// Each step is one block-tridiagonal solve (2x2 blocks in a double cable, scalars in a
// single one).  In a double cable the passive compartments between two nodes are
// eliminated first, with factors that depend on the step length alone (kept for the three
// lengths used last); what remains is a system over the nodes (docs/fibres.md,
// "Numerics").  All storage is allocated when the simulator is built; run() allocates
// nothing.
// docs/fibres.md ("Numerics") says why this scheme.

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "fibre/axon.hpp"
#include "fibre/models.hpp"

namespace tp::fibre {

// The stimulus in time: after delay_ms at zero, phases of constant level (a multiple of the
// amplitude: 1 for the main phase of a positive weight), then zero.
struct Waveform {
  struct Phase {
    double duration_ms = 0.0;
    double level = 0.0;
  };
  double delay_ms = 0.1;
  std::vector<Phase> phases;
  double end_ms() const;
  // The mean level over [t0, t1): a step that straddles an edge gets the charge it covers.
  double mean_level(double t0_ms, double t1_ms) const;
};

struct SimOptions {
  double dt_ms = 0.005;
  // A phase shorter than short_phase_ms (and not a gap at zero) gets steps of a tenth of its
  // length, at least min_dt_ms, from its start to 0.1 ms after its end.
  double short_phase_ms = 0.05;
  double min_dt_ms = 1e-4;
  double tstop_ms = 3.0;
  double detect_mV = -20.0;         // an action potential: v above this
  std::vector<std::size_t> detect;  // node numbers (into Axon::nodes) that must all see one
  bool stop_when_detected = true;   // end the run once every detect node has fired
  // Pause a run that has not excited any node (none above detect_mV) once it has settled:
  // from settle_after_ms after the waveform on, the nodes' largest distance from rest and
  // their largest rise above it both shrinking, and at most settle_fraction of the most
  // they have been since then.  Such a run nearly always stays below threshold, but not
  // provably so: it is paused (SimResult::settled), and resume() finishes it.  The wait
  // lets the fast relaxation just after a short pulse pass.
  bool stop_when_settled = false;
  double settle_after_ms = 0.1;
  double settle_fraction = 0.5;
};

struct SimResult {
  bool fired = false;           // every detect node saw an action potential
  std::size_t first_node = 0;   // the node that crossed detect_mV first (if any did)
  double first_time_ms = -1.0;  // when (-1: no node crossed)
  std::size_t steps = 0;
  bool settled = false;  // paused by stop_when_settled: resume() finishes the run
};

class CableSimulator {
 public:
  CableSimulator(const FibreModel& model, Axon axon);
  const Axon& axon() const { return axon_; }

  // ve_unit_mV: the extracellular potential at each compartment's centre for amplitude 1.
  // The potential applied is amplitude * level(t) * ve_unit.
  SimResult run(const double* ve_unit_mV, double amplitude, const Waveform& waveform,
                const SimOptions& options);
  // The last run that settled (SimResult::settled), continued from where it paused to its
  // end, with the same arguments it was run with (amplitude must be the same; options'
  // stop_when_settled is ignored; only the amplitude is checked): the same numbers as a run
  // that never paused (a trace being recorded is not: it goes on from wherever it is).  Runs
  // since then do not disturb it, until another one settles.
  SimResult resume(const double* ve_unit_mV, double amplitude, const Waveform& waveform,
                   const SimOptions& options);
  // The amplitude of the paused run, if there is one.
  std::optional<double> paused_amplitude() const;

  // Double cables: eliminate the passive compartments first (the default), or solve the
  // whole network directly each step (the same numbers to rounding; for tests).
  void condense(bool on) { condense_ = on; }

  // After run(): each node's membrane potential at the end, and its largest value.
  const std::vector<double>& final_node_mV() const { return final_node_mV_; }
  const std::vector<double>& peak_node_mV() const { return peak_node_mV_; }
  // Optional: every `every` steps, append (t, node potentials...) to trace (reserved by
  // the caller for the whole run, so that run() still allocates nothing).
  void record(std::vector<double>* trace, std::size_t every) {
    trace_ = trace;
    trace_every_ = every;
  }

 private:
  void reset();
  void schedule(const Waveform& w, const SimOptions& o);
  void keep_state();
  // The time steps from step n on (t1: the end of step n - 1; s_old: its potential's scale),
  // pausing once settled if `settle`.
  // keep_rest: keep the state before the first step with a nonzero level (rest_), for a
  // run from rest.
  SimResult integrate(const double* ve, double amplitude, const Waveform& w, const SimOptions& o,
                      bool settle, std::size_t n, double t1, double s_old, bool keep_rest = false);
  double membrane(std::size_t k, double vm_mV, double& g_mS) const;
  void step(double dt, double ve_old_scale, double ve_new_scale, const double* ve_unit);
  // Double cable, condensed: the factors of one step length (a slot), and the step with them.
  struct Condensed {
    double dt = -1.0;  // -1: empty
    unsigned long used = 0;
    // Per passive compartment k, of its run's own tridiagonal system T (T y = r): the
    // inverse of the eliminated diagonal block (symmetric: 11, 12, 22), the forward factor
    // M = G(k-1) Dinv(k-1) and the backward factor P = Dinv(k) G(k) (row-major), and the
    // responses U, W to the left and right nodes' potentials (x = y + U x_left + W x_right).
    // Also, for every compartment, its capacitances over dt (membrane, sheath).
    struct Factors {
      double dinv[3], m[4], p[4], u[4], w[4];
      double c_dt, cs_dt;
    };
    std::vector<Factors> f;  // per compartment (nodes' entries: c_dt and cs_dt alone)
    // Per node j: what its runs take from its diagonal block (symmetric), and its coupling
    // to node j+1 (row-major, the row of j): the runs' Schur complements.
    std::vector<double> s11, s12, s22, c11, c12, c21, c22;
  };
  const Condensed* condensed_for(double dt);
  void fill(Condensed& c, double dt);
  void step_condensed(const Condensed& c, double s_old, double s_new, const double* ve);
  void solve_runs(const Condensed& c, double s_old, double s_new, const double* ve);

  const NodeKinetics& kin_;
  Axon axon_;
  double v_init_;
  std::size_t n_, gates_;
  std::vector<char> is_node_;
  std::vector<double> gi_link_, gp_link_;                // conductance between k and k+1
  std::vector<double> vi_, vp_, gate_;                   // state
  std::vector<double> inv11_, inv12_, inv22_, y1_, y2_;  // solver workspace
  // Condensation (double cable): maximal runs of passive compartments, each between two
  // nodes or between a node and an end of the fibre.
  struct Run {
    std::size_t p, q;  // first and last compartment
    long left, right;  // the node (index into Axon::nodes) before p and after q, or -1
  };
  std::vector<Run> runs_;
  std::vector<long> run_after_node_, run_before_node_;  // the run right of / left of node j
  std::vector<Condensed> slots_;                        // factors of up to three step lengths
  bool condense_ = true;
  unsigned long clock_ = 0;                             // slots' last use
  std::vector<double> nd11_, nd12_, nd22_, nr1_, nr2_;  // the node system, per node
  std::vector<double> final_node_mV_, peak_node_mV_, cross_ms_;
  struct Window {
    double from_ms, until_ms, dt_ms;
  };
  std::vector<Window> windows_;  // reused: no allocation once its capacity is reached
  // A run paused by stop_when_settled: its state and where it stopped.
  struct Paused {
    std::vector<double> vi, vp, gate, peak, cross;
    double amplitude = 0.0, t1 = 0.0, s_old = 0.0;
    std::size_t n = 0;
    bool valid = false;
  } paused_;
  // The state before the waveform's first step with a nonzero level: every run of this
  // simulator from rest with the same schedule up to there (step, stop time, windows,
  // detection level, condensation, onset) takes the same steps there whatever its amplitude
  // and potential (both enter scaled by a level of 0), so a later run starts from it.
  struct Rest {
    std::vector<double> vi, vp, gate, peak, cross;
    std::vector<Window> windows;
    double dt_ms = 0.0, tstop_ms = 0.0, detect_mV = 0.0, onset_ms = 0.0, t1 = 0.0;
    std::size_t n = 0;
    bool condense = true;
    bool valid = false;
  } rest_;
  bool rest_matches(const SimOptions& o, double onset_ms) const;
  std::vector<double>* trace_ = nullptr;
  std::size_t trace_every_ = 1;
};

}  // namespace tp::fibre
