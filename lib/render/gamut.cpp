// The gamut's nearest intensities by the sets of modes on and the faces of their cube
// (gamut.hpp).

#include "render/gamut.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace tp {

namespace {

constexpr int kAtZero = 0, kAtOne = 1, kFree = 2;

GamutAnswer answer_of(const GamutModes& modes, const Rgb& requested,
                      const std::array<double, kGamutModes>& x) {
  GamutAnswer a;
  a.intensity = x;
  a.predicted = predicted_colour(modes, x);
  double sq = 0;
  for (std::size_t k = 0; k < kGamutClasses; ++k)
    sq += (a.predicted[k] - requested[k]) * (a.predicted[k] - requested[k]);
  a.error = std::sqrt(sq);
  return a;
}

// The least-squares intensities of the free modes, the modes on (bit m of `on`) at their
// onset plus their slope times the intensity, the others at their face's 0 or 1; false when
// the free ones leave [0, 1] (another face holds the optimum).  x: 0 off, else on.
bool solve_face(const GamutModes& modes, const Rgb& requested, unsigned on,
                const std::array<int, kGamutModes>& s, std::array<double, kGamutModes>& x) {
  Eigen::Vector3d r(requested[0], requested[1], requested[2]);
  Eigen::Matrix3d a;
  int free = 0;
  for (std::size_t m = 0; m < kGamutModes; ++m) {
    x[m] = 0.0;
    if (!(on >> m & 1u)) continue;
    const Eigen::Vector3d onset(modes.onset[m][0], modes.onset[m][1], modes.onset[m][2]);
    const Eigen::Vector3d full(modes.full[m][0], modes.full[m][1], modes.full[m][2]);
    r -= onset;
    if (s[m] == kAtOne) r -= full - onset;
    if (s[m] == kFree) a.col(free++) = full - onset;
    x[m] = s[m] == kAtOne ? 1.0 : kLeastOn;
  }
  if (free == 0) return true;
  const Eigen::MatrixXd af = a.leftCols(free);
  // Least squares by a rank-revealing QR: a face whose slopes are dependent has many optima,
  // and the least-norm one of them is as near as any.
  const Eigen::VectorXd z = af.completeOrthogonalDecomposition().solve(r);
  int k = 0;
  for (std::size_t m = 0; m < kGamutModes; ++m) {
    if (!(on >> m & 1u) || s[m] != kFree) continue;
    const double v = z(k++);
    if (!(v >= -1e-12 && v <= 1 + 1e-12)) return false;
    x[m] = std::fmin(1.0, std::fmax(kLeastOn, v));
  }
  return true;
}

}  // namespace

Rgb predicted_colour(const GamutModes& modes, const std::array<double, kGamutModes>& intensity) {
  Rgb p{};
  for (std::size_t m = 0; m < kGamutModes; ++m) {
    if (!(intensity[m] > 0)) continue;
    for (std::size_t k = 0; k < kGamutClasses; ++k)
      p[k] += modes.onset[m][k] + intensity[m] * (modes.full[m][k] - modes.onset[m][k]);
  }
  return p;
}

GamutAnswer nearest_in_gamut(const GamutModes& modes, const Rgb& requested) {
  GamutAnswer best = answer_of(modes, requested, {0, 0, 0});  // every mode off
  // The sets of modes on, subsets before their supersets; within each, every face of the
  // cube of its modes' intensities (base-3 digits, a mode off held at digit 0).
  for (unsigned on = 1; on < (1u << kGamutModes); ++on)
    for (int f = 0; f < 27; ++f) {
      const std::array<int, kGamutModes> s{f % 3, (f / 3) % 3, (f / 9) % 3};
      bool face_of_set = true;
      for (std::size_t m = 0; m < kGamutModes; ++m)
        face_of_set = face_of_set && ((on >> m & 1u) || s[m] == kAtZero);
      std::array<double, kGamutModes> x{};
      if (!face_of_set || !solve_face(modes, requested, on, s, x)) continue;
      const GamutAnswer a = answer_of(modes, requested, x);
      if (a.error < best.error - 1e-15) best = a;
    }
  return best;
}

}  // namespace tp
