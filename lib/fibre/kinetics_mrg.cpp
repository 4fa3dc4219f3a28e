// MRG's node of Ranvier: fast Na (m^3 h), persistent Na (mp^3), slow K (s) and leak, with
// the rate functions and Q10s of the published mechanism (AXNODE.mod, ModelDB 3810; McIntyre,
// Richardson & Grill 2002, Appendix).  Constants and their sources: docs/fibres.md.

#include <cmath>
#include <limits>

#include "fibre/kinetics.hpp"

namespace tp::fibre {
namespace {

// AXNODE's guarded exponential and "vtrap" forms: a (x + B) / (1 - exp(-(x + B) / C)),
// with its limit a C where the denominator vanishes.
double guarded_exp(double x) {
  return x < -100.0 ? 0.0 : std::exp(x);
}
double rising(double v, double a, double b, double c) {
  const double u = (v + b) / c;
  if (std::fabs(u) < 1e-6) return a * c;
  return a * (v + b) / (1.0 - guarded_exp(-u));
}
double falling(double v, double a, double b, double c) {
  const double u = (v + b) / c;
  if (std::fabs(u) < 1e-6) return a * c;
  return a * -(v + b) / (1.0 - guarded_exp(u));
}

class MrgNode final : public NodeKinetics {
 public:
  explicit MrgNode(double celsius)
      : q10_1_(std::pow(2.2, (celsius - 20.0) / 10.0)),
        q10_2_(std::pow(2.9, (celsius - 20.0) / 10.0)),
        q10_3_(std::pow(3.0, (celsius - 36.0) / 10.0)) {}

  const char* name() const override { return "mrg-node"; }
  std::size_t gate_count() const override { return 4; }  // mp, m, h, s
  double rest_mV() const override { return -80.0; }

  void steady_state(double v, double* g) const override {
    Rates r = rates(v);
    for (int k = 0; k < 4; ++k) g[k] = r.inf[k];
  }

  double current(double v, const double* g, double* di_dv) const override {
    const double mp = g[0], m = g[1], h = g[2], s = g[3];
    const double gnap = kGnap * mp * mp * mp;
    const double gna = kGna * m * m * m * h;
    const double gk = kGk * s;
    if (di_dv) *di_dv = gnap + gna + gk + kGl;
    return gnap * (v - kEna) + gna * (v - kEna) + gk * (v - kEk) + kGl * (v - kEl);
  }

  void advance(double v, double dt, double* g) const override {
    Rates r = rates(v);  // 1 - exp(-dt / tau), with 1 / tau = alpha + beta
    for (int k = 0; k < 4; ++k) g[k] += (1.0 - std::exp(-dt * r.rate[k])) * (r.inf[k] - g[k]);
  }

 private:
  struct Rates {
    double inf[4], rate[4];  // rate = 1 / tau = alpha + beta
  };
  Rates rates(double v) const {
    Rates r{};
    auto set = [&](int k, double a, double b) {
      const double sum = a + b;
      if (!(sum > 0.0) || !std::isfinite(sum)) {  // both rates under- or overflowed:
        r.rate[k] = 0.0;                          // the gate holds still
        r.inf[k] = 0.0;
        return;
      }
      r.rate[k] = sum;
      r.inf[k] = a / sum;
    };
    set(0, q10_1_ * rising(v, 0.01, 27.0, 10.2), q10_1_ * falling(v, 0.00025, 34.0, 10.0));
    set(1, q10_1_ * rising(v, 1.86, 21.4, 10.3), q10_1_ * falling(v, 0.086, 25.7, 9.16));
    set(2, q10_2_ * falling(v, 0.062, 114.0, 11.0),
        q10_2_ * 2.3 / (1.0 + guarded_exp(-(v + 31.8) / 13.4)));
    const double v2 = v + 80.0;  // AXNODE's "Traub convention": v - vtraub, vtraub = -80
    set(3, q10_3_ * 0.3 / (guarded_exp((v2 - 27.0) / -5.0) + 1.0),
        q10_3_ * 0.03 / (guarded_exp((v2 + 10.0) / -1.0) + 1.0));
    return r;
  }

  static constexpr double kGnap = 0.01, kGna = 3.0, kGk = 0.08, kGl = 0.007;  // S/cm^2
  static constexpr double kEna = 50.0, kEk = -90.0, kEl = -90.0;              // mV
  double q10_1_, q10_2_, q10_3_;
};

}  // namespace

std::unique_ptr<NodeKinetics> make_mrg_node(double celsius) {
  return std::make_unique<MrgNode>(celsius);
}

}  // namespace tp::fibre
