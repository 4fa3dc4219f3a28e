// The gamut's nearest intensities by the cube's faces (gamut.hpp).

#include "render/gamut.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace tp {

namespace {

constexpr int kAtZero = 0, kAtOne = 1, kFree = 2;

// The predicted colour of intensities x, and its distance to the request.
GamutAnswer answer_of(const GamutColours& c, const Rgb& requested,
                      const std::array<double, kGamutModes>& x) {
  GamutAnswer a;
  a.intensity = x;
  double sq = 0;
  for (std::size_t k = 0; k < kGamutClasses; ++k) {
    for (std::size_t m = 0; m < kGamutModes; ++m) a.predicted[k] += x[m] * c[m][k];
    sq += (a.predicted[k] - requested[k]) * (a.predicted[k] - requested[k]);
  }
  a.error = std::sqrt(sq);
  return a;
}

// The least-squares intensities of the free modes with the others held at 0 or 1; false
// when they leave [0, 1] (the face's optimum is not feasible: another face holds it).
bool solve_face(const GamutColours& c, const Rgb& requested, const std::array<int, kGamutModes>& s,
                std::array<double, kGamutModes>& x) {
  Eigen::Vector3d r(requested[0], requested[1], requested[2]);
  Eigen::Matrix3d a;
  int free = 0;
  for (std::size_t m = 0; m < kGamutModes; ++m) {
    x[m] = s[m] == kAtOne ? 1.0 : 0.0;
    const Eigen::Vector3d col(c[m][0], c[m][1], c[m][2]);
    if (s[m] == kAtOne) r -= col;
    if (s[m] == kFree) a.col(free++) = col;
  }
  if (free == 0) return true;
  const Eigen::MatrixXd af = a.leftCols(free);
  // Least squares by a rank-revealing QR: a face whose colours are dependent has many
  // optima, and the least-norm one of them is as near as any.
  const Eigen::VectorXd z = af.completeOrthogonalDecomposition().solve(r);
  int k = 0;
  for (std::size_t m = 0; m < kGamutModes; ++m) {
    if (s[m] != kFree) continue;
    const double v = z(k++);
    if (!(v >= -1e-12 && v <= 1 + 1e-12)) return false;
    x[m] = std::fmin(1.0, std::fmax(0.0, v));
  }
  return true;
}

}  // namespace

GamutAnswer nearest_in_gamut(const GamutColours& colours, const Rgb& requested) {
  GamutAnswer best;
  bool found = false;
  // Every face of the cube: each mode at 0, at 1 or free (base-3 digits).
  for (int f = 0; f < 27; ++f) {
    const std::array<int, kGamutModes> s{f % 3, (f / 3) % 3, (f / 9) % 3};
    std::array<double, kGamutModes> x{};
    if (!solve_face(colours, requested, s, x)) continue;
    const GamutAnswer a = answer_of(colours, requested, x);
    if (!found || a.error < best.error - 1e-15) {
      best = a;
      found = true;
    }
  }
  return best;  // the vertex x = 0 is always feasible, so some face was
}

}  // namespace tp
