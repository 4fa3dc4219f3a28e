// The fibre models against published benchmarks and physics: Reilly 2016's NEURON
// benchmark suite (ModelDB 239006) for SENN, Reilly 1985's SENN threshold, the MRG peer's
// published example, exact amplitude scaling, strength-duration, biphasic against
// monophasic, rest after a sub-threshold pulse, and determinism across threads.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fibre/cable.hpp"
#include "fibre/geometry.hpp"
#include "fibre/report.hpp"
#include "fibre/threshold.hpp"
#include "model/field.hpp"
#include "fibre_support.hpp"
#include "opt/threshold_objective.hpp"

using namespace tp;
using namespace tp::fibre;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A point cathode of 1 mA, 1 mm from node `node` in a medium of 300 ohm cm: the potential
// (mV) at each compartment.
std::vector<double> point_cathode_mV(const Axon& a, std::size_t node) {
  std::vector<double> ve(a.compartments.size());
  const double mid = a.centre_um[a.nodes[node]];
  for (std::size_t k = 0; k < ve.size(); ++k)
    ve[k] = -300.0 / (4 * kPi * std::hypot((a.centre_um[k] - mid) * 1e-4, 0.1));
  return ve;
}

// Bisection to a relative 1e-4 (thresh4.hoc's), from 1 mA by doubling or halving.
double bisect(CableSimulator& sim, const std::vector<double>& ve, const Waveform& w,
              const SimOptions& o) {
  double lo = 0.0, hi = 1.0;
  if (sim.run(ve.data(), hi, w, o).fired) {
    lo = 0.5;
    while (sim.run(ve.data(), lo, w, o).fired) {
      hi = lo;
      lo /= 2;
    }
  } else {
    while (!sim.run(ve.data(), hi, w, o).fired) {
      lo = hi;
      hi *= 2;
      REQUIRE(hi < 1e4);
    }
  }
  while (hi - lo > 1e-4 * hi) {
    const double mid = 0.5 * (lo + hi);
    (sim.run(ve.data(), mid, w, o).fired ? hi : lo) = mid;
  }
  return hi;
}

// Reilly 2016 case A: a 101-node 10 um SENN fibre (the benchmark's constants), point
// electrodes on the surface of a 300 ohm cm half-space at (x, y) cm from the central node;
// currents +1 (cathode, the first) and -1 (anode).  Waveform: `phases` after 1 ms.
double reilly_case_a(double tp_ms, bool biphasic, double xc_cm, double yc_cm, double xa_cm,
                     double ya_cm) {
  auto model = make_senn(SennParams::reilly2016());
  CableSimulator sim(*model, model->axon(10.0, 101));
  const Axon& a = sim.axon();
  std::vector<double> ve(a.compartments.size());
  for (std::size_t k = 0; k < ve.size(); ++k) {
    const double x = (a.centre_um[k] - a.centre_um[50]) * 1e-4;
    // rho / (2 pi r) ohm per mA = mV; cathodic current: negative potential.
    ve[k] = -300.0 / (2 * kPi * std::hypot(x - xc_cm, yc_cm)) +
            300.0 / (2 * kPi * std::hypot(x - xa_cm, ya_cm));
  }
  Waveform w;
  w.delay_ms = 1.0;
  w.phases = {{tp_ms, 1.0}};
  if (biphasic) w.phases.push_back({tp_ms, -1.0});
  SimOptions o;
  o.detect = {0};  // APCount at node[0]
  o.tstop_ms = 8.0;
  return bisect(sim, ve, w, o);
}

// Reilly 2016 case B: a uniform field along the fibre (V/m), spike counted at node[50].
double reilly_case_b(double tp_ms, bool biphasic, double d_um) {
  auto model = make_senn(SennParams::reilly2016());
  CableSimulator sim(*model, model->axon(d_um, 101));
  const Axon& a = sim.axon();
  std::vector<double> ve(a.compartments.size());
  for (std::size_t k = 0; k < ve.size(); ++k) ve[k] = a.centre_um[k] * 1e-3;  // 1 V/m, mV
  Waveform w;
  w.delay_ms = 1.0;
  w.phases = {{tp_ms, 1.0}};
  if (biphasic) w.phases.push_back({tp_ms, -1.0});
  SimOptions o;
  o.detect = {50};
  o.tstop_ms = 12.0;
  return bisect(sim, ve, w, o);
}

}  // namespace

