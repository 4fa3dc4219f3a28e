// What the focus's and the bank's unit tests share.
#pragma once

#include "model/field.hpp"

namespace tp::test {

// A 4 x 4 grid of 1 x 1 mm pads at 2 mm under rect3d, fibres 2 mm beyond the pads.
inline Setup grid_4x4() {
  Setup s;
  s.array = ElectrodeArray::grid_of(4, 4, 2.0, 2.0, 1.0, 1.0);
  s.conductor.model = "rect3d";
  s.lateral_margin_mm = 2.0;
  return s;
}

}  // namespace tp::test
