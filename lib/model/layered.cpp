#include "model/layered.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/error.hpp"
#include "core/number.hpp"
#include "model/quadrature.hpp"

namespace tp {
namespace {

constexpr double kPi = 3.14159265358979323846;

const GaussLegendre<16>& gauss16() {
  static const GaussLegendre<16> g;
  return g;
}

// J1(x) / x, 1/2 at 0.
double j1_over_x(double x) {
  return std::fabs(x) < 1e-8 ? 0.5 - x * x / 16.0 : ::j1(x) / x;
}

}  // namespace

LayeredHalfSpace::LayeredHalfSpace(std::vector<Layer> layers) : layers_(std::move(layers)) {
  if (layers_.empty()) bad_input("layers: none given");
  if (layers_.size() > kMaxLayers)
    bad_input("layers: at most " + std::to_string(kMaxLayers) + ", got " +
              std::to_string(layers_.size()));
  double top = 0.0;
  for (std::size_t i = 0; i < layers_.size(); ++i) {
    const std::string where = "layers[" + std::to_string(i) + "]";
    if (!(layers_[i].resistivity_ohm_m > 0.0) || !std::isfinite(layers_[i].resistivity_ohm_m))
      bad_input(where + ".resistivity_ohm_m: must be > 0, got " +
                number_text(layers_[i].resistivity_ohm_m));
    if (i + 1 < layers_.size() &&
        (!(layers_[i].thickness_mm > 0.0) || !std::isfinite(layers_[i].thickness_mm)))
      bad_input(where + ".thickness_mm: must be > 0, got " + number_text(layers_[i].thickness_mm));
    tops_.push_back(top);
    if (i + 1 < layers_.size()) top += layers_[i].thickness_mm;
  }
  double c = layers_[0].resistivity_ohm_m;
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    if (k > 0) {
      const double a = layers_[k - 1].resistivity_ohm_m, b = layers_[k].resistivity_ohm_m;
      c *= 2.0 * b / (a + b);
    }
    leading_.push_back(c);
  }
}

std::size_t LayeredHalfSpace::layer_of(double y_mm) const {
  std::size_t k = 0;
  while (k + 1 < layers_.size() && y_mm >= tops_[k + 1]) ++k;
  return k;
}

bool LayeredHalfSpace::uniform() const {
  for (const Layer& l : layers_)
    if (l.resistivity_ohm_m != layers_[0].resistivity_ohm_m) return false;
  return true;
}

void LayeredHalfSpace::top_of_layer(double lambda, std::size_t k, double& k_top, double& c) const {
  const std::size_t n = layers_.size();
  // T from the bottom up (Koefoed's resistivity transform).
  std::array<double, kMaxLayers> t{};
  t[n - 1] = layers_[n - 1].resistivity_ohm_m;
  for (std::size_t i = n - 1; i-- > 0;) {
    const double rho = layers_[i].resistivity_ohm_m;
    const double th = std::tanh(lambda * layers_[i].thickness_mm);
    t[i] = rho * (t[i + 1] + rho * th) / (rho + t[i + 1] * th);
  }
  k_top = t[0];
  for (std::size_t i = 0; i < k; ++i) {  // through each whole layer above the point
    const double h = layers_[i].thickness_mm;
    const double ci = layers_[i].resistivity_ohm_m / t[i + 1];
    const double e2 = std::exp(-2.0 * lambda * h);
    k_top *= 2.0 * std::exp(-lambda * h) / ((1.0 + ci) + (1.0 - ci) * e2);
  }
  c = k + 1 == n ? 1.0 : layers_[k].resistivity_ohm_m / t[k + 1];
}

void LayeredHalfSpace::remainder_coefficients(double lambda, std::size_t k, double& alpha,
                                              double& beta) const {
  double k_top = 0.0, c = 1.0;
  top_of_layer(lambda, k, k_top, c);
  const double lead = leading_[k] * std::exp(-lambda * tops_[k]);
  if (k + 1 == layers_.size()) {
    alpha = k_top - lead;
    beta = 0.0;
    return;
  }
  const double h = layers_[k].thickness_mm;
  const double d = (1.0 + c) + (1.0 - c) * std::exp(-2.0 * lambda * h);
  alpha = k_top * (1.0 + c) / d - lead;
  beta = k_top * (1.0 - c) / d;
}

