// Where a receptor's fibres lie (fibre/placements.hpp): the plan counts exactly the
// placements it generates, for every kind of fibre and every conductor; its placements are
// those docs/fibres.md describes; and the three users of the count (fibre_nodes' bound,
// threshold_work's estimate, receptor_threshold's search) count the same placements.

#include <catch2/catch.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fibre/placements.hpp"
#include "fibre/threshold.hpp"
#include "core/number.hpp"
#include "model/conductor.hpp"
#include "model/field.hpp"

using namespace tp;
using namespace tp::fibre;

namespace {

const Waveform kPulse = pulse_waveform(200, 0, 200, false);

// RA (vertical, 0.7 to 2.0 mm), SAI (horizontal at 0.9 mm) and SAI over a depth range.
Receptor receptor(const Setup& setup, const std::string& name) {
  for (const Receptor& r : setup.receptors)
    if (r.name == name) return r;
  Receptor r = receptor(setup, "SAI");  // "SAI-range"
  r.name = name;
  r.depth_min_mm = 0.5;
  r.depth_max_mm = 1.0;
  return r;
}

// Every round of the plan, each refinement around a placement of the round before (one
// off its centre, as a search's best may be): the placements, checked round by round
// against round_size().
std::vector<Spot> generate(const PlacementPlan& plan) {
  std::vector<Spot> all;
  Spot best;
  for (std::size_t k = 0; k < plan.rounds(); ++k) {
    const std::vector<Spot> round = plan.round(k, best);
    CHECK(round.size() == plan.round_size(k));
    REQUIRE_FALSE(round.empty());
    best = round[round.size() / 3];
    all.insert(all.end(), round.begin(), round.end());
  }
  CHECK(plan.round(plan.rounds(), best).empty());
  CHECK(plan.round_size(plan.rounds()) == 0);
  return all;
}

struct Case {
  std::string what;
  Setup setup;
  std::string receptor;
  ThresholdSettings settings;
  std::size_t count;  // along one fibre, as docs/fibres.md counts them
  std::size_t fibres = 1;
};

Setup setup_of(const std::string& model, const ElectrodeArray& array) {
  Setup s;
  s.conductor.model = model;
  s.array = array;
  return s;
}

// The cases of one conductor: 1-D arrays for every model; 2-D ones for the 3-D models.
std::vector<Case> cases_for(const std::string& model) {
  std::vector<Case> out;
  ThresholdSettings s;  // 8 offsets
  ThresholdSettings fixed_x = s, fixed_offset = s, afferent = s, one_stem = s;
  fixed_x.fixed_x_mm = 0.3;
  fixed_offset.fixed_offset_mm = 0.2;
  afferent.geometry = Geometry::afferent;
  one_stem = afferent;
  one_stem.fixed_direction = 1;
  // A 1-D array of n electrodes: 4 (n + 1) + 1 across it (one electrode: 9 across a pitch
  // of 1 mm either side), then twice 9 around the best.
  const Setup paper = setup_of(model, ElectrodeArray::paper());
  const Setup single = setup_of(model, ElectrodeArray::uniform(1, 1.0));
  Setup uneven = paper;
  uneven.array.positions_mm = {-3.0, -1.0, 0.0, 4.0};  // mean pitch 7/3 mm
  out.push_back({"RA, 8 electrodes", paper, "RA", s, 4 * 9 + 1 + 18});
  out.push_back({"RA, 1 electrode", single, "RA", s, 9 + 18});
  out.push_back({"RA, 4 uneven electrodes", uneven, "RA", s, 4 * 5 + 1 + 18});
  out.push_back({"RA at one x", paper, "RA", fixed_x, 1});
  out.push_back({"RA afferent", paper, "RA", afferent, 4 * 9 + 1 + 18, 2});
  out.push_back({"RA afferent, one stem", paper, "RA", one_stem, 4 * 9 + 1 + 18, 1});
  out.push_back({"RA afferent at one x, one stem", paper, "RA",
                 [&] {
                   ThresholdSettings t = one_stem;
                   t.fixed_x_mm = -1.0;
                   return t;
                 }(),
                 1, 1});
  out.push_back({"SAI", paper, "SAI", s, 8});
  out.push_back({"SAI over a depth range", paper, "SAI-range", s, 5 * 8});
  out.push_back({"SAI, 3 offsets", single, "SAI",
                 [&] {
                   ThresholdSettings t = s;
                   t.offsets = 3;
                   return t;
                 }(),
                 3});
  out.push_back({"SAI at one alignment", paper, "SAI-range", fixed_offset, 1});
  if (model == "line2d" || model == "strip2d") return out;
  // A 2-D grid: 5 x 5 around the point, then twice 5 x 5 around the best.
  const Setup grid = setup_of(model, ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.5, 1.5));
  ThresholdSettings at = s;
  at.through_mm = std::array<double, 2>{0.5, -1.0};
  ThresholdSettings at_x = at;
  at_x.fixed_x_mm = 0.5;
  ThresholdSettings at_afferent = at;
  at_afferent.geometry = Geometry::afferent;
  out.push_back({"RA under a grid", grid, "RA", at, 75});
  out.push_back({"RA under a grid at one x", grid, "RA", at_x, 1});
  out.push_back({"RA afferent under a grid", grid, "RA", at_afferent, 75, 2});
  out.push_back({"SAI under a grid", grid, "SAI-range", at, 5 * 8});
  return out;
}

}  // namespace

