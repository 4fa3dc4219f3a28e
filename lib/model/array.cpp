#include "model/array.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "io/number.hpp"
#include "model/ranges.hpp"

namespace tp {

ElectrodeArray ElectrodeArray::uniform(int count, double pitch_mm, double width_mm,
                                       double length_mm) {
  if (count < 1 || count > ranges::max_electrodes)
    bad_input("electrodes: " + std::to_string(count) + " outside [1, " +
              std::to_string(ranges::max_electrodes) + "]");
  ranges::check(pitch_mm, ranges::pitch_mm, "pitch");
  ElectrodeArray a;
  a.width_mm = width_mm;
  a.length_mm = length_mm;
  a.pitch_mm = pitch_mm;
  a.positions_mm.resize(static_cast<std::size_t>(count));
  const double centre = 0.5 * (count - 1);
  for (int i = 0; i < count; ++i)
    a.positions_mm[static_cast<std::size_t>(i)] = (i - centre) * pitch_mm;
  a.validate();
  return a;
}

void ElectrodeArray::validate() const {
  if (positions_mm.empty()) bad_input("array: no electrodes");
  if (positions_mm.size() > static_cast<std::size_t>(ranges::max_electrodes))
    bad_input("array: " + std::to_string(positions_mm.size()) + " electrodes, at most " +
              std::to_string(ranges::max_electrodes));
  for (std::size_t i = 0; i < positions_mm.size(); ++i)
    ranges::check(positions_mm[i], ranges::position_mm,
                  "array.positions_mm[" + std::to_string(i) + "]");
  ranges::check(width_mm, ranges::width_mm, "array.width_mm");
  ranges::check(length_mm, ranges::length_mm, "array.length_mm");
  if (pitch_mm) {
    ranges::check(*pitch_mm, ranges::pitch_mm, "array.pitch_mm");
    // A pitch and positions must agree: consecutive centres one pitch apart.
    for (std::size_t i = 1; i < positions_mm.size(); ++i) {
      const double gap = positions_mm[i] - positions_mm[i - 1];
      if (std::fabs(gap - *pitch_mm) > 1e-9 * std::max(1.0, *pitch_mm))
        bad_input("array: positions_mm[" + std::to_string(i - 1) + "] and [" + std::to_string(i) +
                  "] are " + number_text(gap) + " mm apart, not pitch_mm " +
                  number_text(*pitch_mm) + " mm");
    }
  }
  std::vector<double> sorted = positions_mm;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i] - sorted[i - 1] < width_mm || sorted[i] == sorted[i - 1])
      bad_input("array: electrodes overlap (centres closer than their width)");
}

double ElectrodeArray::x_min_mm() const {
  return *std::min_element(positions_mm.begin(), positions_mm.end());
}
double ElectrodeArray::x_max_mm() const {
  return *std::max_element(positions_mm.begin(), positions_mm.end());
}

}  // namespace tp
