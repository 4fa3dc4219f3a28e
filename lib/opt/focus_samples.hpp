#pragma once
// The focus problem's samples (opt/focus_solver.hpp): points on every receptor's fibres,
// and their rows, the AF per unit z (w = B z, B the zero-sum basis) at each.
//
// A 1-D array's fibre region is sampled row by row (its depths, and along x); a 2-D
// array's box on its faces (the maximum principle, model/field.cpp), a grid's face planes
// on a lattice of its pads (model/lattice.hpp: a PlaneTable), whose points' rows are
// looked up rather than evaluated pad by pad.  The step at depth y is min(0.25, y / 4) mm:
// the AF varies on the scale of the depth.

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "model/field.hpp"
#include "model/lattice.hpp"
#include "opt/focus.hpp"
#include "opt/ldp.hpp"

namespace tp::focus {

inline constexpr double kPi = 3.14159265358979323846;

struct Sample {
  double x, y, z;
  std::size_t receptor;
  int table = -1;  // a PlaneTable's (index into the tables): the sample is its point (a, b)
  int a = 0, b = 0;
};

// A grid's face plane, sampled on a lattice, with the lone pad's responses on it.
struct PlaneTable {
  GridLattice g;
  std::shared_ptr<const PadTable> t;
};

// Sampling step of a face at depth y: the AF varies on the scale of the depth.
inline double step_at(double y) {
  return std::min(0.25, y / 4.0);
}

// f at n + 1 points from a to b, n = ceil((b - a) / step) (at least 1), both ends exact; at
// a alone when b is not above a.  Bad input beyond kMaxSamples points.
template <class F>
void sample_line(double a, double b, double step, F&& f) {
  const double n = std::max(1.0, std::ceil((b - a) / step));
  if (!(n < kMaxSamples)) refuse_sample_count("a fibre region's samples", n);
  const auto k = static_cast<std::size_t>(n);
  if (!(b > a)) {
    f(a);
    return;
  }
  for (std::size_t i = 0; i <= k; ++i)
    f(i == k ? b : a + (b - a) * static_cast<double>(i) / static_cast<double>(k));
}

// The distance from the focus across the skin: along x (a 1-D array), in (x, z) (2-D).
inline double lateral(const FocusOptions& o, bool two_d, double x, double z) {
  return two_d ? std::sqrt((x - o.x_mm) * (x - o.x_mm) + (z - o.z_mm) * (z - o.z_mm))
               : std::fabs(x - o.x_mm);
}

// Receptor r's fibres, sampled, appended to `out` (a grid's planes' tables to `tables`).
// Bad input when out would pass the cap of kMaxProblemEntries entries (samples x pads).
void sample_receptor(const Setup& s, std::size_t r, std::vector<Sample>& out,
                     std::vector<PlaneTable>& tables);

// The rows (AF per unit z, zero-sum basis) of the samples from `first` on, in blocks (the
// pads' responses, then one product with the basis).
Eigen::MatrixXd rows_of(const Setup& s, const Conductor& c, const std::vector<PlaneTable>& tables,
                        const std::vector<Sample>& pts, const Eigen::MatrixXd& basis,
                        std::size_t first = 0);

// The samples' rows (row-major), grown by the rounds with room to spare (reserve_spare).
struct SampleRows {
  std::vector<double> v;
  Eigen::Index n = 0, cols = 0;
  explicit SampleRows(Eigen::Index columns) : cols(columns) {}
  RowBlock all() const { return from(0); }
  RowBlock from(Eigen::Index i) const { return RowBlock(v.data() + i * cols, n - i, cols); }
  void append(const Eigen::MatrixXd& m);
};

// Rows for the samples added since the rows were last extended.
void extend_rows(SampleRows& m, const Setup& s, const Conductor& c,
                 const std::vector<PlaneTable>& tables, const std::vector<Sample>& pts,
                 const Eigen::MatrixXd& basis);

}  // namespace tp::focus
