// Focal patterns (issue 21, items 3 and 4): every pattern checked by the test's own
// evaluation of the field on a fine grid (the peak's place, the spill bound, the ratio), and
// symmetric foci giving symmetric weights.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "model/field.hpp"
#include "opt/focus.hpp"
#include "opt_support.hpp"

using namespace tp;
using tp::test::grid_4x4;

namespace {

struct Check {
  double peak_af, peak_x, peak_z, spill, ratio;
};

// The test's own evaluation: every receptor's AF on a grid `h` apart over its fibres (the
// depths of its region every h too), the target's peak, its largest AF beyond the radius
// over that peak, and the mode's ratio.
Check independent(const Setup& s, const std::vector<double>& currents, std::size_t target,
                  const FocusOptions& o, double radius, double h) {
  const Field f(s, currents);
  const bool two_d = s.array.two_d();
  Check c{-INFINITY, 0, 0, -INFINITY, 0};
  double off = -INFINITY;
  for (std::size_t r = 0; r < s.receptors.size(); ++r) {
    const Receptor& rec = s.receptors[r];
    const Region g = fibre_region(s, rec);
    const double hy =
        g.y1_mm > g.y0_mm ? (g.y1_mm - g.y0_mm) / std::ceil((g.y1_mm - g.y0_mm) / h) : 1;
    for (double y = g.y0_mm; y <= g.y1_mm + 1e-9; y += hy)
      for (double z = g.z0_mm; z <= g.z1_mm + 1e-9; z += (two_d ? h : 1.0))
        for (double x = g.x0_mm; x <= g.x1_mm + 1e-9; x += h) {
          const double v =
              two_d ? f.af_3d(rec.fibre, fibre_axis(rec), x, y, z) : f.af(rec.fibre, x, y);
          if (r != target) {
            off = std::max(off, v);
            continue;
          }
          if (v > c.peak_af) c = {v, x, z, c.spill, 0};
          const double d = two_d ? std::hypot(x - o.x_mm, z - o.z_mm) : std::fabs(x - o.x_mm);
          if (d > radius) c.spill = std::max(c.spill, v);
        }
  }
  c.spill /= c.peak_af;
  c.ratio = off / c.peak_af;
  return c;
}

void confirm(const Setup& s, const std::string& mode, const FocusOptions& o, double h) {
  const FocusResult r = optimize_focus(s, mode, o);
  const std::size_t t = receptor_index(s, mode);
  const Check c = independent(s, r.currents_mA, t, o, r.radius_mm, h);
  INFO(mode << " ratio " << r.ratio << " vs " << c.ratio << ", spill " << r.spill << " vs "
            << c.spill << ", peak at " << c.peak_x << ", " << c.peak_z);
  const double d = s.array.two_d() ? std::hypot(c.peak_x - o.x_mm, c.peak_z - o.z_mm)
                                   : std::fabs(c.peak_x - o.x_mm);
  CHECK(d <= r.pitch_mm / 4 + h);
  CHECK(c.spill <= o.spill * 1.005);
  CHECK(r.spill <= o.spill * 1.005);
  CHECK(std::fabs(c.ratio - r.ratio) <= 0.005 * std::fabs(r.ratio));
  CHECK(std::fabs(c.peak_af - r.target_max_af) <= 0.005 * r.target_max_af);
  double sum = 0, big = 0;
  for (double w : r.weights) {
    sum += w;
    big = std::max(big, std::fabs(w));
  }
  CHECK(std::fabs(sum) < 1e-12);
  CHECK(big == 1.0);
}

// SAI and PC at the centre of a 3 x 3 grid (2 mm, 1 x 1 mm pads) under a model: weights
// symmetric under both mirrors, and the pattern confirmed by the independent fine grid.
void centre_pixel_of_3x3(const char* model) {
  Setup g;
  g.array = ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.0, 1.0);
  g.conductor.model = model;
  g.lateral_margin_mm = 3.0;
  FocusOptions c;
  for (const char* mode : {"SAI", "PC"}) {
    const FocusResult q = optimize_focus(g, mode, c);
    auto w = [&](int row, int col) { return q.weights[static_cast<std::size_t>(row * 3 + col)]; };
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) {
        CHECK(std::fabs(w(row, col) - w(row, 2 - col)) < 1e-6);  // x -> -x
        CHECK(std::fabs(w(row, col) - w(2 - row, col)) < 1e-6);  // z -> -z
      }
    confirm(g, mode, c, 0.05);
  }
}

}  // namespace

