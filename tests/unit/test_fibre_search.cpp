// The threshold search over any potential (fibre/search.hpp), on closed forms: a point
// source's potential along a straight MRG fibre.  The answer is the lattice point where the
// fibre first fires, within the tolerance of a plain bisection; it scales exactly with the
// potential; it depends neither on the start nor on the threads, only the work does; ties go
// to the lowest index; and the passive estimate's pieces have their closed forms.

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "fibre/search.hpp"

using namespace tp;
using namespace tp::fibre;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A point cathode of 1 mA at h_mm from node `node` of the axon, in 300 ohm cm: the
// potential (mV) at each compartment, -rho / (4 pi r).
std::vector<double> point_source_mV(const Axon& a, std::size_t node, double h_mm,
                                    double scale = 1.0) {
  std::vector<double> ve(a.compartments.size());
  const double mid = a.centre_um[a.nodes[node]];
  for (std::size_t k = 0; k < ve.size(); ++k)
    ve[k] = -scale * 300.0 / (4 * kPi * std::hypot((a.centre_um[k] - mid) * 1e-4, h_mm * 0.1));
  return ve;
}

// A 10 um MRG fibre of 21 nodes, a 100 us cathodic pulse, detection at the sixth node from
// each end.
struct TestFibre {
  std::unique_ptr<FibreModel> model = make_fibre_model("mrg");
  Axon axon = model->axon(10.0, 21);
  Waveform pulse = pulse_waveform(100, 0, 100, true);
  SimOptions options() const {
    SimOptions o;
    o.tstop_ms = pulse.end_ms() + 1.5;
    o.detect = {5, axon.nodes.size() - 6};
    return o;
  }
  ThresholdSettings settings(unsigned threads = 1) const {
    ThresholdSettings s;
    s.threads = threads;
    return s;
  }
  AmplitudeSearch search(const ThresholdSettings& s) const {
    return AmplitudeSearch(*model, axon, pulse, options(), s);
  }
};

long from_1mA(const AmplitudeSearch& s) {
  return s.lattice().at_or_above(1.0);
}

}  // namespace

TEST_CASE("The search finds the lattice point where a point source first fires the fibre",
          "[fibre][search]") {
  TestFibre f;
  const std::vector<double> ve = point_source_mV(f.axon, 10, 1.0);
  AmplitudeSearch search = f.search(f.settings());
  const Best best = search.minimum({ve}, 0, Best{}, from_1mA(search), false);
  REQUIRE(best.found);
  CHECK(best.index == 0);
  REQUIRE(best.j > search.jmin());
  REQUIRE(best.j <= search.jmax());
  // Fires at the point, and is not even excited one point below (runs to their ends).
  const AmplitudeLattice& lattice = search.lattice();
  CableSimulator sim(*f.model, f.axon);
  const SimOptions o = f.options();
  CHECK(sim.run(ve.data(), lattice.amplitude(best.j), f.pulse, o).fired);
  CHECK(sim.run(ve.data(), lattice.amplitude(best.j - 1), f.pulse, o).first_time_ms < 0.0);
  // A plain bisection on firing, to 1e-5, agrees within one lattice step (0.1 %).
  double lo = 0.5 * lattice.amplitude(best.j - 1), hi = 2.0 * lattice.amplitude(best.j);
  REQUIRE_FALSE(sim.run(ve.data(), lo, f.pulse, o).fired);
  REQUIRE(sim.run(ve.data(), hi, f.pulse, o).fired);
  while (hi - lo > 1e-5 * hi) {
    const double mid = 0.5 * (lo + hi);
    (sim.run(ve.data(), mid, f.pulse, o).fired ? hi : lo) = mid;
  }
  CHECK(lattice.amplitude(best.j) >= lo);
  CHECK(lattice.amplitude(best.j) <= hi * (1.0 + 1e-3));
  // And fibre_threshold, the search on one potential, gives that point in mA.
  const std::optional<double> t = fibre_threshold(*f.model, f.axon, ve, f.pulse, o, f.settings());
  REQUIRE(t);
  CHECK(*t == lattice.amplitude(best.j));
}

TEST_CASE("The search's answer scales exactly with the potential", "[fibre][search]") {
  TestFibre f;
  AmplitudeSearch search = f.search(f.settings());
  const long K = search.lattice().per_octave;
  auto point = [&](double scale) {
    const Best b =
        search.minimum(std::vector<std::vector<double>>{point_source_mV(f.axon, 10, 1.0, scale)}, 0,
                       Best{}, from_1mA(search), false);
    REQUIRE(b.found);
    return b.j;
  };
  const long j = point(1.0);
  CHECK(point(2.0) == j - K);       // twice the potential: half the threshold
  CHECK(point(0.25) == j + 2 * K);  // a quarter: four times
  CHECK(point(512.0) == j - 9 * K);
}

TEST_CASE("The start and the threads change the search's work, not its answer", "[fibre][search]") {
  TestFibre f;
  // Sources at 0.5, 1, 1.5 and 2 mm, then 0.5 mm again: the nearest fires first, and the
  // tie between the two nearest goes to the lower index.
  std::vector<std::vector<double>> ve;
  for (double h : {1.5, 0.5, 2.0, 1.0, 0.5}) ve.push_back(point_source_mV(f.axon, 10, h));
  AmplitudeSearch reference = f.search(f.settings());
  const Best best = reference.minimum(ve, 0, Best{}, from_1mA(reference), false);
  REQUIRE(best.found);
  CHECK(best.index == 1);
  for (unsigned threads : {1u, 3u})
    for (double start_mA : {1e-6, 0.05, 1.0, 99.0})
      for (bool close : {false, true}) {
        CAPTURE(threads, start_mA, close);
        AmplitudeSearch search = f.search(f.settings(threads));
        const Best b = search.minimum(ve, 0, Best{}, search.lattice().at_or_above(start_mA), close);
        CHECK(b.found);
        CHECK(b.j == best.j);
        CHECK(b.index == best.index);
      }
  // One potential: a close start at the answer costs fewer runs than one far below it.
  auto runs = [&](long guess) {
    AmplitudeSearch search = f.search(f.settings());
    CHECK(search.minimum({ve[1]}, 0, Best{}, guess, true).j == best.j);
    return search.simulations();
  };
  CHECK(runs(best.j) < runs(best.j - 10 * reference.lattice().per_octave));
}