// Values: ModelDB 239006 readme.html and initA.hoc/initB10.hoc/initB5.hoc (Reilly 2016,
// "NTC-NEUR"); table in docs/fibres.md.  Tolerance 5 % (the issue's); we are within 1 %.
TEST_CASE("SENN matches Reilly 2016's point-electrode benchmarks", "[fibre][reilly][numerics]") {
  struct Case {
    int id;
    double tp_ms;
    bool biphasic;
    double xc, yc, xa, ya, expected_mA;
  } cases[] = {
      {1, 0.005, false, 0, 0.25, 50, 0.25, 11.08643}, {2, 2.0, false, 0, 0.25, 50, 0.25, 0.47032},
      {3, 0.005, false, 0, 1.0, 50, 0.25, 409.95312}, {4, 2.0, false, 0, 1.0, 50, 0.25, 12.83545},
      {5, 2.0, false, 50, 0.25, 0, 0.25, 2.10657},    {6, 2.0, false, 1, 1, 0, 1, 11.00342},
      {7, 0.005, true, 0, 0.25, 50, 0.25, 32.57227},  {8, 2.0, true, 0, 0.25, 50, 0.25, 0.47038},
  };
  for (const Case& c : cases) {
    CAPTURE(c.id);
    const double th = reilly_case_a(c.tp_ms, c.biphasic, c.xc, c.yc, c.xa, c.ya);
    CHECK(th == Approx(c.expected_mA).epsilon(0.05));
  }
}

TEST_CASE("SENN matches Reilly 2016's uniform-field benchmarks", "[fibre][reilly][numerics]") {
  struct Case {
    int id;
    double tp_ms;
    bool biphasic;
    double d_um, expected_V_per_m;
  } cases[] = {
      {13, 0.005, false, 10, 281.54688}, {14, 2.0, false, 10, 11.36865},
      {15, 2.0, false, 5, 22.71191},     {16, 0.005, true, 10, 802.59375},
      {17, 2.0, true, 10, 11.05225},     {18, 2.0, true, 5, 22.08301},
  };
  for (const Case& c : cases) {
    CAPTURE(c.id);
    CHECK(reilly_case_b(c.tp_ms, c.biphasic, c.d_um) == Approx(c.expected_V_per_m).epsilon(0.05));
  }
}

// Reilly, Freeman & Larkin 1985: a 20 um SENN fibre, a point electrode 2 mm from a node in
// an infinite 300 ohm cm medium, a 100 us cathodic pulse: 0.68 mA.
TEST_CASE("SENN reproduces Reilly 1985's 0.68 mA", "[fibre][reilly]") {
  auto model = make_fibre_model("senn");
  CableSimulator sim(*model, model->axon(20.0, 51));
  const Axon& a = sim.axon();
  std::vector<double> ve(a.compartments.size());
  for (std::size_t k = 0; k < ve.size(); ++k) {
    const double x_cm = (a.centre_um[k] - a.centre_um[25]) * 1e-4;
    ve[k] = -300.0 / (4 * kPi * std::hypot(x_cm, 0.2));
  }
  Waveform w;
  w.phases = {{0.1, 1.0}};
  SimOptions o;
  o.detect = {5, 45};
  o.tstop_ms = 3.0;
  o.dt_ms = 0.001;
  CHECK(bisect(sim, ve, w, o) == Approx(0.68).epsilon(0.05));
}