TEST_CASE("focal patterns on the paper's array, confirmed by an independent fine grid", "[focus]") {
  Setup s;  // the paper's 8 x 1 mm array, line2d
  FocusOptions o;
  o.x_mm = -0.5;  // under electrode 4
  for (const char* mode : {"RA", "SAI", "PC"}) confirm(s, mode, o, 0.01);
  s.conductor.model = "rect3d";
  for (const char* mode : {"RA", "SAI", "PC"}) confirm(s, mode, o, 0.02);
}

TEST_CASE("a symmetric focus gives symmetric weights (1-D and 2-D)", "[focus]") {
  Setup s;
  FocusOptions o;
  o.x_mm = 0.0;  // the paper's array's centre, between electrodes 4 and 5: PC is feasible
  const FocusResult r = optimize_focus(s, "PC", o);
  for (std::size_t i = 0; i < 8; ++i) CHECK(std::fabs(r.weights[i] - r.weights[7 - i]) < 1e-6);
  // RA and SAI cannot peak between two electrodes 1 mm apart under line2d: a runtime
  // failure naming the least spill reachable.
  for (const char* mode : {"RA", "SAI"}) {
    try {
      optimize_focus(s, mode, o);
      FAIL(mode << " accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::failure);
      CHECK_THAT(e.what(), Catch::Contains("no spill up to 1 is possible"));
    }
  }
  // A ring of samples closed under the mirrors (5 x 5, PC, whose step gave 51 before).
  {
    Setup f;
    f.array = ElectrodeArray::grid_of(5, 5, 2.0, 2.0, 1.0, 1.0);
    f.conductor.model = "rect3d";
    f.lateral_margin_mm = 2.0;
    const FocusResult q = optimize_focus(f, "PC", FocusOptions{});
    for (int row = 0; row < 5; ++row)
      for (int col = 0; col < 5; ++col)
        CHECK(std::fabs(q.weights[static_cast<std::size_t>(row * 5 + col)] -
                        q.weights[static_cast<std::size_t>(row * 5 + 4 - col)]) < 1e-6);
  }
  // The least Sum w^2 does not depend on the AF's scale: a resistivity of 0.01 ohm m (the
  // AF 300 times smaller) gives the same weights.
  {
    Setup f;
    f.conductor.resistivity_ohm_m = 0.01;
    const FocusResult q = optimize_focus(f, "PC", o);
    CHECK(q.least_norm);
    for (std::size_t i = 0; i < 8; ++i) CHECK(std::fabs(q.weights[i] - r.weights[i]) < 1e-6);
  }
  centre_pixel_of_3x3("rect3d");
}

TEST_CASE("a pixel on a layered grid: symmetric, and confirmed by an independent fine grid",
          "[focus][layered][numerics]") {
  centre_pixel_of_3x3("layered");  // the built-in fingertip skin
}

TEST_CASE("a focus is checked before any work", "[focus]") {
  Setup s;
  auto refuses = [&](FocusOptions o) {
    CHECK_THROWS_MATCHES(
        optimize_focus(s, "SAI", o), Error,
        Catch::Predicate<Error>([](const Error& e) { return e.code() == ExitCode::bad_input; }));
  };
  FocusOptions o;
  o.x_mm = 4.6;  // beyond 3.5 + one pitch
  refuses(o);
  o = FocusOptions{};
  o.spill = 0.0;
  refuses(o);
  o.spill = 1.5;
  refuses(o);
  o = FocusOptions{};
  o.radius_mm = -1.0;
  refuses(o);
}

TEST_CASE("a grid of one row gives the 1-D array's pixel when their fibres are the same",
          "[focus]") {
  // The fields are the same (test_model3d); the fibres are when the margin is 0 and every
  // receptor is horizontal (the grid's then lie in the plane z = 0 over the pads' centres,
  // as the 1-D array's; vertical ones would ascend under the pads' whole length). Then
  // both problems are one, sampled differently (the grid's faces on the pads' lattice):
  // the optima agree within the check's tolerance for an off-target lobe (1 %), and each
  // pattern scores the same on the other's fibres.
  for (const char* model : {"rect3d", "layered"}) {
    Setup line, row;
    line.array = ElectrodeArray::paper();
    row.array = ElectrodeArray::grid_of(8, 1, 1.0, 20.0, 0.5, 10.0);
    for (Setup* s : {&line, &row}) {
      s->conductor.model = model;
      s->lateral_margin_mm = 0.0;
      s->receptors = {{"SAI", Fibre{}, 0.9, 0.9}, {"PC", Fibre{}, 2.0, 2.0}};
    }
    // layered: the 1-D and 2-D tables are separate tabulations (agreeing to 1e-9).
    const double same = std::string(model) == "layered" ? 1e-8 : 1e-9;
    for (const char* mode : {"SAI", "PC"}) {
      FocusOptions o;
      o.x_mm = -0.5;  // under electrode 4
      const FocusResult a = optimize_focus(line, mode, o);
      const FocusResult b = optimize_focus(row, mode, o);
      INFO(model << " " << mode << ": 1-D ratio " << a.ratio << ", one row " << b.ratio);
      CHECK(b.ratio == Approx(a.ratio).epsilon(0.01));
      CHECK(a.spill <= o.spill * 1.001);
      CHECK(b.spill <= o.spill * 1.001);
      // Each answer's summary on the other's fibres: the same numbers.
      const FocusResult ab = evaluate_focus(row, mode, o, a.weights);
      const FocusResult ba = evaluate_focus(line, mode, o, b.weights);
      CHECK(ab.ratio == Approx(a.ratio).epsilon(same));
      // (The spill is largest at the radius, where the AF is not flat: found to 1e-7.)
      CHECK(ab.spill == Approx(a.spill).epsilon(1e-7));
      CHECK(ba.ratio == Approx(b.ratio).epsilon(same));
      CHECK(ba.spill == Approx(b.spill).epsilon(1e-7));
    }
  }
}

namespace {

// A 4 x 3 grid (pitches 2 and 1.5 mm, 1 x 0.8 mm pads) under a 3-D model, its fibres
// margin_mm beyond the pads, and a current on every pad, none alike.
struct LatticeCase {
  Setup s;
  std::vector<double> currents;
};
LatticeCase lattice_case(const char* model, double margin_mm) {
  LatticeCase c;
  c.s.array = ElectrodeArray::grid_of(4, 3, 2.0, 1.5, 1.0, 0.8);
  c.s.conductor.model = model;
  c.s.lateral_margin_mm = margin_mm;
  for (std::size_t i = 0; i < c.s.array.size(); ++i)
    c.currents.push_back(std::sin(1.7 * static_cast<double>(i) + 0.3));
  return c;
}
// How closely the lattice's values equal every pad evaluated: to rounding, or under layered
// to its tables' accuracy (docs/model.md: 1e-9; a point on a tile's edge may fall in
// either tile, whose interpolants agree to that, not to rounding).
double lattice_tolerance(const char* model) {
  return std::string(model) == "layered" ? 1e-9 : 1e-12;
}

}  // namespace

TEST_CASE("a grid's plane on the lattice equals every pad evaluated (one pad's table)", "[focus]") {
  // The lattice correlates one pad's tabulated response with the currents (model/
  // lattice.hpp): at every point it must equal the direct sum over the pads.
  for (const char* model : {"rect3d", "point3d", "layered"}) {
    const auto [s, currents] = lattice_case(model, 2.3);  // edges off the lattice
    const Field f(s, currents);
    for (const Receptor& r : s.receptors) {
      const Region g = fibre_region(s, r);
      const GridValues v = f.plane_af(r, g.y0_mm, g.y0_mm / 7);
      REQUIRE(v.s.front() == Approx(g.x0_mm).margin(1e-9));
      REQUIRE(v.s.back() == Approx(g.x1_mm).margin(1e-9));
      REQUIRE(v.t.front() == Approx(g.z0_mm).margin(1e-9));
      REQUIRE(v.t.back() == Approx(g.z1_mm).margin(1e-9));
      double worst = 0, scale = 0;
      for (std::size_t j = 0; j < v.t.size(); ++j)
        for (std::size_t i = 0; i < v.s.size(); ++i) {
          const double d = f.af_3d(r.fibre, fibre_axis(r), v.s[i], g.y0_mm, v.t[j]);
          worst = std::max(worst, std::fabs(d - v.v[j * v.s.size() + i]));
          scale = std::max(scale, std::fabs(d));
        }
      INFO(model << " " << r.name << ": " << v.s.size() << " x " << v.t.size() << " points");
      CHECK(worst <= lattice_tolerance(model) * scale);
    }
  }
}

TEST_CASE("a grid's walls on the lattice equal every pad evaluated (one pad's wall table)",
          "[focus]") {
  // The fibre box's walls (Field::wall_af) correlate a lone pad's response on the wall with
  // the currents: at every point the direct sum over the pads, under each 3-D model.
  for (const char* model : {"rect3d", "point3d", "layered"}) {
    const auto [s, currents] = lattice_case(model, 2.35);  // walls off the lattice
    const Field f(s, currents);
    for (const Receptor& r : s.receptors) {
      const Region g = fibre_region(s, r);
      for (const bool along_x : {true, false})
        for (const double fixed : along_x ? std::vector<double>{g.z0_mm, g.z1_mm}
                                          : std::vector<double>{g.x0_mm, g.x1_mm}) {
          const double step = g.y0_mm / 7;
          const GridValues v = f.wall_af(r, along_x, fixed, step);
          // On the lattice (a pitch a whole number of steps), not the uniform grid.
          const double pitch = along_x ? 2.0 : 1.5;
          REQUIRE(v.hs == Approx(pitch / std::ceil(pitch / step - 1e-9)).epsilon(1e-12));
          bool on_centre = false;  // a pad's centre among the points (-3 or -1.5)
          for (const double x : v.s) on_centre |= std::fabs(x - (along_x ? -3.0 : -1.5)) < 1e-9;
          REQUIRE(on_centre);
          REQUIRE(v.s.front() == Approx(along_x ? g.x0_mm : g.z0_mm).margin(1e-9));
          REQUIRE(v.s.back() == Approx(along_x ? g.x1_mm : g.z1_mm).margin(1e-9));
          REQUIRE(v.t.front() == g.y0_mm);
          REQUIRE(v.t.back() == g.y1_mm);
          REQUIRE(v.v.size() == v.s.size() * v.t.size());
          double worst = 0, scale = 0;
          for (std::size_t j = 0; j < v.t.size(); ++j)
            for (std::size_t i = 0; i < v.s.size(); ++i) {
              const double x = along_x ? v.s[i] : fixed, z = along_x ? fixed : v.s[i];
              const double d = f.af_3d(r.fibre, fibre_axis(r), x, v.t[j], z);
              worst = std::max(worst, std::fabs(d - v.v[j * v.s.size() + i]));
              scale = std::max(scale, std::fabs(d));
            }
          INFO(model << " " << r.name << (along_x ? " z = " : " x = ") << fixed << ": "
                     << v.s.size() << " x " << v.t.size() << " points, worst " << worst / scale);
          CHECK(scale > 0);
          CHECK(worst <= lattice_tolerance(model) * scale);
        }
    }
  }
}

TEST_CASE("a pixel certified: the best over every place its peak may take", "[focus]") {
  // The LP at every target sample within a quarter pitch of the focus: the focus itself is
  // one of them, so the certified optimum is at most the sampled one.
  const Setup s = grid_4x4();
  FocusOptions o;
  o.x_mm = 1.0;
  o.z_mm = -1.0;
  o.certify = true;
  for (const char* mode : {"RA", "SAI", "PC"}) {
    const FocusResult r = optimize_focus(s, mode, o);
    REQUIRE(r.certified_optimum);
    INFO(mode << ": certified " << *r.certified_optimum << " at (" << r.certified_at.x_mm << ", "
              << r.certified_at.z_mm << "), sampled " << r.sampled_optimum);
    CHECK(r.certified_points > 4);
    CHECK(*r.certified_optimum <= r.sampled_optimum * (1 + 1e-9));
    CHECK(std::hypot(r.certified_at.x_mm - o.x_mm, r.certified_at.z_mm - o.z_mm) <=
          r.pitch_mm / 4 + 1e-9);
  }
}

TEST_CASE("a 2-D array's field with pads at zero: the pads that carry current alone", "[focus]") {
  // Field evaluates only the pads with current under a 2-D array: the same as every pad.
  Setup s;
  s.array = ElectrodeArray::grid_of(4, 3, 2.0, 1.5, 1.0, 0.8);
  s.conductor.model = "rect3d";
  std::vector<double> currents(s.array.size(), 0.0);
  currents[1] = 1.5;
  currents[6] = -1.0;
  currents[10] = -0.5;
  const Field f(s, currents);
  const auto c = make_conductor(s.conductor, s.array);
  std::vector<double> k(s.array.size());
  for (const Receptor& r : s.receptors)
    for (const double x : {-4.1, -0.3, 2.2})
      for (const double z : {-1.7, 0.0, 0.9}) {
        c->unit_d2_along(x, 1.1, z, fibre_axis(r), k.data());
        double sum = 0.0;
        for (std::size_t i = 0; i < k.size(); ++i) sum += currents[i] * k[i];
        CHECK(f.af_3d(r.fibre, fibre_axis(r), x, 1.1, z) ==
              Approx(fibre_factor_mm2_per_ms(r.fibre) * sum).epsilon(1e-13));
      }
}
