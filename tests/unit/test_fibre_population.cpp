// Populations of afferents (issue 24): a fibre placed where the single-fibre search found
// its minimum has that threshold exactly, and no sampled RA fibre beats the search; the
// same seed gives the same population, another seed another; recruitment is monotone and
// ends at the fraction that fires; the selectivity index is the stated difference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
#include <vector>

#include "fibre/population.hpp"
#include "fibre/threshold.hpp"
#include "model/field.hpp"

using namespace tp;
using namespace tp::fibre;

namespace {
struct Case {
  Setup setup;  // the paper's array, line2d, the default receptors
  std::vector<double> w{0, 0, -0.5, 1, -0.5, 0, 0, 0};
  std::unique_ptr<Conductor> conductor = make_conductor(setup.conductor, setup.array);
  std::unique_ptr<FibreModel> model = make_fibre_model("mrg");
  Waveform wf = pulse_waveform(200, 0, 200, false);
};
}  // namespace

TEST_CASE("a fibre where the search put it has the search's threshold", "[fibre][population]") {
  Case c;
  ThresholdSettings s;
  s.offsets = 4;
  s.threads = 1;
  // RA (vertical): the search over x, then one fibre at its x.
  const Receptor& ra = c.setup.receptors[0];
  const ReceptorThreshold searched =
      receptor_threshold(*c.model, c.setup, *c.conductor, c.w, ra, c.wf, s);
  REQUIRE(searched.threshold_mA);
  ThresholdSettings one = s;
  one.fixed_x_mm = searched.x_mm;
  const ReceptorThreshold fixed =
      receptor_threshold(*c.model, c.setup, *c.conductor, c.w, ra, c.wf, one);
  REQUIRE(fixed.threshold_mA);
  CHECK(*fixed.threshold_mA == *searched.threshold_mA);
  CHECK(fixed.placements == 1);
  // SAI (horizontal): the search over alignments, then one fibre at its alignment; the
  // search's minimum is the least of the fixed fibres at the alignments it tries (a
  // quarter internode apart), each of which needs at least as much.
  const Receptor& sai = c.setup.receptors[1];
  const ReceptorThreshold h =
      receptor_threshold(*c.model, c.setup, *c.conductor, c.w, sai, c.wf, s);
  REQUIRE(h.threshold_mA);
  ThresholdSettings at = s;
  at.fixed_offset_mm = h.offset_mm;
  const ReceptorThreshold hf =
      receptor_threshold(*c.model, c.setup, *c.conductor, c.w, sai, c.wf, at);
  REQUIRE(hf.threshold_mA);
  CHECK(*hf.threshold_mA == *h.threshold_mA);
  const double L = c.model->internode_um(sai.fibre.diameter_um) * 1e-3;
  double least = 1e9;
  for (int q = 0; q < 4; ++q) {
    at.fixed_offset_mm = L * q / 4.0;
    const auto t = receptor_threshold(*c.model, c.setup, *c.conductor, c.w, sai, c.wf, at);
    REQUIRE(t.threshold_mA);
    CHECK(*t.threshold_mA >= *h.threshold_mA);
    least = std::min(least, *t.threshold_mA);
  }
  CHECK(least == *h.threshold_mA);
}