TEST_CASE("The placement plan counts the placements it generates, for every conductor",
          "[fibre][placements]") {
  const auto model = make_fibre_model("mrg");
  for (const std::string& name : conductor_models()) {
    for (const Case& c : cases_for(name)) {
      CAPTURE(name, c.what);
      const auto conductor = make_conductor(c.setup.conductor, c.setup.array);
      const Receptor r = receptor(c.setup, c.receptor);
      // The fibres are accepted, and the plan's fibres are the ones simulated.
      const FibreRun f = fibre_run(*model, c.setup, *conductor, r, kPulse, c.settings);
      const PlacementPlan plan(c.setup, r, c.settings, f.internode_mm);
      CHECK(plan.fibres() == c.fibres);
      CHECK(plan.fibres() == f.axons.size());
      CHECK(plan.vertical() == (r.fibre.orientation == Orientation::vertical));
      const std::vector<Spot> all = generate(plan);
      CHECK(all.size() == plan.count());
      CHECK(plan.count() == c.count);
    }
  }
}

TEST_CASE("The placements are those of docs/fibres.md", "[fibre][placements]") {
  const auto model = make_fibre_model("mrg");
  const Setup paper = setup_of("line2d", ElectrodeArray::paper());  // -3.5 to 3.5 mm
  ThresholdSettings s;

  SECTION("vertical fibres across a 1-D array: every quarter pitch, then by quarters") {
    const Receptor ra = receptor(paper, "RA");
    const PlacementPlan plan(paper, ra, s, 0.36);
    REQUIRE(plan.kind() == PlacementPlan::Kind::vertical_across);
    const std::vector<Spot> first = plan.round(0);
    REQUIRE(first.size() == 37);
    for (std::size_t i = 0; i < first.size(); ++i) {
      CHECK(first[i].x0_mm == Approx(-4.5 + 0.25 * static_cast<double>(i)).margin(1e-12));
      CHECK(first[i].y0_mm == ra.depth_min_mm);  // the sealed terminal at the top
      CHECK(first[i].z0_mm == 0.0);
      CHECK(first[i].direction == 0);
    }
    const Spot best = first[20];  // x = 0.5
    const std::vector<Spot> second = plan.round(1, best);
    REQUIRE(second.size() == 9);
    for (std::size_t i = 0; i < 9; ++i)
      CHECK(second[i].x0_mm == Approx(0.5 - 0.25 + 0.0625 * static_cast<double>(i)).margin(1e-12));
    const std::vector<Spot> third = plan.round(2, second[7]);  // x = 0.6875
    REQUIRE(third.size() == 9);
    CHECK(third.front().x0_mm == Approx(0.6875 - 0.0625).margin(1e-12));
    CHECK(third[1].x0_mm - third[0].x0_mm == Approx(1.0 / 64).margin(1e-12));  // a 64th
  }

  SECTION("vertical fibres under a grid: 5 x 5 around the point, then at half the step") {
    const Setup grid = setup_of("rect3d", ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.5, 1.5));
    s.through_mm = std::array<double, 2>{0.5, -1.0};
    const PlacementPlan plan(grid, receptor(grid, "RA"), s, 0.36);
    REQUIRE(plan.kind() == PlacementPlan::Kind::vertical_around);
    const std::vector<Spot> first = plan.round(0);
    REQUIRE(first.size() == 25);
    CHECK(first.front().x0_mm == Approx(0.5 - 1.0));  // a quarter pitch is 0.5 mm
    CHECK(first.front().z0_mm == Approx(-1.0 - 1.0));
    CHECK(first[12].x0_mm == Approx(0.5));  // the point at the centre
    CHECK(first[12].z0_mm == Approx(-1.0));
    CHECK(first.back().x0_mm == Approx(0.5 + 1.0));
    const std::vector<Spot> second = plan.round(1, first[3]);
    CHECK(second[12].x0_mm == first[3].x0_mm);
    CHECK(second[1].x0_mm - second[0].x0_mm == Approx(0.25));
    const std::vector<Spot> third = plan.round(2, second[0]);
    CHECK(third[12].z0_mm == second[0].z0_mm);
    CHECK(third[5].z0_mm - third[0].z0_mm == Approx(0.125));  // a 16th of the pitch
  }

  SECTION("horizontal fibres: K alignments over an internode at five depths of a range") {
    const Receptor sai = receptor(paper, "SAI-range");
    const double L = model->internode_um(sai.fibre.diameter_um) * 1e-3;
    s.offsets = 4;
    const PlacementPlan plan(paper, sai, s, L);
    REQUIRE(plan.kind() == PlacementPlan::Kind::horizontal);
    const std::vector<Spot> all = plan.round(0);
    REQUIRE(all.size() == 20);
    const double left = fibre_region(paper, sai).x0_mm - 5.0 * L;
    for (std::size_t i = 0; i < all.size(); ++i) {
      CAPTURE(i);
      const std::size_t depth = i / 4, q = i % 4;
      CHECK(all[i].y0_mm == Approx(0.5 + 0.125 * static_cast<double>(depth)));
      CHECK(all[i].offset_mm == Approx(L * static_cast<double>(q) / 4));
      // A node at offset + m L, the first at or before five internodes left of the region.
      CHECK(all[i].x0_mm <= left + 1e-12);
      CHECK(all[i].x0_mm > left - L);
      const double m = (all[i].x0_mm - all[i].offset_mm) / L;
      CHECK(m == Approx(std::round(m)).margin(1e-9));
    }
  }
}

