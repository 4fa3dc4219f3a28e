// 2-D conductor models: a uniform, unbounded medium with electrodes as infinitely long
// sources along z (the paper's Sec. 4.2).
//
// line2d (Eq. 21): a line electrode carrying I over length L is a 2-D point source of
// I/L per unit length.  With the project's convention (positive current is cathodic, i.e.
// drawn out of the tissue) the potential is
//     Psi = rho (I/L) ln(R) / (2 pi),          R = sqrt((x - x_i)^2 + y^2),
// the paper's Eq. 21 with its injected current written as -I.  This makes
//     d2Psi/dx2 = rho (I/L) / (2 pi) * (y^2 - u^2) / (u^2 + y^2)^2,   u = x - x_i  (Eq. 23)
// positive under a cathode, as in the paper's Fig. 4, and d2Psi/dy2 = -d2Psi/dx2 (Eq. 27).
// Units: rho in ohm*m times I/L in mA/mm gives volts; lengths in mm give V/mm^2.
//
// strip2d: the same medium with each electrode a strip of width w carrying a uniform
// current density (Eq. 24 integrated over the strip), using
//     integral (y^2 - u^2) / (u^2 + y^2)^2 du = u / (u^2 + y^2).

#include <cmath>
#include <memory>

#include "core/error.hpp"
#include "model/conductor.hpp"
#include "model/constants.hpp"

namespace tp {
namespace {

constexpr double kPi = 3.14159265358979323846;

class Line2d : public Conductor {
 public:
  Line2d(const ElectrodeArray& array, double rho_ohm_m)
      : x_(array.positions_mm), scale_(rho_ohm_m / (array.length_mm * 2.0 * kPi)) {}
  const char* name() const override { return "line2d"; }
  std::size_t size() const override { return x_.size(); }
  bool planar_harmonic() const override { return true; }

  void unit_potentials(double x_mm, double y_mm, double* psi) const override {
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i];
      psi[i] = scale_ * 0.5 * std::log(u * u + y_mm * y_mm);
    }
  }

  void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const override {
    const double y2 = y_mm * y_mm;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i];
      const double u2 = u * u;
      const double r2 = u2 + y2;
      const double v = scale_ * (y2 - u2) / (r2 * r2);
      if (xx) xx[i] = v;
      if (yy) yy[i] = -v;
    }
  }

 private:
  std::vector<double> x_;
  double scale_;  // rho / (2 pi L), V per mA per mm^0 (see above)
};

class Strip2d : public Conductor {
 public:
  Strip2d(const ElectrodeArray& array, double rho_ohm_m)
      : x_(array.positions_mm),
        half_(0.5 * array.width_mm),
        scale_(rho_ohm_m / (array.length_mm * 2.0 * kPi)) {
    if (!(array.width_mm > 0.0)) bad_input("strip2d: electrode width_mm must be > 0");
  }
  const char* name() const override { return "strip2d"; }
  std::size_t size() const override { return x_.size(); }
  bool planar_harmonic() const override { return true; }

  // Antiderivative of ln R along the strip: d/du [u ln R - u + y atan(u/y)] = ln R.
  void unit_potentials(double x_mm, double y_mm, double* psi) const override {
    const double inv_w = 1.0 / (2.0 * half_);
    auto g = [y_mm](double u) {
      return 0.5 * u * std::log(u * u + y_mm * y_mm) - u + y_mm * std::atan(u / y_mm);
    };
    for (std::size_t i = 0; i < x_.size(); ++i)
      psi[i] = scale_ * inv_w * (g(x_mm - x_[i] + half_) - g(x_mm - x_[i] - half_));
  }

  void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const override {
    const double y2 = y_mm * y_mm;
    const double inv_w = 1.0 / (2.0 * half_);
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double a = x_mm - x_[i] + half_;
      const double b = x_mm - x_[i] - half_;
      const double v = scale_ * inv_w * (a / (a * a + y2) - b / (b * b + y2));
      if (xx) xx[i] = v;
      if (yy) yy[i] = -v;
    }
  }

 private:
  std::vector<double> x_;
  double half_;
  double scale_;
};

}  // namespace

std::unique_ptr<Conductor> make_line2d(const ElectrodeArray& array, double rho_ohm_m) {
  return std::make_unique<Line2d>(array, rho_ohm_m);
}

std::unique_ptr<Conductor> make_strip2d(const ElectrodeArray& array, double rho_ohm_m) {
  return std::make_unique<Strip2d>(array, rho_ohm_m);
}

}  // namespace tp
