// The selectivity design (opt/selectivity_design.hpp, issue 40 item 3): never worse than
// its starts on the design's population; its score is the population's selectivity at
// half recruitment; every design it returns can be delivered (balanced in whole units,
// within the limits and the comfort bound at I50); held out, SAI's design keeps recruiting
// SAI first; no design is usable when the current limit is below every I50; the same
// options give the same design.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "fibre/population.hpp"
#include "model/field.hpp"
#include "opt/selectivity_design.hpp"
#include "pulse/shape.hpp"

using namespace tp;
using namespace tp::fibre;

namespace {
struct Case {
  Setup setup;  // the paper's array, line2d, the default receptors
  std::unique_ptr<FibreModel> model = make_fibre_model("mrg");
  ThresholdSettings settings;
  SelectivityOptions o;
  // SAI's AF optimum on the paper's array, rounded (optimize-weights --mode SAI).
  std::vector<double> sai{0, 0, -0.5, 1, -0.5, 0, 0, 0};
  Case() {
    settings.offsets = 2;
    settings.tolerance = 0.01;
    o.per_class = 4;
    o.max_evaluations = 8;
    o.threads = 2;
  }
  std::vector<ScoredDesign> starts() const {
    return {{"af optimum", {sai, shorthand_phases(200, 0, 200)}, {}, {}}};
  }
};
}  // namespace

// [numerics]: not under the sanitizers (the next case runs the same search).
TEST_CASE("a selectivity design: never worse than its start, deliverable, held out",
          "[opt][selectivity][numerics]") {
  Case c;
  const SelectivityResult r =
      design_for_selectivity(c.setup, "SAI", c.starts(), *c.model, c.settings, c.o);
  REQUIRE(r.starts.size() == 1);
  REQUIRE(r.evaluations <= c.o.max_evaluations);
  CHECK_FALSE(better(r.starts[0].score, r.best.score));
  REQUIRE(r.best.score.usable());
  // The score is the population's selectivity at half recruitment for the design.
  PulseSpec pulse;
  pulse.phases = r.best.design.phases;
  PopulationOptions po;
  po.per_class = c.o.per_class;
  po.seed = c.o.seed;
  po.threads = 2;
  const Population p = sample_population(c.setup, r.best.design.weights, *c.model, pulse,
                                         c.settings, default_afferent_classes(), po);
  const auto h = selectivity_at_half(p, "SAI");
  REQUIRE(h);
  CHECK(h->index == r.best.score.half.index);
  CHECK(h->i50_mA == r.best.score.half.i50_mA);
  // Deliverable: balanced in whole units, within the comfort bound (twice the start's).
  CHECK_NOTHROW(check_phases(r.best.design.phases, PhaseLimits{}));
  CHECK(shape_units(r.best.design.phases).unit <= 4);
  CHECK(r.max_charge_nC == Approx(2 * r.starts[0].score.charge_nC));
  CHECK(r.best.score.charge_nC <= r.max_charge_nC);
  // Held out (another seed): SAI still recruited first.
  REQUIRE(r.best.held_out.fires);
  CHECK(r.best.held_out.half.index > 0);
  // The front: ascending charge, each point better in index than those before or as good.
  for (std::size_t k = 1; k < r.front.size(); ++k) {
    CHECK(r.front[k].charge_nC >= r.front[k - 1].charge_nC);
    CHECK(r.front[k].index >= r.front[k - 1].index);
  }
  // The same options: the same design.
  const SelectivityResult again =
      design_for_selectivity(c.setup, "SAI", c.starts(), *c.model, c.settings, c.o);
  CHECK(again.best.design.weights == r.best.design.weights);
  CHECK(same_phases(again.best.design.phases, r.best.design.phases));
}

TEST_CASE("a selectivity design below every I50's current limit is not usable, and says why",
          "[opt][selectivity]") {
  Case c;
  c.o.limits.max_current_mA = 0.05;  // SAI's I50 is about 0.7 mA
  c.o.max_evaluations = 4;
  const SelectivityResult r =
      design_for_selectivity(c.setup, "SAI", c.starts(), *c.model, c.settings, c.o);
  CHECK_FALSE(r.best.score.usable());
  CHECK_FALSE(r.improved);  // nothing beat the start: it is returned
  CHECK(r.best.score.refused.find("current") != std::string::npos);
  CHECK(r.front.empty());
}

TEST_CASE("a selectivity design refuses bad options before any work", "[opt][selectivity]") {
  Case c;
  auto message = [&](const std::string& target, SelectivityOptions o) {
    try {
      design_for_selectivity(c.setup, target, c.starts(), *c.model, c.settings, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SelectivityOptions o = c.o;
  o.per_class = 0;
  CHECK(message("SAI", o) == "--population: 0 outside [1, 1000]");
  o = c.o;
  o.max_evaluations = 2;
  CHECK(message("SAI", o) == "--max-evaluations: 2 outside [4, 1000]");
  CHECK(message("Merkel", c.o) == "--mode: Merkel is not a class of afferents (RA, SAI, PC)");
  o = c.o;
  o.per_class = 1000;
  o.max_evaluations = 1000;
  CHECK(message("SAI", o).find("--objective selectivity (1000 populations of 1000 a class)") !=
        std::string::npos);
}
