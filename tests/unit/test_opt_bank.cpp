// A bank's steps (opt/bank.hpp): each focus's window of the grid, the mirrors it admits,
// and a window's weights placed on the whole array, reflected.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "opt/bank.hpp"

using namespace tp;

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
