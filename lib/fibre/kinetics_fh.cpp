// The Frankenhaeuser-Huxley node (Frankenhaeuser & Huxley 1964; McNeal 1976, Table I), as
// written in fh.mod of ModelDB 239006 (Reilly 2016's NEURON benchmark): Na and P currents
// through m^2 h and p^2 with the Na GHK factor, K through n^2 with the K GHK factor, and a
// leak.  Constants and sources: docs/fibres.md.

#include <cmath>

#include "fibre/kinetics.hpp"

namespace tp::fibre {
namespace {

constexpr double kFaraday = 96485.3321;  // C/mol (NEURON's FARADAY, 2019 SI)
constexpr double kGas = 8.314462618;     // J/(mol K)

// x / (exp(x / y) - 1), with its limit near x = 0 (fh.mod's expM1).
double exp_m1(double x, double y) {
  if (std::fabs(x / y) < 1e-6) return y * (1.0 - x / y / 2.0);
  return x / (std::exp(x / y) - 1.0);
}
// z / (exp(z) - 1) (fh.mod's efun).
double efun(double z) {
  if (std::fabs(z) < 1e-4) return 1.0 - z / 2.0;
  return z / (std::exp(z) - 1.0);
}

class FhNode final : public NodeKinetics {
 public:
  explicit FhNode(const FhParams& p)
      : p_(p),
        q10_(std::pow(3.0, (p.rate_celsius - 20.0) / 10.0)),
        f_rt_(1e-3 * kFaraday / (kGas * (p.celsius + 273.15))) {}

  const char* name() const override { return "fh-node"; }
  std::size_t gate_count() const override { return 4; }  // m, h, n, p
  double rest_mV() const override { return p_.rest_mV; }

  void steady_state(double v, double* g) const override {
    for (int k = 0; k < 4; ++k) {
      const double a = alpha(v, k), b = beta(v, k);
      g[k] = a + b > 0.0 && std::isfinite(a + b) ? a / (a + b) : 0.0;
    }
  }

  double current(double v, const double* g, double* di_dv) const override {
    const double i = ionic(v, g);
    if (di_dv) *di_dv = (ionic(v + 1e-3, g) - i) / 1e-3;  // NEURON's numerical derivative
    return i;
  }

  void advance(double v, double dt, double* g) const override {
    for (int k = 0; k < 4; ++k) {
      const double a = alpha(v, k), b = beta(v, k);
      if (!(a + b > 0.0) || !std::isfinite(a + b)) continue;  // rates out of range: hold
      const double tau = 1.0 / (a + b), inf = a / (a + b);
      g[k] += (1.0 - std::exp(-dt / tau)) * (inf - g[k]);
    }
  }

 private:
  // GHK factor in mC/cm^3 (times a permeability in cm/s: mA/cm^2).
  double ghk(double v, double ci, double co) const {
    const double z = f_rt_ * v;
    return 1e-3 * kFaraday * (ci * efun(-z) - co * efun(z));
  }
  double ionic(double v, const double* g) const {
    const double m = g[0], h = g[1], n = g[2], pp = g[3];
    const double gna = ghk(v, p_.na_i_mM, p_.na_o_mM);
    return p_.p_na_cm_s * m * m * h * gna + p_.p_p_cm_s * pp * pp * gna +
           p_.p_k_cm_s * n * n * ghk(v, p_.k_i_mM, p_.k_o_mM) + p_.g_l_S_cm2 * (v - p_.e_l_mV);
  }
  double alpha(double v, int k) const {
    const double u = v + 70.0;
    switch (k) {
      case 0:
        return q10_ * 0.36 * exp_m1(22.0 - u, 3.0);
      case 1:
        return q10_ * 0.1 * exp_m1(u + 10.0, 6.0);
      case 2:
        return q10_ * 0.02 * exp_m1(35.0 - u, 10.0);
      default:
        return q10_ * 0.006 * exp_m1(40.0 - u, 10.0);
    }
  }
  double beta(double v, int k) const {
    const double u = v + 70.0;
    switch (k) {
      case 0:
        return q10_ * 0.4 * exp_m1(u - 13.0, 20.0);
      case 1:
        return q10_ * 4.5 / (std::exp((45.0 - u) / 10.0) + 1.0);
      case 2:
        return q10_ * 0.05 * exp_m1(u - 10.0, 10.0);
      default:
        return q10_ * 0.09 * exp_m1(u + 25.0, 20.0);
    }
  }

  FhParams p_;
  double q10_, f_rt_;
};

}  // namespace

std::unique_ptr<NodeKinetics> make_fh_node(const FhParams& params) {
  return std::make_unique<FhNode>(params);
}

}  // namespace tp::fibre