// The peer's README example: 10 um MRG, 41 nodes, line2d single cathode, 0.9 mm deep,
// 200 us monophasic: NEURON gives 0.35566 mA.  Same scheme and dt: same bisection result.
TEST_CASE("MRG reproduces the NEURON peer's example", "[fibre][mrg]") {
  auto model = make_fibre_model("mrg");
  CableSimulator sim(*model, model->axon(10.0, 41));
  const Axon& a = sim.axon();
  std::vector<double> ve(a.compartments.size());
  const double mid = a.centre_um[a.nodes[20]];
  for (std::size_t k = 0; k < ve.size(); ++k)
    ve[k] = 1e3 * 3.0 / 10.0 * std::log(std::hypot((a.centre_um[k] - mid) * 1e-3, 0.9)) / (2 * kPi);
  Waveform w;
  w.phases = {{0.2, 1.0}};
  SimOptions o;
  o.detect = {5, 35};
  double lo = 0.0, hi = 0.05;
  while (!sim.run(ve.data(), hi, w, o).fired) {
    lo = hi;
    hi *= 2;
  }
  while (hi - lo > 1e-3 * hi) {
    const double m = 0.5 * (lo + hi);
    (sim.run(ve.data(), m, w, o).fired ? hi : lo) = m;
  }
  CHECK(hi == Approx(0.35566406).epsilon(1e-6));
  // The library's search (lattice, galloping, one core) on the same fibre: a lattice point
  // within the tolerance of the bisection's answer, whatever its start.
  ThresholdSettings s;
  for (double start : {0.0, 0.3, 5.0}) {
    s.start_mA = {start};
    const auto t = fibre_threshold(*model, a, ve, w, o, s);
    REQUIRE(t);
    CHECK(std::fabs(*t / hi - 1) <= 1e-3);
    CHECK(*t == Approx(0.35567847).epsilon(1e-7));
  }
}

// The condensed solve (passive runs eliminated first, factors per step length) against the
// direct block-tridiagonal solve of the whole network: the same potentials to rounding, for
// a straight MRG fibre and an afferent (an ending before the first node), under a pulse
// whose short phases bring steps of other lengths (and steps cut short at their edges).
TEST_CASE("The condensed cable solve equals the direct one", "[fibre][mrg]") {
  auto model = make_fibre_model("mrg");
  for (int fibre = 0; fibre < 2; ++fibre) {
    Axon axon = fibre == 0 ? model->axon(10.0, 21) : afferent_axon(*model, 4.0, 0.5, 1, 2.0);
    std::vector<double> ve(axon.compartments.size());
    for (std::size_t k = 0; k < ve.size(); ++k) {
      const double x_mm = fibre == 0 ? (axon.centre_um[k] - axon.centre_um[axon.nodes[10]]) * 1e-3
                                     : axon.path_x_mm[k],
                   y_mm = fibre == 0 ? 0.5 : axon.path_y_mm[k] + 0.1;
      ve[k] = -300.0 / (4 * kPi * std::hypot(x_mm * 0.1, y_mm * 0.1));
    }
    Waveform w;
    w.phases = {{0.2, 1.0}, {0.013, 0.0}, {0.03, -2.0}};
    SimOptions o;
    o.tstop_ms = 1.5;
    o.stop_when_detected = false;
    CableSimulator direct(*model, axon), condensed(*model, axon);
    direct.condense(false);
    for (double amplitude : {0.05, 2.0}) {  // below and above threshold
      direct.run(ve.data(), amplitude, w, o);
      condensed.run(ve.data(), amplitude, w, o);
      double worst = 0.0, swing = 0.0;
      for (std::size_t j = 0; j < axon.nodes.size(); ++j) {
        worst =
            std::max(worst, std::fabs(direct.final_node_mV()[j] - condensed.final_node_mV()[j]));
        worst = std::max(worst, std::fabs(direct.peak_node_mV()[j] - condensed.peak_node_mV()[j]));
        swing = std::max(swing, direct.peak_node_mV()[j] - model->initial_mV());
      }
      INFO("fibre " << fibre << ", amplitude " << amplitude << ", swing " << swing);
      CHECK(swing > 1.0);   // the field moved the membrane
      CHECK(worst < 1e-6);  // mV; a wrong factor moves them by mV
    }
  }
}