double LayeredHalfSpace::kernel(double lambda, double y_mm) const {
  const std::size_t k = layer_of(y_mm);
  double alpha = 0.0, beta = 0.0;
  remainder_coefficients(lambda, k, alpha, beta);
  const double s = y_mm - tops_[k];
  double v = leading_[k] * std::exp(-lambda * y_mm) + alpha * std::exp(-lambda * s);
  if (beta != 0.0) v += beta * std::exp(-lambda * (2.0 * layers_[k].thickness_mm - s));
  return v;
}

double LayeredHalfSpace::kernel_between(double lambda, double d, double y) const {
  const std::size_t n = layers_.size();
  const std::size_t j = layer_of(d);
  const double rho_j = layers_[j].resistivity_ohm_m;
  // The source's own term and its derivative / lambda at depth t (above the source when
  // t <= d: d = 0 is a surface source, just below the surface).
  auto prim = [&](double t) { return 0.5 * rho_j * std::exp(-lambda * std::fabs(t - d)); };
  auto prim_d = [&](double t) { return (t <= d ? 1.0 : -1.0) * prim(t); };
  // Unknowns: a_k (k = 0..n-1) at 2k, b_k (k = 0..n-2) at 2k+1.
  const auto m = static_cast<Eigen::Index>(2 * n - 1);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  auto ia = [](std::size_t k) { return static_cast<Eigen::Index>(2 * k); };
  auto ib = [](std::size_t k) { return static_cast<Eigen::Index>(2 * k + 1); };
  auto e = [&](std::size_t k) { return std::exp(-lambda * layers_[k].thickness_mm); };
  // Surface: dPhi/dy = 0 at y = 0 (top of layer 0).
  Eigen::Index row = 0;
  a(row, ia(0)) = -1.0;
  if (n > 1) a(row, ib(0)) = e(0);
  if (j == 0) rhs(row) = -prim_d(0.0);
  ++row;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double t = tops_[k + 1];
    const double src_above = j == k ? 1.0 : 0.0, src_below = j == k + 1 ? 1.0 : 0.0;
    // Potential: Phi_k(t) = Phi_{k+1}(t).
    a(row, ia(k)) = e(k);
    a(row, ib(k)) = 1.0;
    a(row, ia(k + 1)) = -1.0;
    if (k + 2 < n) a(row, ib(k + 1)) = -e(k + 1);
    rhs(row) = (src_below - src_above) * prim(t);
    ++row;
    // Normal current: (1 / rho_k) dPhi_k/dy = (1 / rho_{k+1}) dPhi_{k+1}/dy.
    const double gk = 1.0 / layers_[k].resistivity_ohm_m;
    const double g1 = 1.0 / layers_[k + 1].resistivity_ohm_m;
    a(row, ia(k)) = -gk * e(k);
    a(row, ib(k)) = gk;
    a(row, ia(k + 1)) = g1;
    if (k + 2 < n) a(row, ib(k + 1)) = -g1 * e(k + 1);
    rhs(row) = g1 * src_below * prim_d(t) - gk * src_above * prim_d(t);
    ++row;
  }
  const Eigen::VectorXd x = a.partialPivLu().solve(rhs);
  const std::size_t k = layer_of(y);
  double v = x(ia(k)) * std::exp(-lambda * (y - tops_[k]));
  if (k + 1 < n) v += x(ib(k)) * std::exp(-lambda * (tops_[k + 1] - y));
  if (k == j) v += prim(y);
  return v;
}

double LayeredHalfSpace::leading(double y_mm) const {
  return leading_[layer_of(y_mm)];
}

double LayeredHalfSpace::remainder_distance(double y_mm) const {
  return remainder_distance_in(layer_of(y_mm), y_mm);
}

double LayeredHalfSpace::remainder_distance_in(std::size_t k, double y_mm) const {
  double d = INFINITY;
  for (std::size_t i = 0; i < k; ++i) d = std::min(d, layers_[i].thickness_mm);
  double a = y_mm + 2.0 * d;
  if (k + 1 < layers_.size()) a = std::min(a, 2.0 * tops_[k + 1] - y_mm);
  return a;
}

