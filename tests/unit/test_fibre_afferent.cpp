// The afferent geometry (fibre/geometry.hpp): its path and compartments as described
// (docs/fibres.md, "Afferent geometry"), the model's own internodes unchanged, the short
// ones exactly as long as asked, mirror symmetry of the search, and its refusals.  NEURON's
// agreement is tests/neuron/compare-afferent's.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fibre/geometry.hpp"
#include "fibre/threshold.hpp"
#include "model/field.hpp"

using namespace tp;
using namespace tp::fibre;

TEST_CASE("MRG's internodes, the model's own length and shortened", "[fibre][afferent]") {
  // MRGaxon.hoc's 10 um fibre: node 1 um, MYSA 3 um, FLUT 46 um, six STIN of
  // (1150 - 1 - 6 - 92) / 6 um, nodes 1150 um apart; an internode of 80 um keeps the node
  // and MYSA and shortens FLUT and STIN by (80 - 7) / (1150 - 7).
  const auto mrg = make_fibre_model("mrg");
  const Axon a = mrg->axon_with_internodes(10.0, {1150.0, 80.0});
  const double stin = (1150.0 - 1.0 - 6.0 - 92.0) / 6.0, k = (80.0 - 7.0) / (1150.0 - 7.0);
  const std::vector<double> lengths{
      1, 3,      46,       stin,     stin,     stin,     stin,     stin,     stin,   46, 3, 1,
      3, 46 * k, stin * k, stin * k, stin * k, stin * k, stin * k, stin * k, 46 * k, 3,  1};
  REQUIRE(a.compartments.size() == lengths.size());
  for (std::size_t c = 0; c < lengths.size(); ++c)
    CHECK(a.compartments[c].length_um == Approx(lengths[c]).epsilon(1e-12));
  REQUIRE(a.nodes.size() == 3);
  CHECK(a.centre_um[a.nodes[1]] - a.centre_um[a.nodes[0]] == Approx(1150.0).epsilon(1e-12));
  CHECK(a.centre_um[a.nodes[2]] - a.centre_um[a.nodes[1]] == Approx(80.0).epsilon(1e-12));
  // The same axon as axon(d, n) where every internode is the model's own.
  const Axon b = mrg->axon(10.0, 2), c = mrg->axon_with_internodes(10.0, {1150.0});
  REQUIRE(b.compartments.size() == c.compartments.size());
  for (std::size_t q = 0; q < b.compartments.size(); ++q)
    CHECK(b.compartments[q].ri_half_kohm == c.compartments[q].ri_half_kohm);
}

TEST_CASE("an afferent's path: ending, heminode, short internodes, bend, stem",
          "[fibre][afferent]") {
  const auto mrg = make_fibre_model("mrg");
  const AfferentShape shape;
  const double drop = 1.3, stem = 5.0, d = 4.0;
  for (int dir : {-1, 1}) {
    const Axon a = afferent_axon(*mrg, d, drop, dir, stem, shape);
    REQUIRE(a.path_x_mm.size() == a.compartments.size());
    // The ending: four passive compartments from the tip, straight down.
    for (std::size_t k = 0; k < shape.ending_compartments; ++k) {
      CHECK(a.compartments[k].kind == CompartmentKind::ending);
      CHECK(a.path_x_mm[k] == 0.0);
    }
    // The heminode just below it; the short internodes node to node exactly 80 um.
    CHECK(a.nodes[0] == shape.ending_compartments);
    CHECK(a.path_y_mm[a.nodes[0]] == Approx(0.0805).margin(1e-12));
    for (std::size_t i = 0; i < shape.short_internodes; ++i)
      CHECK(a.centre_um[a.nodes[i + 1]] - a.centre_um[a.nodes[i]] ==
            Approx(shape.short_internode_um).epsilon(1e-12));
    CHECK(a.centre_um[a.nodes[5]] - a.centre_um[a.nodes[4]] ==
          Approx(mrg->internode_um(d)).epsilon(1e-12));
    // The path is continuous (no step longer than the arc between centres, nor much
    // shorter: a chord of the bend), never climbs
    // above the tip, and ends in the stem at the drop, at least `stem` beyond the bend, on
    // the side asked.
    for (std::size_t k = 1; k < a.compartments.size(); ++k) {
      const double step =
          std::hypot(a.path_x_mm[k] - a.path_x_mm[k - 1], a.path_y_mm[k] - a.path_y_mm[k - 1]);
      CHECK(step <= (a.centre_um[k] - a.centre_um[k - 1]) * 1e-3 + 1e-12);
      CHECK(step >= 0.98 * (a.centre_um[k] - a.centre_um[k - 1]) * 1e-3);
      CHECK(a.path_y_mm[k] >= a.path_y_mm[k - 1] - 1e-12);
    }
    CHECK(a.path_y_mm.back() == Approx(drop).epsilon(1e-12));
    CHECK(dir * a.path_x_mm.back() >= shape.bend_radius_mm + stem);
  }
}