// A run's numbers depend on its inputs alone: on a new simulator and on one that has run
// other pulses (other step lengths) before, the same bits.
TEST_CASE("A run does not depend on what the simulator ran before", "[fibre][mrg]") {
  auto model = make_fibre_model("mrg");
  const Axon axon = model->axon(10.0, 21);
  std::vector<double> ve(axon.compartments.size());
  for (std::size_t k = 0; k < ve.size(); ++k)
    ve[k] =
        -300.0 /
        (4 * kPi * std::hypot((axon.centre_um[k] - axon.centre_um[axon.nodes[10]]) * 1e-4, 0.05));
  const Waveform w = pulse_waveform(200, 0, 200, false);
  Waveform other;
  other.phases = {{0.02, 1.0}, {0.007, 0.0}, {0.03, -1.0}};  // finer steps, cut steps
  SimOptions o;
  o.detect = {5, 15};  // runs that fire stop early, at different steps
  CableSimulator fresh(*model, axon), used(*model, axon);
  for (double a : {3.0, 0.01, 3.0}) used.run(ve.data(), a, w, o);
  for (double a : {0.3, 3.0}) used.run(ve.data(), a, other, o);
  for (double a : {3.0, 0.01, 3.0}) used.run(ve.data(), a, w, o);
  fresh.run(ve.data(), 0.2, w, o);
  used.run(ve.data(), 0.2, w, o);
  CHECK(fresh.final_node_mV() == used.final_node_mV());
  CHECK(fresh.peak_node_mV() == used.peak_node_mV());
}

namespace {
using tp::test::PaperCase;
double sai_threshold(const PaperCase& p, const std::vector<double>& w, const Waveform& wf,
                     unsigned threads = 1, std::size_t offsets = 4) {
  ThresholdSettings s;
  s.threads = threads;
  s.offsets = offsets;
  auto r = receptor_threshold(*p.model, p.setup, *p.conductor, w, p.sai(), wf, s);
  REQUIRE(r.threshold_mA);
  return *r.threshold_mA;
}
}  // namespace

TEST_CASE("Doubling every weight halves the threshold exactly", "[fibre][mrg]") {
  PaperCase p;
  std::vector<double> w2;
  for (double x : p.w) w2.push_back(2 * x);
  const Waveform wf = pulse_waveform(200, 0, 200, false);
  CHECK(sai_threshold(p, w2, wf) == sai_threshold(p, p.w, wf) / 2);
}

TEST_CASE("The threshold does not depend on the number of threads", "[fibre][mrg]") {
  PaperCase p;
  const Waveform wf = pulse_waveform(200, 0, 200, false);
  CHECK(sai_threshold(p, p.w, wf, 1, 8) == sai_threshold(p, p.w, wf, 2, 8));
}

// Where a search starts (the caller's guess, near or far, on either side) changes the work,
// not the answer: the lattice point and the placement are the same bytes.
TEST_CASE("The threshold does not depend on where its search starts", "[fibre][mrg]") {
  PaperCase p;
  const Waveform wf = pulse_waveform(200, 0, 200, false);
  ThresholdSettings s;
  s.threads = 2;
  s.offsets = 4;
  const auto base = receptor_threshold(*p.model, p.setup, *p.conductor, p.w, p.sai(), wf, s);
  REQUIRE(base.threshold_mA);
  for (double start : {1e-3, 0.999 * *base.threshold_mA, *base.threshold_mA, 1.2, 80.0}) {
    s.start_mA = {start};
    const auto r = receptor_threshold(*p.model, p.setup, *p.conductor, p.w, p.sai(), wf, s);
    INFO("start " << start << " mA");
    REQUIRE(r.threshold_mA);
    CHECK(*r.threshold_mA == *base.threshold_mA);
    CHECK(r.offset_mm == base.offset_mm);
    CHECK(r.node == base.node);
  }
}

