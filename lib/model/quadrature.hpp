#pragma once
// Gauss-Legendre rules and Chebyshev interpolation, for the layered model's Hankel integrals
// and tables (model/layered.cpp, model/layered_rect.cpp).

#include <array>
#include <cmath>

namespace tp {

inline constexpr double kQuadPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre recurrence).
template <int N>
struct GaussLegendre {
  std::array<double, N> x{}, w{};
  GaussLegendre() {
    for (int i = 0; i < (N + 1) / 2; ++i) {
      double z = std::cos(kQuadPi * (i + 0.75) / (N + 0.5));
      double dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = 0.0;
        for (int j = 1; j <= N; ++j) {
          const double p2 = p1;
          p1 = p0;
          p0 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p2) / j;
        }
        dp = N * (z * p0 - p1) / (z * z - 1.0);
        const double dz = p0 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-16) break;
      }
      x[static_cast<std::size_t>(i)] = -z;
      x[static_cast<std::size_t>(N - 1 - i)] = z;
      w[static_cast<std::size_t>(i)] = w[static_cast<std::size_t>(N - 1 - i)] =
          2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

// Chebyshev interpolation of degree N - 1 on [-1, 1] at the first-kind nodes
// t_j = cos(pi (j + 1/2) / N): the coefficients by the discrete cosine transform, values by
// Clenshaw's recurrence.  For a function analytic inside the Bernstein ellipse of parameter
// rho the error falls as rho^-N.
template <int N>
struct Chebyshev {
  std::array<double, N> t{};
  std::array<std::array<double, N>, N> cosines{};  // cos(pi m (j + 1/2) / N)
  Chebyshev() {
    for (int j = 0; j < N; ++j) t[static_cast<std::size_t>(j)] = std::cos(kQuadPi * (j + 0.5) / N);
    for (int m = 0; m < N; ++m)
      for (int j = 0; j < N; ++j)
        cosines[static_cast<std::size_t>(m)][static_cast<std::size_t>(j)] =
            std::cos(kQuadPi * m * (j + 0.5) / N);
  }
  // Coefficients c[m * stride] from values f[j * stride] at the nodes t_j.
  void fit(const double* f, double* c, std::size_t stride = 1) const {
    for (std::size_t m = 0; m < static_cast<std::size_t>(N); ++m) {
      double s = 0.0;
      for (std::size_t j = 0; j < static_cast<std::size_t>(N); ++j)
        s += f[j * stride] * cosines[m][j];
      c[m * stride] = (m == 0 ? 1.0 : 2.0) * s / N;
    }
  }
  static double eval(const double* c, double x, std::size_t stride = 1) {
    double b1 = 0.0, b2 = 0.0;
    const double x2 = 2.0 * x;
    for (std::size_t m = static_cast<std::size_t>(N) - 1; m > 0; --m) {
      const double b0 = c[m * stride] + x2 * b1 - b2;
      b2 = b1;
      b1 = b0;
    }
    return c[0] + x * b1 - b2;
  }
};

}  // namespace tp