TEST_CASE("afferents are refused where they cannot be built", "[fibre][afferent]") {
  const auto mrg = make_fibre_model("mrg");
  // The drop must hold the ending (0.08 mm), four 80 um internodes and the bend (0.1 mm).
  CHECK_NOTHROW(afferent_axon(*mrg, 4.0, 0.5, 1, 5.0));
  CHECK_THROWS_AS(afferent_axon(*mrg, 4.0, 0.499, 1, 5.0), Error);
  CHECK_THROWS_AS(afferent_axon(*mrg, 4.0, 1.3, 0, 5.0), Error);
  CHECK_THROWS_AS(afferent_axon(*make_fibre_model("senn"), 4.0, 1.3, 1, 5.0), Error);
  CHECK_THROWS_AS(mrg->axon_with_internodes(4.0, {10.0}), Error);
  CHECK_THROWS_AS(geometry_from_string("bent"), Error);
}

namespace {
// n pads 0.5 x 10 mm at 1 mm under line2d, MRG, 200 us monophasic: receptor k's threshold
// (0: RA, vertical; 1: SAI, horizontal) for weights w.
struct Line2d {
  Setup setup;
  std::unique_ptr<Conductor> conductor;
  std::unique_ptr<FibreModel> mrg = make_fibre_model("mrg");
  explicit Line2d(int n) {
    setup.array = ElectrodeArray::uniform(n, 1.0, 0.5, 10.0);
    setup.conductor.model = "line2d";
    conductor = make_conductor(setup.conductor, setup.array);
  }
  ReceptorThreshold operator()(const std::vector<double>& w, std::size_t k,
                               const ThresholdSettings& s) const {
    return receptor_threshold(*mrg, setup, *conductor, w, setup.receptors[k],
                              pulse_waveform(200, 0, 200, true), s);
  }
};
}  // namespace

TEST_CASE("a mirrored pattern finds the mirrored afferent", "[fibre][afferent]") {
  // Three pads: a pattern and its mirror image give the same threshold, with the stem on
  // the other side; the straight fibre differs from both.
  const Line2d line(3);
  REQUIRE(line.setup.receptors[0].name == "RA");
  ThresholdSettings s;
  s.tolerance = 0.01;
  s.geometry = Geometry::afferent;
  const auto a = line({-1, 0.2, 0}, 0, s);
  const auto b = line({0, 0.2, -1}, 0, s);
  REQUIRE(a.threshold_mA);
  REQUIRE(b.threshold_mA);
  CHECK(*a.threshold_mA == Approx(*b.threshold_mA).epsilon(1e-12));
  CHECK(a.direction != 0);
  CHECK(a.direction == -b.direction);
  CHECK(a.x_mm == Approx(-b.x_mm).margin(1e-9));
  s.geometry = Geometry::straight;
  const auto c = line({-1, 0.2, 0}, 0, s);
  REQUIRE(c.threshold_mA);
  CHECK(std::fabs(*c.threshold_mA / *a.threshold_mA - 1) > 0.05);
}

