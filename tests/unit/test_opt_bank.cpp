// A bank's steps (opt/bank.hpp): each focus's window of the grid, the mirrors it admits,
// and a window's weights placed on the whole array, reflected.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/number.hpp"
#include "opt/bank.hpp"
#include "opt/focus.hpp"
#include "opt_support.hpp"

using namespace tp;
using tp::test::grid_4x4;

namespace {

Setup grid_5x4() {
  Setup s;
  s.array = ElectrodeArray::grid_of(5, 4, 2.0, 1.5, 1.0, 1.0);
  s.conductor.model = "rect3d";
  return s;
}

}  // namespace

TEST_CASE("a bank's window: K x K pads around the focus's pad, kept inside the grid",
          "[opt][bank]") {
  // Pad centres: x = -4, -2, 0, 2, 4 (columns), z = -2.25, -0.75, 0.75, 2.25 (rows).
  const Setup s = grid_5x4();
  {
    // The corner pad: the window shifted to start there.
    const BankWindow w = bank_window(s, 3, -4.0, -2.25);
    CHECK(w.sub_grid);
    CHECK(w.c0 == 0);
    CHECK(w.r0 == 0);
    CHECK(w.setup.array.columns == 3);
    CHECK(w.setup.array.rows == 3);
    CHECK(w.wx == Approx(-2.0));
    CHECK(w.wz == Approx(-0.75));
    CHECK(w.ox == 0.0);  // the window's own pads are centred on (0, 0)
    CHECK(w.oz == 0.0);
    CHECK(w.mirror_x);  // 3 x 3 pads, every fibre along x or vertical
    CHECK(w.mirror_z);
  }
  {
    // Near the middle (nearest pad: column 3, row 2): centred on it.
    const BankWindow w = bank_window(s, 3, 1.6, 0.5);
    CHECK(w.c0 == 2);
    CHECK(w.r0 == 1);
    CHECK(w.wx == Approx(2.0));
    CHECK(w.wz == Approx(0.75));
  }
  {
    // The last column and row: shifted back inside.
    const BankWindow w = bank_window(s, 3, 4.0, 2.25);
    CHECK(w.c0 == 2);
    CHECK(w.r0 == 1);
  }
  {
    // K beyond the grid: the whole grid, rows as many as it has.
    const BankWindow w = bank_window(s, 7, 4.0, 2.25);
    CHECK(w.c0 == 0);
    CHECK(w.r0 == 0);
    CHECK(w.setup.array.columns == 5);
    CHECK(w.setup.array.rows == 4);
    CHECK(w.wx == Approx(0.0).margin(1e-12));
    CHECK(w.wz == Approx(0.0).margin(1e-12));
  }
  {
    // No neighbourhood: the array itself, its centre its own coordinates' too.
    const BankWindow w = bank_window(s, 0, 4.0, 2.25);
    CHECK_FALSE(w.sub_grid);
    CHECK(w.setup.array.size() == 20);
    CHECK(w.wx == w.ox);
    CHECK(w.wz == w.oz);
    CHECK(w.mirror_x);
    CHECK(w.mirror_z);
  }
  // Pads that no reflection through their centre maps onto themselves: no mirror.
  Setup free;
  free.array = ElectrodeArray::pads({0.0, 1.0, 3.0}, {0.0, 0.0, 1.0}, 0.5, 0.5);
  free.conductor.model = "point3d";
  const BankWindow w = bank_window(free, 0, 0.0, 0.0);
  CHECK_FALSE(w.mirror_x);
  CHECK_FALSE(w.mirror_z);
}

TEST_CASE("a bank's window weights on the array: placed, reflected, zero elsewhere",
          "[opt][bank]") {
  const Setup s = grid_5x4();
  const BankWindow w = bank_window(s, 3, 1.6, 0.5);  // columns 2-4, rows 1-3
  REQUIRE(w.c0 == 2);
  REQUIRE(w.r0 == 1);
  std::vector<double> ww(9);
  for (std::size_t j = 0; j < 9; ++j) ww[j] = static_cast<double>(j + 1);
  auto pad = [](int c, int r) { return static_cast<std::size_t>(r * 5 + c); };
  for (const bool mx : {false, true})
    for (const bool mz : {false, true}) {
      const std::vector<double> a = weights_on_array(s.array, w, mx, mz, ww);
      REQUIRE(a.size() == 20);
      double total = 0.0;
      for (double v : a) total += v;
      CHECK(total == 45.0);  // every window weight once
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          // Window pad (c, r) carries to (c, r) reflected through the window's centre.
          const int tc = mx ? 2 - c : c, tr = mz ? 2 - r : r;
          INFO("mirror " << mx << mz << ", window pad " << c << ", " << r);
          CHECK(a[pad(w.c0 + tc, w.r0 + tr)] == ww[static_cast<std::size_t>(r * 3 + c)]);
        }
      for (int c = 0; c < 2; ++c)
        for (int r = 0; r < 4; ++r) CHECK(a[pad(c, r)] == 0.0);
      for (int c = 0; c < 5; ++c) CHECK(a[pad(c, 0)] == 0.0);
    }
  // The whole array (no neighbourhood): the weights as they are.
  const BankWindow whole = bank_window(s, 0, 0.0, 0.0);
  std::vector<double> all(20);
  for (std::size_t j = 0; j < 20; ++j) all[j] = static_cast<double>(j);
  CHECK(weights_on_array(s.array, whole, false, false, all) == all);
}