// One count: the work estimate and the bound on unit potentials scale with the plan's
// count, and the search tries exactly the plan's placements.
TEST_CASE("threshold_work and fibre_nodes count the plan's placements", "[fibre][placements]") {
  const auto model = make_fibre_model("mrg");
  for (const std::string& name : conductor_models()) {
    for (const Case& c : cases_for(name)) {
      // An afferent's stem reaches past every ending it serves: at one x it is shorter.
      if (c.settings.geometry == Geometry::afferent) continue;
      CAPTURE(name, c.what);
      const auto conductor = make_conductor(c.setup.conductor, c.setup.array);
      const Receptor r = receptor(c.setup, c.receptor);
      // The same fibre at one placement: the work per placement.
      ThresholdSettings one = c.settings;
      if (r.fibre.orientation == Orientation::vertical)
        one.fixed_x_mm = 0.5;
      else
        one.fixed_offset_mm = 0.1;
      const double per = threshold_work(*model, c.setup, *conductor, r, kPulse, one);
      const double all = threshold_work(*model, c.setup, *conductor, r, kPulse, c.settings);
      CHECK(all / per == Approx(static_cast<double>(c.count)).epsilon(1e-12));
    }
  }
}

TEST_CASE("fibre_nodes bounds the unit potentials of the plan's placements",
          "[fibre][placements]") {
  const auto model = make_fibre_model("mrg");
  // 64 electrodes over 189 mm: SAI's fibre at five depths, 64 alignments each, keeps more
  // than 3e7 unit potentials; one alignment at each depth far fewer.
  const Setup setup = setup_of("line2d", ElectrodeArray::uniform(64, 3.0));
  const auto conductor = make_conductor(setup.conductor, setup.array);
  const Receptor sai = receptor(setup, "SAI-range");
  ThresholdSettings s;
  s.offsets = 1;
  const std::size_t nodes = fibre_nodes(*model, setup, *conductor, sai, s);
  s.offsets = 64;
  const double per_placement =
      static_cast<double>(nodes) *
      static_cast<double>(model->axon(sai.fibre.diameter_um, 2).compartments.size() - 1) * 64.0;
  const PlacementPlan plan(setup, sai, s, model->internode_um(sai.fibre.diameter_um) * 1e-3);
  REQUIRE(plan.count() == 320);
  try {
    fibre_nodes(*model, setup, *conductor, sai, s);
    FAIL("not refused");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Contains(number_text(per_placement * 320.0) +
                                         " unit potentials to keep (at most 30000000)"));
  }
}