TEST_CASE("a fibre that fires at a cut end is marked", "[fibre][cut]") {
  // One pad of the paper's array: a cathode excites SAI's horizontal fibre under the pad;
  // an anode only where its field is felt at the fibre's far ends, cut five internodes
  // beyond the margin (docs/fibres.md, "Cut ends").  A longer fibre moves that end, and the
  // anodic threshold with it; the cathodic one stays.
  // The fibre as asked (lengthen off): the search reports the cut end.
  Line2d line(8);
  REQUIRE(line.setup.receptors[1].name == "SAI");
  ThresholdSettings s;
  s.offsets = 2;
  s.tolerance = 0.01;
  s.lengthen = false;
  const std::vector<double> cathode{0, 0, 0, 1, 0, 0, 0, 0}, anode{0, 0, 0, -1, 0, 0, 0, 0};
  const auto c = line(cathode, 1, s);
  const auto a = line(anode, 1, s);
  REQUIRE(c.threshold_mA);
  REQUIRE(a.threshold_mA);
  CHECK_FALSE(c.at_cut_end);
  CHECK(a.at_cut_end);
  CHECK(std::fabs(a.x_mm + 0.5) > line.setup.lateral_margin_mm);
  line.setup.lateral_margin_mm = 10.0;
  const auto c2 = line(cathode, 1, s);
  const auto a2 = line(anode, 1, s);
  REQUIRE(c2.threshold_mA);
  REQUIRE(a2.threshold_mA);
  CHECK(*c2.threshold_mA == Approx(*c.threshold_mA).epsilon(0.011));
  CHECK(std::fabs(*a2.threshold_mA / *a.threshold_mA - 1) > 0.02);
  // RA's straight vertical fibre: a cathode fires its terminal, which is no cut; an anode
  // its deep end, ten internodes below the receptor, which is.
  const auto rc = line(cathode, 0, s);
  const auto ra = line(anode, 0, s);
  REQUIRE(rc.threshold_mA);
  REQUIRE(ra.threshold_mA);
  CHECK(rc.node == 0);
  CHECK_FALSE(rc.at_cut_end);
  CHECK(ra.at_cut_end);
  CHECK(ra.depth_mm > line.setup.receptors[0].depth_max_mm);
}

TEST_CASE("a fibre made too short is lengthened until it fires inside", "[fibre][cut]") {
  // One anodic pad of the paper's array fires SAI's horizontal fibre and RA's straight
  // vertical one at their cut ends (above).  Cut at a quarter of the default extension
  // beyond the pads, each is doubled where it fired and searched again until the action
  // potential starts inside (docs/fibres.md, "Cut ends"): at_cut_end false, a reach beyond
  // the one asked, and a threshold that doubling the fibre again moves by less than 1 %.
  Line2d line(8);
  ThresholdSettings s;
  s.offsets = 2;
  s.tolerance = 1e-3;
  s.reach = {0.25, 0.25, 0.25};
  const std::vector<double> anode{0, 0, 0, -1, 0, 0, 0, 0};
  for (std::size_t k : {std::size_t{0}, std::size_t{1}}) {
    INFO("receptor " << line.setup.receptors[k].name);
    ThresholdSettings as_asked = s;
    as_asked.lengthen = false;
    const auto short_cut = line(anode, k, as_asked);
    REQUIRE(short_cut.threshold_mA);
    CHECK(short_cut.at_cut_end);
    CHECK(short_cut.searches == 1);
    const auto t = line(anode, k, s);
    REQUIRE(t.threshold_mA);
    CHECK_FALSE(t.at_cut_end);
    CHECK(t.cut_end_reason.empty());
    CHECK(t.searches > 2);
    CHECK(std::max({t.reach.minus_x, t.reach.plus_x, t.reach.below}) >= 2.0);
    CHECK(*t.threshold_mA > 1.5 * *short_cut.threshold_mA);
    ThresholdSettings doubled = s;
    doubled.lengthen = false;
    doubled.reach = {2 * t.reach.minus_x, 2 * t.reach.plus_x, 2 * t.reach.below};
    const auto d = line(anode, k, doubled);
    REQUIRE(d.threshold_mA);
    CHECK_FALSE(d.at_cut_end);
    CHECK(std::fabs(*d.threshold_mA / *t.threshold_mA - 1) < 0.01);
  }
  // A straight vertical fibre with no internodes below its receptor cannot be lengthened:
  // it keeps at_cut_end and says why.
  ThresholdSettings none = s;
  none.extra_internodes = 0;
  none.reach = {};
  const auto ra = line(anode, 0, none);
  REQUIRE(ra.threshold_mA);
  CHECK(ra.at_cut_end);
  CHECK_THAT(ra.cut_end_reason, Catch::Matchers::Contains("cannot be moved"));
}