TEST_CASE("A search without a guess starts near the threshold (the passive estimate)",
          "[fibre][mrg]") {
  // One fibre, thresholds from 0.11 to 28 mA (the weights scaled by powers of 2, the
  // threshold exactly inversely), 50 us to 1 ms, with the run that locates the first node:
  // 11 or 12 simulations from the estimate; 12 to 17 started at 1 mA by octaves (5 of the
  // 9 above 13).
  PaperCase p;
  ThresholdSettings s;
  s.threads = 1;
  s.fixed_offset_mm = 0.0;
  for (double width : {50.0, 200.0, 1000.0}) {
    const Waveform wf = pulse_waveform(width, 0, width, false);
    std::optional<double> reference;
    for (double scale : {1.0 / 8, 1.0, 8.0}) {
      CAPTURE(width, scale);
      std::vector<double> w;
      for (double x : p.w) w.push_back(scale * x);
      const auto r = receptor_threshold(*p.model, p.setup, *p.conductor, w, p.sai(), wf, s);
      REQUIRE(r.threshold_mA);
      if (!reference) reference = *r.threshold_mA * scale;
      CHECK(*r.threshold_mA * scale == *reference);
      CHECK(r.simulations <= 13);
    }
  }
}

TEST_CASE("Strength-duration is monotone and charge-balanced pulses need more", "[fibre][mrg]") {
  PaperCase p;
  double last = 1e9;
  for (double width : {20.0, 50.0, 100.0, 200.0, 500.0, 1000.0}) {
    CAPTURE(width);
    const double mono = sai_threshold(p, p.w, pulse_waveform(width, 0, width, true));
    const double bi = sai_threshold(p, p.w, pulse_waveform(width, 0, width, false));
    CHECK(mono < last);
    CHECK(bi >= mono);
    last = mono;
  }
}

TEST_CASE("A sub-threshold pulse leaves the fibre at rest", "[fibre][mrg]") {
  auto model = make_fibre_model("mrg");
  CableSimulator sim(*model, model->axon(10.0, 21));
  const Axon& a = sim.axon();
  const std::vector<double> ve = point_cathode_mV(a, 10);
  const Waveform w = pulse_waveform(200, 0, 200, false);
  SimOptions o;
  o.detect = {3, 17};
  o.tstop_ms = 6.0;
  o.stop_when_detected = false;
  sim.run(ve.data(), 0.0, w, o);
  const std::vector<double> quiet = sim.final_node_mV();
  const double th = bisect(sim, ve, w, o);
  const SimResult r = sim.run(ve.data(), 0.95 * th, w, o);
  CHECK_FALSE(r.fired);
  for (std::size_t j = 0; j < quiet.size(); ++j) {
    CAPTURE(j);
    CHECK(sim.peak_node_mV()[j] < -20.0);
    CHECK(sim.final_node_mV()[j] == Approx(quiet[j]).margin(0.5));
  }
}