TEST_CASE("populations: seeds, bounds, recruitment", "[fibre][population]") {
  Case c;
  ThresholdSettings s;
  PopulationOptions o;
  o.per_class = 12;
  o.seed = 5;
  const PulseSpec pulse;
  const auto classes = default_afferent_classes();
  const Population a = sample_population(c.setup, c.w, *c.model, pulse, s, classes, o);
  const Population b = sample_population(c.setup, c.w, *c.model, pulse, s, classes, o);
  REQUIRE(a.afferents.size() == 36);
  CHECK(population_csv(a) == population_csv(b));
  CHECK(recruitment_csv(a) == recruitment_csv(b));
  o.seed = 6;
  const Population d = sample_population(c.setup, c.w, *c.model, pulse, s, classes, o);
  CHECK(population_csv(d) != population_csv(a));
  // Within each class's ranges; the placed strip is the array and its 5 mm margin.
  for (const Afferent& f : a.afferents) {
    const auto& k = *std::find_if(classes.begin(), classes.end(),
                                  [&](const AfferentClass& x) { return x.receptor == f.receptor; });
    CHECK(f.diameter_um >= k.diameter_min_um);
    CHECK(f.diameter_um <= k.diameter_max_um);
    CHECK(f.depth_mm >= k.depth_min_mm);
    CHECK(f.depth_mm <= k.depth_max_mm);
    if (f.vertical) {
      CHECK(f.x_mm >= c.setup.array.x_min_mm() - 5.0);
      CHECK(f.x_mm <= c.setup.array.x_max_mm() + 5.0);
    }
  }
  // No RA fibre of the population beats the search over x for its own diameter and top.
  ThresholdSettings one;
  one.threads = 1;
  for (const Afferent& f : a.afferents) {
    if (!f.vertical || !f.threshold_mA) continue;
    Receptor r = c.setup.receptors[0];
    r.fibre.diameter_um = f.diameter_um;
    r.depth_min_mm = f.depth_mm;
    const auto best = receptor_threshold(*c.model, c.setup, *c.conductor, c.w, r, c.wf, one);
    REQUIRE(best.threshold_mA);
    CHECK(*f.threshold_mA >= *best.threshold_mA);
    break;  // one is enough for the bound (each search takes a while)
  }
  // Recruitment: monotone, from 0, ending at the fraction that fires; SI as stated.
  std::istringstream in(recruitment_csv(a));
  std::string line;
  std::getline(in, line);
  CHECK(line == "current_mA,recruited_RA,recruited_SAI,recruited_PC,si_RA,si_SAI,si_PC");
  std::vector<double> last(3, -1.0);
  double last_i = -1;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    REQUIRE(v.size() == 7);
    CHECK(v[0] > last_i);
    last_i = v[0];
    for (int k = 0; k < 3; ++k) {
      CHECK(v[1 + k] >= last[k]);
      CHECK(v[1 + k] <= 1.0);
      last[k] = v[1 + k];
      const double others = (v[1] + v[2] + v[3] - v[1 + k]) / 2;
      CHECK(v[4 + k] == Approx(v[1 + k] - others).margin(1e-9));
    }
  }
  for (int k = 0; k < 3; ++k) {
    std::size_t fired = 0;
    for (const Afferent& f : a.afferents)
      if (f.receptor == a.classes[k] && f.threshold_mA) ++fired;
    CHECK(last[k] == Approx(static_cast<double>(fired) / 12.0).margin(1e-9));
  }
}

TEST_CASE("a population over a 2-D array", "[fibre][population][array2d]") {
  // A 3 x 3 grid of 1 x 1 mm pads at 2 mm under rect3d, a cross of weights: afferents are
  // placed over the pads and margin in x and z, and each one's threshold is the single
  // fibre's through its (x, z).
  Setup setup;
  setup.array = ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.0, 1.0);
  setup.conductor.model = "rect3d";
  setup.lateral_margin_mm = 2.0;
  const std::vector<double> w{0, -0.25, 0, -0.25, 1, -0.25, 0, -0.25, 0};
  const auto model = make_fibre_model("mrg");
  const auto conductor = make_conductor(setup.conductor, setup.array);
  ThresholdSettings s;
  s.tolerance = 0.01;
  s.offsets = 2;
  PopulationOptions o;
  o.per_class = 2;
  o.seed = 3;
  const PulseSpec pulse;
  const Population p = sample_population(setup, w, *model, pulse, s, default_afferent_classes(), o);
  REQUIRE(p.afferents.size() == 6);
  CHECK(p.area_cm2 == Approx(0.64));  // (4 + 2 x 2)^2 mm^2
  CHECK(population_csv(p).rfind("class,x_mm,offset_mm,depth_mm,diameter_um,threshold_mA,z_mm",
                                0) == 0);
  std::size_t checked = 0;
  for (const Afferent& a : p.afferents) {
    CHECK(a.z_mm >= -4.0);
    CHECK(a.z_mm <= 4.0);
    if (!a.threshold_mA || a.receptor == "PC") continue;
    Receptor r = setup.receptors[a.vertical ? 0 : 1];
    r.fibre.diameter_um = a.diameter_um;
    r.depth_min_mm = a.depth_mm;
    ThresholdSettings one = s;
    one.threads = 1;
    one.through_mm = std::array<double, 2>{a.vertical ? a.x_mm : 0.0, a.z_mm};
    if (a.vertical) {
      one.fixed_x_mm = a.x_mm;
    } else {
      r.depth_max_mm = a.depth_mm;
      one.fixed_offset_mm = a.offset_mm;
    }
    const auto t =
        receptor_threshold(*model, setup, *conductor, w, r, waveform_of(pulse, s.delay_ms), one);
    REQUIRE(t.threshold_mA);
    CHECK(*t.threshold_mA == *a.threshold_mA);
    ++checked;
  }
  CHECK(checked >= 2);
}

