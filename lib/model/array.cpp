#include "model/array.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tp {

ElectrodeArray ElectrodeArray::uniform(int count, double pitch_mm, double width_mm,
                                       double length_mm) {
  if (count < 1) bad_input("electrodes: need at least 1, got " + std::to_string(count));
  if (count > 4096) bad_input("electrodes: at most 4096, got " + std::to_string(count));
  if (!(pitch_mm > 0.0) || !std::isfinite(pitch_mm)) bad_input("pitch: must be > 0 mm");
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
  if (positions_mm.size() > 4096) bad_input("array: at most 4096 electrodes");
  for (double x : positions_mm)
    if (!std::isfinite(x)) bad_input("array: non-finite electrode position");
  if (!(width_mm >= 0.0) || !std::isfinite(width_mm)) bad_input("array: width_mm must be >= 0");
  if (!(length_mm > 0.0) || !std::isfinite(length_mm)) bad_input("array: length_mm must be > 0");
  if (pitch_mm && !(*pitch_mm > 0.0)) bad_input("array: pitch_mm must be > 0");
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