// A run below threshold may pause once it has settled (SimOptions::stop_when_settled);
// resumed, it is the run to its end, to the bit, whatever ran in between: for a double
// cable (MRG) and a single one (SENN), with uniform steps (200 us) and with the finer steps
// of a short phase (20 us).
TEST_CASE("A run paused once settled and resumed is the run to its end", "[fibre][mrg]") {
  for (const char* name : {"mrg", "senn"})
    for (double width : {200.0, 20.0}) {
      CAPTURE(name, width);
      auto model = make_fibre_model(name);
      CableSimulator sim(*model, model->axon(10.0, 21));
      const Axon& a = sim.axon();
      const std::vector<double> ve = point_cathode_mV(a, 10);
      const Waveform w = pulse_waveform(width, 0, width, width < 100.0);
      SimOptions o;
      o.detect = {3, 17};
      const double th = bisect(sim, ve, w, o);
      SimOptions settling = o;
      settling.stop_when_settled = true;
      for (double f : {0.5, 0.95}) {
        CAPTURE(f);
        const SimResult whole = sim.run(ve.data(), f * th, w, o);
        const std::vector<double> final_mV = sim.final_node_mV(), peak_mV = sim.peak_node_mV();
        REQUIRE_FALSE(whole.settled);
        const SimResult paused = sim.run(ve.data(), f * th, w, settling);
        CHECK(paused.settled);
        CHECK_FALSE(paused.fired);
        CHECK(paused.steps < whole.steps / 2);
        REQUIRE(sim.paused_amplitude() == f * th);
        // A run that excites the fibre never settles, and leaves the paused run alone.
        const SimResult above = sim.run(ve.data(), 1.2 * th, w, settling);
        CHECK(above.fired);
        CHECK_FALSE(above.settled);
        CHECK_THROWS(sim.resume(ve.data(), 1.2 * th, w, o));
        const SimResult resumed = sim.resume(ve.data(), f * th, w, o);
        CHECK(resumed.steps == whole.steps);
        CHECK(resumed.fired == whole.fired);
        CHECK(resumed.first_time_ms == whole.first_time_ms);
        CHECK(sim.final_node_mV() == final_mV);
        CHECK(sim.peak_node_mV() == peak_mV);
        CHECK_FALSE(sim.paused_amplitude());
        CHECK_THROWS(sim.resume(ve.data(), f * th, w, o));
      }
    }
}

// The search pauses settled runs below threshold and finishes only the last before a
// decision rests on it; if that one excites after all, it searches again with every run to
// its end.  Either way the threshold is that of runs to their ends.  An eager rule
// (settling at once, at 95 % of the largest distance) pauses runs that go on to excite,
// and so exercises the second search.
TEST_CASE("Pausing settled runs changes the work, not the threshold", "[fibre][mrg]") {
  auto model = make_fibre_model("mrg");
  const Axon axon = model->axon(7.0, 31);
  std::vector<double> ve(axon.compartments.size());
  const double mid = axon.centre_um[axon.nodes[15]] + 300.0;
  for (std::size_t k = 0; k < ve.size(); ++k) {  // two lines 1 mm apart, 1.4 mm deep
    const double x = (axon.centre_um[k] - mid) * 1e-3;
    ve[k] = 1000.0 * 0.3 / (2 * kPi) *
            (std::log(std::hypot(x + 0.5, 1.4)) - 0.6 * std::log(std::hypot(x - 0.5, 1.4)));
  }
  SimOptions o;
  o.detect = {5, 25};
  SimOptions eager = o;
  eager.settle_after_ms = 0.0;
  eager.settle_fraction = 0.95;
  ThresholdSettings to_end, settling;
  to_end.settle = false;
  to_end.threads = settling.threads = 1;
  std::size_t misled = 0;
  CableSimulator sim(*model, axon);
  for (double width : {20.0, 200.0, 1000.0})
    for (bool monophasic : {true, false})
      for (double sign : {1.0, -1.0}) {
        CAPTURE(width, monophasic, sign);
        std::vector<double> field = ve;
        for (double& v : field) v *= sign;
        const Waveform wf = pulse_waveform(width, 0, width, monophasic);
        const auto reference = fibre_threshold(*model, axon, field, wf, o, to_end);
        REQUIRE(reference);
        CHECK(fibre_threshold(*model, axon, field, wf, o, settling) == reference);
        CHECK(fibre_threshold(*model, axon, field, wf, eager, settling) == reference);
        SimOptions eager_run = eager;
        eager_run.stop_when_settled = true;
        if (sim.run(field.data(), *reference, wf, eager_run).settled &&
            sim.resume(field.data(), *reference, wf, o).first_time_ms >= 0.0)
          ++misled;
      }
  CHECK(misled > 0);
}

TEST_CASE("The amplitude lattice", "[fibre]") {
  const AmplitudeLattice l(1e-3);
  CHECK(l.amplitude(l.per_octave) == 2.0);
  CHECK(l.amplitude(1) / l.amplitude(0) <= 1.001);
  for (double a : {1e-4, 0.3, 1.0, 1.7, 99.9, 100.0}) {
    const long j = l.at_or_above(a);
    CHECK(l.amplitude(j) >= a);
    CHECK(l.amplitude(j - 1) < a);
  }
}