TEST_CASE("The search tries the plan's placements, round by round", "[fibre][placements][mrg]") {
  const auto model = make_fibre_model("mrg");
  // One electrode (the plan's 27 across and around it), a cathode; the afferent's two stems.
  const Setup setup = setup_of("line2d", ElectrodeArray::uniform(1, 1.0));
  const auto conductor = make_conductor(setup.conductor, setup.array);
  const Receptor ra = receptor(setup, "RA");
  for (const Geometry geometry : {Geometry::straight, Geometry::afferent}) {
    CAPTURE(geometry == Geometry::afferent);
    ThresholdSettings s;
    s.tolerance = 0.01;
    s.threads = 2;
    s.geometry = geometry;
    const ReceptorThreshold t = receptor_threshold(*model, setup, *conductor, {1.0}, ra, kPulse, s);
    REQUIRE(t.threshold_mA);
    const FibreRun f = fibre_run(*model, setup, *conductor, ra, kPulse, s);
    const PlacementPlan plan(setup, ra, s, f.internode_mm);
    REQUIRE(plan.count() == 27);
    CHECK(t.placements == plan.count() * plan.fibres());
    REQUIRE(t.tried.size() == t.placements);
    // Each fibre's rounds in order: the first as planned, each refinement the plan's
    // around one placement of the round before.
    for (std::size_t fi = 0; fi < plan.fibres(); ++fi) {
      const auto at = t.tried.begin() + static_cast<long>(fi * plan.count());
      std::vector<Spot> round0(at, at + 9), round1(at + 9, at + 18), round2(at + 18, at + 27);
      for (Spot& x : round0) CHECK(x.direction == f.directions[fi]);
      for (auto* r : {&round0, &round1, &round2})
        for (Spot& x : *r) x.direction = 0;
      CHECK(round0 == plan.round(0));
      auto refines = [&](const std::vector<Spot>& before, std::size_t k,
                         const std::vector<Spot>& after) {
        for (const Spot& b : before)
          if (plan.round(k, b) == after) return true;
        return false;
      };
      CHECK(refines(round0, 1, round1));
      CHECK(refines(round1, 2, round2));
    }
  }
}

namespace {
// A conductor that is another but says its sources lie buried at depth_mm.
class BuriedSources : public Conductor {
 public:
  BuriedSources(const Conductor& c, double depth_mm) : c_(c), depth_mm_(depth_mm) {}
  const char* name() const override { return "buried"; }
  std::size_t size() const override { return c_.size(); }
  void unit_second_derivatives(double x, double y, double* xx, double* yy) const override {
    c_.unit_second_derivatives(x, y, xx, yy);
  }
  void unit_potentials(double x, double y, double* psi) const override {
    c_.unit_potentials(x, y, psi);
  }
  bool planar_harmonic() const override { return c_.planar_harmonic(); }
  double buried_source_depth_mm() const override { return depth_mm_; }

 private:
  const Conductor& c_;
  double depth_mm_;
};

bool refused_near_source(const Setup& setup, const Conductor& c) {
  const auto model = make_fibre_model("mrg");
  try {
    fibre_nodes(*model, setup, c, setup.receptors[0], ThresholdSettings{});  // RA
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Contains("model.source_depth_mm: 4 mm is"));
    return true;
  }
  return false;
}
}  // namespace

// A conductor says where its sources are (Conductor::buried_source_depth_mm); the fibres'
// check asks it, not the model's name.
TEST_CASE("The fibres keep clear of the sources the conductor says are buried",
          "[fibre][placements]") {
  Setup setup = setup_of("point3d", ElectrodeArray::paper());
  for (const std::string& name : conductor_models()) {
    CAPTURE(name);
    setup.conductor.model = name;
    setup.conductor.source_depth_mm = name == "point3d" ? 4.0 : 0.0;
    const auto c = make_conductor(setup.conductor, setup.array);
    CHECK(c->buried_source_depth_mm() == setup.conductor.source_depth_mm);
    // 4 mm: between the RA fibre's nodes below its receptor.
    CHECK(refused_near_source(setup, *c) == (name == "point3d"));
    setup.conductor.source_depth_mm = 0.0;
    const auto surface = make_conductor(setup.conductor, setup.array);
    CHECK(surface->buried_source_depth_mm() == 0.0);
    CHECK(refused_near_source(setup, BuriedSources(*surface, 4.0)));
  }
}