TEST_CASE("a bank: derived patterns equal the ones solved directly, translation", "[focus]") {
  const Setup s = grid_4x4();
  BankOptions b;
  b.modes = {"SAI"};
  b.threads = 2;
  const Bank bank = optimize_bank(s, b);
  REQUIRE(bank.patterns.size() == 16);
  CHECK(bank.solves == 4);  // one quadrant: the others are its mirror images
  // A derived pattern (pad 15, the mirror in x and z of pad 0) against its own solve.
  const BankPattern& p = bank.patterns[15];
  REQUIRE(!p.solved);
  CHECK(p.mirror_x);
  CHECK(p.mirror_z);
  FocusOptions o;
  o.x_mm = 3.0;
  o.z_mm = 3.0;
  const FocusResult direct = optimize_focus(s, "SAI", o);
  for (std::size_t i = 0; i < 16; ++i)
    CHECK(std::fabs(direct.weights[i] - p.result.weights[i]) < 1e-6);
  CHECK(p.result.ratio == Approx(direct.ratio).epsilon(1e-6));
  CHECK(p.result.bounds_hold);

  // A neighbourhood of 3 on a 7 x 5 grid: the interior pixels share one pattern, moved by
  // whole pitches: pad (2, 2)'s weights shifted one column are pad (3, 2)'s, exactly.
  Setup t = s;
  t.array = ElectrodeArray::grid_of(7, 5, 2.0, 2.0, 1.0, 1.0);
  BankOptions n = b;
  n.neighbourhood = 3;
  n.at = {{-2.0, 0.0}, {0.0, 0.0}, {2.0, 0.0}};  // columns 2, 3, 4 of row 2
  const Bank tb = optimize_bank(t, n);
  REQUIRE(tb.patterns.size() == 3);
  CHECK(tb.solves == 1);
  for (const BankPattern& q : tb.patterns) REQUIRE(q.feasible);
  for (std::size_t k = 0; k + 1 < 3; ++k) {
    const auto& w0 = tb.patterns[k].result.weights;
    const auto& w1 = tb.patterns[k + 1].result.weights;
    for (int row = 0; row < 5; ++row)
      for (int col = 0; col + 1 < 7; ++col)
        CHECK(w1[static_cast<std::size_t>(row * 7 + col + 1)] ==
              w0[static_cast<std::size_t>(row * 7 + col)]);
    int used = 0;
    for (double w : w1) used += w != 0.0;
    CHECK(used <= 9);
    CHECK(tb.patterns[k].result.bounds_hold);
  }
}

TEST_CASE("a bank: a problem first met mirrored, threads, and the failures' places", "[focus]") {
  const Setup s = grid_4x4();
  BankOptions b;
  b.modes = {"SAI"};
  b.at = {{3.0, 3.0}, {-3.0, -3.0}};  // the first is solved as its mirror image
  b.threads = 1;
  const Bank bank = optimize_bank(s, b);
  REQUIRE(bank.patterns.size() == 2);
  CHECK(bank.solves == 1);
  FocusOptions o;
  o.x_mm = 3.0;
  o.z_mm = 3.0;
  const FocusResult direct = optimize_focus(s, "SAI", o);
  const BankPattern& p = bank.patterns[0];
  REQUIRE(p.feasible);
  CHECK(p.solved);
  for (std::size_t i = 0; i < 16; ++i)
    CHECK(std::fabs(direct.weights[i] - p.result.weights[i]) < 1e-6);
  const Peak& peak = p.result.summary.peaks[receptor_index(s, "SAI")].second;
  CHECK(std::hypot(peak.x_mm - 3.0, peak.z_mm - 3.0) < 0.5);
  CHECK(p.result.bounds_hold);

  // The same bank on 1 and on 3 threads: the same numbers.
  Setup g = s;
  g.array = ElectrodeArray::grid_of(3, 3, 2.0, 2.0, 1.0, 1.0);
  BankOptions all;
  all.modes = {"SAI", "PC"};
  all.threads = 1;
  const Bank one = optimize_bank(g, all);
  all.threads = 3;
  const Bank three = optimize_bank(g, all);
  REQUIRE(one.patterns.size() == three.patterns.size());
  for (std::size_t i = 0; i < one.patterns.size(); ++i) {
    CHECK(one.patterns[i].feasible == three.patterns[i].feasible);
    CHECK(one.patterns[i].reason == three.patterns[i].reason);
    CHECK(one.patterns[i].result.weights == three.patterns[i].result.weights);
    CHECK(one.patterns[i].result.ratio == three.patterns[i].result.ratio);
  }
  // A pixel without a pattern is named by its own place, not its problem's (PC's corners
  // have none: 4, solved once).
  int without = 0;
  for (const BankPattern& q : one.patterns) {
    if (q.feasible) continue;
    ++without;
    const auto [x, z] = one.pixels[q.pixel];
    const std::string at = "(" + number_text(x) + ", " + number_text(z) + ") mm";
    INFO(q.reason);
    CHECK(q.reason.find(at) != std::string::npos);
  }
  CHECK(without == 4);
}