TEST_CASE("selectivity at half recruitment: I50, the fractions there, the worst other class",
          "[fibre][population]") {
  fibre::Population p;
  p.classes = {"RA", "SAI", "PC"};
  auto add = [&](const std::string& c, std::optional<double> th) {
    fibre::Afferent a;
    a.receptor = c;
    a.threshold_mA = th;
    p.afferents.push_back(a);
  };
  // SAI: 5 afferents, thresholds 1..4 and one that never fires: I50 = the 3rd lowest, 3 mA.
  for (double t : {4.0, 1.0, 3.0, 2.0}) add("SAI", t);
  add("SAI", std::nullopt);
  // RA: 4, of which 1 at or below 3 mA (0.25); PC: 2, both below (1.0).
  for (double t : {2.5, 3.5, 5.0, 9.0}) add("RA", t);
  for (double t : {0.5, 3.0}) add("PC", t);
  const auto h = fibre::selectivity_at_half(p, "SAI");
  REQUIRE(h);
  CHECK(h->i50_mA == 3.0);
  CHECK(h->fraction == std::vector<double>{0.25, 0.6, 1.0});
  CHECK(h->worst == "PC");
  CHECK(h->index == -1.0);
  // RA: half of 4 is the 2nd lowest, 3.5 mA: SAI 3 of 5 (0.6), PC all: -1; without PC's
  // afferents, SAI's 0.6 is the worst: 1 - 1.2.
  const auto ra = fibre::selectivity_at_half(p, "RA");
  REQUIRE(ra);
  CHECK(ra->i50_mA == 3.5);
  CHECK(ra->index == -1.0);
  p.afferents.erase(std::remove_if(p.afferents.begin(), p.afferents.end(),
                                   [](const fibre::Afferent& a) { return a.receptor == "PC"; }),
                    p.afferents.end());
  CHECK(fibre::selectivity_at_half(p, "RA")->index == Approx(1.0 - 2 * 0.6));
  // The target fires first: 1.  Fewer than half firing, or no such class: none.
  fibre::Population first;
  first.classes = {"SAI", "PC"};
  for (double t : {1.0, 1.1}) {
    fibre::Afferent a;
    a.receptor = "SAI";
    a.threshold_mA = t;
    first.afferents.push_back(a);
    a.receptor = "PC";
    a.threshold_mA = t + 5;
    first.afferents.push_back(a);
  }
  CHECK(fibre::selectivity_at_half(first, "SAI")->index == 1.0);
  CHECK(fibre::selectivity_at_half(first, "SAI")->i50_mA == 1.0);
  CHECK(!fibre::selectivity_at_half(first, "RA"));
  for (auto& a : first.afferents)
    if (a.receptor == "SAI") a.threshold_mA.reset();
  CHECK(!fibre::selectivity_at_half(first, "SAI"));
}
