#pragma once
// A horizontally layered half-space: the potential of a point current on its insulated
// surface, by Hankel transform (the building block of the `layered` conductor model).
//
// Layers i = 1..N from the surface down, each of resistivity rho_i (ohm m) and thickness
// h_i (mm); the last is semi-infinite.  A current I (mA, injected) at the surface origin
// sets up, at horizontal distance r and depth y (mm),
//     Phi(r, y) = I / (2 pi) * Integral_0^inf K(lambda, y) J0(lambda r) dlambda     [V]
// with the kernel K built by the layer recursion (docs/model.md):
//   T_N = rho_N,  T_i = rho_i (T_{i+1} + rho_i t_i) / (rho_i + T_{i+1} t_i),  t_i = tanh(lambda
//   h_i) K(lambda, 0) = T_1, and down through each layer (c_i = rho_i / T_{i+1}, s = depth in it)
//   K(s) = K(top) e^{-lambda s} ((1 + c_i) + (1 - c_i) e^{-2 lambda (h_i - s)})
//                               / ((1 + c_i) + (1 - c_i) e^{-2 lambda h_i})
// written with decaying exponentials only, so it is stable for every lambda.  For large
// lambda, K -> C_k e^{-lambda y} in layer k, C_k = rho_1 Prod_{i<k} 2 rho_{i+1} / (rho_i +
// rho_{i+1}): that part is a point source's 1/R in closed form, and only the remainder,
// which decays exponentially in lambda, is integrated numerically.

#include <vector>

namespace tp {

struct Layer {
  double thickness_mm = 0.0;  // ignored for the last (semi-infinite) layer
  double resistivity_ohm_m = 0.0;
};

class LayeredHalfSpace {
 public:
  // At most this many layers (a skin file's range).
  static constexpr std::size_t kMaxLayers = 16;

  // 1 to kMaxLayers layers; every thickness (but the last's) and resistivity > 0 and finite
  // (bad input).
  explicit LayeredHalfSpace(std::vector<Layer> layers);

  const std::vector<Layer>& layers() const { return layers_; }
  // The layer holding depth y (an interface belongs to the layer below it).
  std::size_t layer_of(double y_mm) const;
  // Depth of the top of layer k.
  double top_of(std::size_t k) const { return tops_[k]; }

  // K(lambda, y), ohm m.
  double kernel(double lambda_per_mm, double y_mm) const;
  // K for a source buried at depth d (d = 0: on the surface) and a receiver at depth y,
  // normalised as kernel() (Phi = I / (2 pi) Int K J0(lambda r) dlambda).  Solved directly:
  // in each layer a e^{-lambda (y - top)} + b e^{-lambda (bottom - y)}, plus the source's own
  // (rho_j / 2) e^{-lambda |y - d|} in its layer; the insulated surface, and continuity of
  // the potential and of the normal current at each interface, as a (2N - 1)-square linear
  // system (Eigen LU).  Slower than kernel(); used for reciprocity and buried sources.
  double kernel_between(double lambda_per_mm, double source_depth_mm, double y_mm) const;
  // C_k for the layer holding y: K(lambda, y) e^{lambda y} -> C_k as lambda -> inf.
  double leading(double y_mm) const;
  double leading_of(std::size_t k) const { return leading_[k]; }

  // The remainder K - C_k e^{-lambda y} inside layer k (top t_k, thickness h, s = y - t_k):
  //     alpha e^{-lambda s} + beta e^{-lambda (2 h - s)}      (beta = 0 in the bottom layer)
  // so that, once alpha and beta are known at a lambda, every depth of the layer costs two
  // exponentials.  Both decay with lambda: alpha as e^{-lambda (t_k + 2 h_min)} (h_min the
  // thinnest layer above), beta e^{-2 lambda h} as e^{-lambda (2 t_{k+1} - t_k)}.
  void remainder_coefficients(double lambda_per_mm, std::size_t k, double& alpha,
                              double& beta) const;
  // a(y): the remainder at depth y decays as e^{-lambda a(y)}; a is the distance from the
  // point to the remainder's nearest image, so the remainder is analytic within a(y) of it.
  // Infinite for a single layer (no remainder).
  double remainder_distance(double y_mm) const;
  // The same by layer k's own formula, also at its bottom interface (which belongs to the
  // layer below): a = min(y + 2 h_min above, 2 t_{k+1} - y).
  double remainder_distance_in(std::size_t k, double y_mm) const;
  // True when every layer has the same resistivity: the remainder is zero.
  bool uniform() const;

  // For 1 mA injected at the surface origin, at horizontal offsets (u, w) (r^2 = u^2 + w^2)
  // and depth y > 0: the potential (V) and its second derivatives along u and along y
  // (V/mm^2).  d2/dy2 holds inside a layer (it jumps at an interface).
  struct Response {
    double psi, psi_uu, psi_yy;
  };
  Response point(double u_mm, double w_mm, double y_mm) const;

 private:
  // K at the top of layer k and c_k = rho_k / T_{k+1} (c = 1 in the bottom layer).
  void top_of_layer(double lambda, std::size_t k, double& k_top, double& c) const;

  std::vector<Layer> layers_;
  std::vector<double> tops_;     // depth of each layer's top, mm
  std::vector<double> leading_;  // C_k of each layer
};

}  // namespace tp