namespace {
// Conduction velocity of an MRG fibre (m/s): an action potential started by a point cathode
// 0.5 mm over node 3 at 1.2 times threshold, timed between nodes 12 and 32 (20 internodes) where it
// crosses -20 mV.
double mrg_velocity(double d_um, double dt_ms) {
  auto model = make_fibre_model("mrg");
  CableSimulator sim(*model, model->axon(d_um, 41));
  const Axon& a = sim.axon();
  std::vector<double> ve(a.compartments.size());
  const double x0 = a.centre_um[a.nodes[3]];
  for (std::size_t k = 0; k < ve.size(); ++k)
    ve[k] = -300.0 / (4 * kPi * std::hypot((a.centre_um[k] - x0) * 1e-4, 0.05));
  Waveform w;
  w.phases = {{0.1, 1.0}};
  SimOptions o;
  o.detect = {12, 32};
  o.tstop_ms = 4.0;
  o.dt_ms = dt_ms;
  // From below: a cathode this close blocks conduction at several times threshold.
  double lo = 0.0, th = 0.01;
  while (!sim.run(ve.data(), th, w, o).fired) {
    lo = th;
    th *= 2;
    REQUIRE(th < 100);
  }
  while (th - lo > 1e-3 * th) {
    const double m = 0.5 * (lo + th);
    (sim.run(ve.data(), m, w, o).fired ? th : lo) = m;
  }
  std::vector<double> trace;
  const std::size_t nn = a.nodes.size();
  trace.reserve(static_cast<std::size_t>(o.tstop_ms / dt_ms + 2) * (nn + 1));
  sim.record(&trace, 1);
  o.stop_when_detected = false;
  REQUIRE(sim.run(ve.data(), 1.2 * th, w, o).fired);
  sim.record(nullptr, 1);
  // Crossing times, interpolated linearly within the step.
  auto crossing = [&](std::size_t node) {
    for (std::size_t r = 1; r * (nn + 1) < trace.size(); ++r) {
      const double* prev = &trace[(r - 1) * (nn + 1)];
      const double* cur = &trace[r * (nn + 1)];
      if (prev[1 + node] <= -20.0 && cur[1 + node] > -20.0)
        return prev[0] +
               (cur[0] - prev[0]) * (-20.0 - prev[1 + node]) / (cur[1 + node] - prev[1 + node]);
    }
    return -1.0;
  };
  const double t12 = crossing(12), t32 = crossing(32);
  REQUIRE(t12 > 0);
  REQUIRE(t32 > t12);
  const double dist_mm = (a.centre_um[a.nodes[32]] - a.centre_um[a.nodes[12]]) * 1e-3;
  return dist_mm / (t32 - t12);  // mm/ms = m/s
}
}  // namespace

// Boyd & Kalu 1979 (J Physiol 289:277): conduction velocity over total fibre diameter is
// 5.6 m/s per um for large cutaneous (A-beta) afferents of the cat, 5.7 for group I muscle
// afferents; the relation MRG's model is compared with (docs/fibres.md).  At the fine step
// the velocity is the model's own; the thresholds' 5 us step runs it a few percent slow.
TEST_CASE("MRG conduction velocity follows the large-fibre scaling factor", "[fibre][mrg]") {
  for (double d : {10.0, 12.8, 16.0}) {
    CAPTURE(d);
    const double v = mrg_velocity(d, 0.001);
    CAPTURE(v);
    CHECK(v / d == Approx(5.6).epsilon(0.05));
  }
}

