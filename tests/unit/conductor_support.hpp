#pragma once
// Helpers shared by the conductor tests (test_model3d.cpp, test_layered_rect.cpp).

#include "model/conductor.hpp"

namespace tp::test {

// One electrode of the given size, centred on x = 0.
inline ElectrodeArray one_electrode(double width_mm, double length_mm) {
  ElectrodeArray a;
  a.positions_mm = {0.0};
  a.width_mm = width_mm;
  a.length_mm = length_mm;
  return a;
}

// A single-electrode conductor's second derivatives and potential at a point.
struct D2 {
  double xx, yy;
};
inline D2 d2(const Conductor& c, double x, double y) {
  D2 r{};
  c.unit_second_derivatives(x, y, &r.xx, &r.yy);
  return r;
}
inline double psi(const Conductor& c, double x, double y) {
  double p = 0;
  c.unit_potentials(x, y, &p);
  return p;
}

}  // namespace tp::test
