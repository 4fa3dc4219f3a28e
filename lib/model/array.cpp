#include "model/array.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"

namespace tp {

namespace {

void check_count(double count, const std::string& what) {
  if (!(count >= 1 && count <= ranges::max_line_electrodes))
    bad_input(what + ": " + number_text(count) + " outside [1, " +
              std::to_string(ranges::max_line_electrodes) + "]");
}

}  // namespace

std::string ElectrodeArray::describe() const {
  const std::string n = std::to_string(size());
  if (grid()) {
    // "an" before the numbers spoken with a vowel first (8, 11, 18, 80 to 89).
    const bool an =
        columns == 8 || columns == 11 || columns == 18 || (columns >= 80 && columns <= 89);
    return (an ? "an " : "a ") + std::to_string(columns) + " x " + std::to_string(rows) +
           " grid of pads";
  }
  if (two_d()) return n + (size() == 1 ? " pad" : " pads");
  return n + (size() == 1 ? " electrode" : " electrodes");
}

ElectrodeArray ElectrodeArray::uniform(int count, double pitch_mm, double width_mm,
                                       double length_mm) {
  check_count(count, "electrodes");
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

ElectrodeArray ElectrodeArray::grid_of(int columns, int rows, double pitch_mm, double row_pitch_mm,
                                       double width_mm, double length_mm) {
  if (columns < 1 || columns > ranges::max_grid_side)
    bad_input("array.grid.columns: " + std::to_string(columns) + " outside [1, " +
              std::to_string(ranges::max_grid_side) + "]");
  if (rows < 1 || rows > ranges::max_grid_side)
    bad_input("array.grid.rows: " + std::to_string(rows) + " outside [1, " +
              std::to_string(ranges::max_grid_side) + "]");
  if (columns * rows > ranges::max_electrodes)
    bad_input("array.grid: " + std::to_string(columns) + " x " + std::to_string(rows) + " = " +
              std::to_string(columns * rows) + " pads, at most " +
              std::to_string(ranges::max_electrodes));
  ranges::check(pitch_mm, ranges::pitch_mm, "array.grid.pitch_mm");
  ranges::check(row_pitch_mm, ranges::pitch_mm, "array.grid.row_pitch_mm");
  ElectrodeArray a;
  a.width_mm = width_mm;
  a.length_mm = length_mm;
  a.pitch_mm = pitch_mm;
  a.row_pitch_mm = row_pitch_mm;
  a.columns = columns;
  a.rows = rows;
  const double cx = 0.5 * (columns - 1), cz = 0.5 * (rows - 1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      a.positions_mm.push_back((c - cx) * pitch_mm);
      a.z_mm.push_back((r - cz) * row_pitch_mm);
    }
  a.validate();
  return a;
}

ElectrodeArray ElectrodeArray::pads(std::vector<double> x_mm, std::vector<double> z_mm,
                                    double width_mm, double length_mm) {
  ElectrodeArray a;
  a.positions_mm = std::move(x_mm);
  a.z_mm = std::move(z_mm);
  a.width_mm = width_mm;
  a.length_mm = length_mm;
  a.validate();
  return a;
}

void ElectrodeArray::validate() const {
  const char* what = two_d() ? "pads" : "electrodes";
  if (positions_mm.empty()) bad_input(std::string("array: no ") + what);
  const int most = two_d() ? ranges::max_electrodes : ranges::max_line_electrodes;
  if (positions_mm.size() > static_cast<std::size_t>(most))
    bad_input("array: " + std::to_string(positions_mm.size()) + " " + what + ", at most " +
              std::to_string(most) + (two_d() ? "" : " (a 1-D array; a 2-D array up to 256 pads)"));
  if (two_d() && z_mm.size() != positions_mm.size())
    failure("array: " + std::to_string(z_mm.size()) + " z positions for " +
            std::to_string(positions_mm.size()) + " pads");
  for (std::size_t i = 0; i < positions_mm.size(); ++i) {
    ranges::check(positions_mm[i], ranges::position_mm,
                  (two_d() ? "array.pads[" + std::to_string(i) + "].x_mm"
                           : "array.positions_mm[" + std::to_string(i) + "]"));
    if (two_d())
      ranges::check(z_mm[i], ranges::position_mm, "array.pads[" + std::to_string(i) + "].z_mm");
  }
  ranges::check(width_mm, ranges::width_mm, "array.width_mm");
  ranges::check(length_mm, ranges::length_mm, "array.length_mm");
  if (two_d()) {
    // Rectangles overlap when they are closer than their size along both axes; pads that
    // touch along an edge do not (to 1e-9 relative: a grid's centres are rounded).
    if (!(width_mm > 0.0)) bad_input("array.width_mm: a 2-D array's pads need a width > 0 mm");
    for (std::size_t i = 0; i < size(); ++i)
      for (std::size_t j = i + 1; j < size(); ++j)
        if (std::fabs(positions_mm[i] - positions_mm[j]) < width_mm * (1.0 - 1e-9) &&
            std::fabs(z_mm[i] - z_mm[j]) < length_mm * (1.0 - 1e-9))
          bad_input("array: pads " + std::to_string(i) + " (" + number_text(positions_mm[i]) +
                    ", " + number_text(z_mm[i]) + ") and " + std::to_string(j) + " (" +
                    number_text(positions_mm[j]) + ", " + number_text(z_mm[j]) + ") mm overlap (" +
                    number_text(width_mm) + " x " + number_text(length_mm) + " mm pads)");
    return;
  }
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

std::size_t ElectrodeArray::centre_index() const {
  if (!two_d()) return (size() - 1) / 2;
  const double cx = 0.5 * (x_min_mm() + x_max_mm()), cz = 0.5 * (z_min_mm() + z_max_mm());
  std::size_t best = 0;
  double best_d = INFINITY;
  for (std::size_t i = 0; i < size(); ++i) {
    const double d = std::hypot(positions_mm[i] - cx, z_mm[i] - cz);
    if (d < best_d * (1.0 - 1e-12)) {
      best = i;
      best_d = d;
    }
  }
  return best;
}

double ElectrodeArray::x_min_mm() const {
  return *std::min_element(positions_mm.begin(), positions_mm.end());
}
double ElectrodeArray::x_max_mm() const {
  return *std::max_element(positions_mm.begin(), positions_mm.end());
}
double ElectrodeArray::z_min_mm() const {
  return z_mm.empty() ? 0.0 : *std::min_element(z_mm.begin(), z_mm.end());
}
double ElectrodeArray::z_max_mm() const {
  return z_mm.empty() ? 0.0 : *std::max_element(z_mm.begin(), z_mm.end());
}

}  // namespace tp