TEST_CASE("The search goes on from the best of earlier potentials", "[fibre][search]") {
  TestFibre f;
  // A near source, a far one, the near one again.
  const std::vector<std::vector<double>> ve{point_source_mV(f.axon, 10, 0.5),
                                            point_source_mV(f.axon, 10, 2.0),
                                            point_source_mV(f.axon, 10, 0.5)};
  AmplitudeSearch all = f.search(f.settings());
  const Best whole = all.minimum(ve, 0, Best{}, from_1mA(all), false);
  // The first alone, then the rest from its best: the same minimum.
  AmplitudeSearch parts = f.search(f.settings());
  const Best first = parts.minimum({ve[0]}, 0, Best{}, from_1mA(parts), false);
  std::vector<std::vector<double>> grown{ve[0]};
  const Best again = parts.minimum(grown, 0, Best{}, from_1mA(parts), false);
  CHECK(again.j == first.j);
  grown.push_back(ve[1]);
  grown.push_back(ve[2]);
  const Best rest = parts.minimum(grown, 1, first, from_1mA(parts), false);
  CHECK(rest.j == whole.j);
  CHECK(rest.index == whole.index);
  // The near source again ties with the first, and loses.
  CHECK(whole.index == 0);
  CHECK(whole.j == first.j);
  // A potential that cannot beat the best so far costs one run: the source 2 mm away does
  // not excite the fibre at the best's point.
  AmplitudeSearch one = f.search(f.settings());
  const Best unchanged = one.minimum({ve[0], ve[1]}, 1, first, from_1mA(one), true);
  CHECK(unchanged.j == first.j);
  CHECK(unchanged.index == 0);
  CHECK(one.simulations() == 1);
}

TEST_CASE("The search's range: no threshold below max_mA, or fired even at its floor",
          "[fibre][search]") {
  TestFibre f;
  const SimOptions o = f.options();
  // No field: nothing fires.
  const std::vector<double> zero(f.axon.compartments.size(), 0.0);
  AmplitudeSearch search = f.search(f.settings());
  CHECK_FALSE(search.minimum({zero}, 0, Best{}, from_1mA(search), false).found);
  CHECK_FALSE(fibre_threshold(*f.model, f.axon, zero, f.pulse, o, f.settings()));
  // A threshold near 1 mA with max_mA at 0.01 mA: none.
  const std::vector<double> ve = point_source_mV(f.axon, 10, 1.0);
  ThresholdSettings low = f.settings();
  low.max_mA = 0.01;
  AmplitudeSearch capped = f.search(low);
  CHECK_FALSE(capped.minimum({ve}, 0, Best{}, from_1mA(capped), false).found);
  CHECK_FALSE(fibre_threshold(*f.model, f.axon, ve, f.pulse, o, low));
  // 1e15 times the potential: excited at the floor (2^-50 x 100 mA), reported below it.
  const std::vector<double> huge = point_source_mV(f.axon, 10, 1.0, 1e15);
  const Best floor = search.minimum({huge}, 0, Best{}, from_1mA(search), false);
  REQUIRE(floor.found);
  CHECK(floor.j == search.jmin() - 1);
  CHECK(search.lattice().amplitude(search.jmin()) ==
        Approx(100.0 * std::ldexp(1.0, -50)).epsilon(1e-3));
  CHECK_FALSE(fibre_threshold(*f.model, f.axon, huge, f.pulse, o, f.settings()));
}

TEST_CASE("The passive estimate's pieces have their closed forms", "[fibre][search]") {
  TestFibre f;
  // The activating function at the nodes: one node at -1 mV, the rest at 0, drives it by 2.
  std::vector<double> ve(f.axon.compartments.size(), 0.0);
  ve[f.axon.nodes[7]] = -1.0;
  CHECK(largest_af(f.axon, ve.data()) == 2.0);
  // A uniform gradient drives only the end nodes, by one internode's drop.
  for (std::size_t k = 0; k < ve.size(); ++k) ve[k] = 0.5 * static_cast<double>(k);
  const double drop = 0.5 * static_cast<double>(f.axon.nodes[1] - f.axon.nodes[0]);
  CHECK(largest_af(f.axon, ve.data()) == Approx(drop));
  // K = 4.3 + 5.3 / sqrt(the longest phase in ms); a gap is not a phase.
  CHECK(passive_k_mV(pulse_waveform(100, 0, 100, true)) == Approx(4.3 + 5.3 / std::sqrt(0.1)));
  CHECK(passive_k_mV(pulse_waveform(200, 50, 400, false)) == Approx(4.3 + 5.3 / std::sqrt(0.4)));
  CHECK(passive_k_mV(Waveform{}) == 0.0);
  // The caller's start: positive and finite, at most max_mA.
  ThresholdSettings s;
  CHECK_FALSE(caller_start(s));
  s.start_mA = {0.0};
  CHECK_FALSE(caller_start(s));
  s.start_mA = {std::nan("")};
  CHECK_FALSE(caller_start(s));
  s.start_mA = {250.0};
  CHECK(caller_start(s) == 100.0);
  s.start_mA = {0.3, 7.0};
  CHECK(caller_start(s) == 0.3);
}