namespace {
// The paper's conductor, but with a non-finite potential everywhere: every simulation
// diverges (a runtime failure thrown inside the search's worker threads).
class NanConductor : public Conductor {
 public:
  explicit NanConductor(const Conductor& c) : c_(c) {}
  const char* name() const override { return "nan"; }
  std::size_t size() const override { return c_.size(); }
  void unit_second_derivatives(double x, double y, double* xx, double* yy) const override {
    c_.unit_second_derivatives(x, y, xx, yy);
  }
  void unit_potentials(double, double, double* psi) const override {
    for (std::size_t i = 0; i < c_.size(); ++i) psi[i] = std::nan("");
  }
  bool planar_harmonic() const override { return c_.planar_harmonic(); }

 private:
  const Conductor& c_;
};
}  // namespace

// Issue 20, item 4: an exception in a worker thread used to call std::terminate (exit 134).
// It is caught there and rethrown on the caller's thread, whatever the number of threads.
TEST_CASE("A failure in a search thread reaches the caller", "[fibre][threads]") {
  PaperCase p;
  const NanConductor nan_conductor(*p.conductor);
  const Waveform wf = pulse_waveform(200, 0, 200, false);
  for (unsigned threads : {1u, 2u, 4u}) {
    CAPTURE(threads);
    ThresholdSettings s;
    s.threads = threads;
    s.offsets = 8;
    try {
      receptor_threshold(*p.model, p.setup, nan_conductor, p.w, p.sai(), wf, s);
      FAIL("no error");
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::failure);
      CHECK(std::string(e.what()).find("diverged") != std::string::npos);
    }
  }
}

// Issue 20, item 4: a buried point source on or within an internode of any fibre's path
// (the RA fibre's internodes below its receptor included) is bad input before any work.
TEST_CASE("A point source on a fibre's path is refused", "[fibre]") {
  Setup setup;
  setup.array = ElectrodeArray::uniform(1, 1.0);
  setup.conductor.model = "point3d";
  auto model = make_fibre_model("mrg");
  ThresholdSettings s;
  auto refused = [&](double depth_mm, double plane_z_mm = 0.0) {
    setup.conductor.source_depth_mm = depth_mm;
    setup.conductor.plane_z_mm = plane_z_mm;
    const auto c = make_conductor(setup.conductor, setup.array);
    try {
      for (const Receptor& r : setup.receptors) fibre_nodes(*model, setup, *c, r, s);
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      return true;
    }
    return false;
  };
  const Receptor& ra = setup.receptors[0];
  REQUIRE(ra.fibre.orientation == Orientation::vertical);
  const double L = model->internode_um(ra.fibre.diameter_um) * 1e-3;
  const double bottom = ra.depth_min_mm + 14 * L;  // its 15 nodes (docs/fibres.md)
  CHECK(refused(bottom));                          // its deepest node (the case)
  CHECK(refused(4.0));                             // between its nodes, below the receptor
  CHECK(refused(bottom + 0.9 * L));                // within an internode of its end
  CHECK_FALSE(refused(bottom + 1.1 * L));          // beyond
  CHECK_FALSE(refused(4.0, 1.1 * L));              // out of the fibres' plane by more
}

// Issue 20, item 10: where the target fires nowhere below max_mA, the objective is +inf; the
// summary optimize-weights prints says so in words, never "inf".
TEST_CASE("The threshold search's summary never says inf", "[fibre]") {
  ThresholdOptimum t;
  for (const char* name : {"RA", "SAI", "PC"}) {
    ReceptorThreshold r;
    r.receptor = name;
    t.report.receptors.push_back(r);
  }
  t.report.receptors[0].threshold_mA = 0.5;
  t.start = t.report;
  CHECK(threshold_search_summary(t, 1, 100.0) ==
        "SAI threshold ratio none (SAI has no threshold below 100 mA, nor at the AF optimum)");
  t.report.receptors[1].threshold_mA = 0.25;
  CHECK(threshold_search_summary(t, 1, 100.0) ==
        "SAI threshold ratio 0.5 (AF optimum: none, where SAI has no threshold below 100 mA)");
  t.start = t.report;
  t.report.receptors[1].threshold_mA = 0.2;
  CHECK(threshold_search_summary(t, 1, 100.0) == "SAI threshold ratio 0.4 (AF optimum: 0.5)");
}