LayeredHalfSpace::Response LayeredHalfSpace::point(double u_mm, double w_mm, double y_mm) const {
  if (!(y_mm > 0.0)) bad_input("layered: depth must be > 0 mm, got " + number_text(y_mm));
  const double r2 = u_mm * u_mm + w_mm * w_mm;
  const double r = std::sqrt(r2);
  const double big_r2 = r2 + y_mm * y_mm;
  const double big_r = std::sqrt(big_r2);
  const double big_r5 = big_r2 * big_r2 * big_r;
  const double c = leading(y_mm);
  // The point source of strength C_k in closed form: C / R and its second derivatives.
  Response out{c / big_r, c * (3.0 * u_mm * u_mm - big_r2) / big_r5,
               c * (3.0 * y_mm * y_mm - big_r2) / big_r5};

  // The remainder K - C e^{-lambda y} decays as e^{-lambda a}, a = remainder_distance(y).
  const double a = remainder_distance(y_mm);
  if (std::isfinite(a) && !uniform()) {
    const double lambda_max = 40.0 / a;  // e^-40: far below double rounding of the total
    // Panels: half a period of J0 at most, and fine enough for the remainder's decay.  At
    // small lambda the kernel changes on the scale of the whole stack, 1 / (2 H), and has
    // poles on the negative axis close to 0, so the first 20 / H are cut finer.
    double stack = y_mm;
    for (std::size_t i = 0; i + 1 < layers_.size(); ++i) stack += layers_[i].thickness_mm;
    const double coarse = std::min(r > 0.0 ? kPi / r : INFINITY, 0.5 / a);
    const double fine = std::min(coarse, 0.05 / stack);
    const double lambda_fine = std::min(lambda_max, 20.0 / stack);
    const double panels = std::ceil(lambda_fine / fine) + std::ceil(lambda_max / coarse);
    if (!(panels <= 1e6))
      failure("layered: the Hankel transform needs " + number_text(panels) +
              " panels (a point too close to an interface, or too far away)");
    const auto& g = gauss16();
    double i_psi = 0.0, i_rr = 0.0, i_r_over_r = 0.0, i_yy = 0.0;
    auto panel = [&](double lo, double width) {
      for (std::size_t q = 0; q < 16; ++q) {
        const double lambda = lo + 0.5 * width * (1.0 + g.x[q]);
        const double wt = 0.5 * width * g.w[q];
        const double rem = kernel(lambda, y_mm) - c * std::exp(-lambda * y_mm);
        const double x = lambda * r;
        const double j0 = ::j0(x);
        const double j1x = j1_over_x(x);
        const double l2 = lambda * lambda;
        i_psi += wt * rem * j0;
        i_rr += wt * rem * l2 * (-j0 + j1x);
        i_r_over_r += wt * rem * l2 * (-j1x);
        i_yy += wt * rem * l2 * j0;
      }
    };
    const auto n_fine = static_cast<std::size_t>(std::ceil(lambda_fine / fine));
    const double w_fine = lambda_fine / static_cast<double>(n_fine);
    for (std::size_t p = 0; p < n_fine; ++p) panel(static_cast<double>(p) * w_fine, w_fine);
    if (lambda_max > lambda_fine) {
      const auto n_coarse =
          static_cast<std::size_t>(std::ceil((lambda_max - lambda_fine) / coarse));
      const double w_coarse = (lambda_max - lambda_fine) / static_cast<double>(n_coarse);
      for (std::size_t p = 0; p < n_coarse; ++p)
        panel(lambda_fine + static_cast<double>(p) * w_coarse, w_coarse);
    }
    // d2/du2 of f(r): f'' u^2 / r^2 + (f' / r) w^2 / r^2 (both terms equal at r = 0).
    const double fu = r > 0.0 ? u_mm * u_mm / r2 : 0.5;
    out.psi += i_psi;
    out.psi_uu += i_rr * fu + i_r_over_r * (1.0 - fu);
    out.psi_yy += i_yy;
  }
  const double scale = 1.0 / (2.0 * kPi);  // 1 mA; rho in ohm m over mm gives V
  out.psi *= scale;
  out.psi_uu *= scale;
  out.psi_yy *= scale;
  return out;
}

}  // namespace tp
