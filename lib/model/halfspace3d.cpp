// 3-D conductor models: electrodes on the insulated surface (y = 0) of a uniform
// half-space y > 0.  Coordinates: x across the electrodes, y depth, z along their length;
// the fibres lie in the plane z = plane_z_mm.
//
// A point current I on the insulated surface of a half-space of resistivity rho sets up
// twice the full-space potential (its image in the surface coincides with it):
//     Psi = -rho I / (2 pi r)                 (I > 0 cathodic: drawn out of the tissue)
// so that d2Psi/dx2 = rho I / (2 pi) (r^2 - 3 u^2) / r^5, u = x - x_i, which is positive
// straight under a cathode (depolarising a horizontal fibre), as in the 2-D models.
// Units: rho in ohm*m times I in mA over r in mm gives volts; lengths in mm give V/mm^2.
//
// point3d: each electrode a point source at (x_i, d, 0), d = source_depth_mm (0: on the
// surface).  A buried source in the half-space has its image at depth -d:
//     Psi = -rho I / (4 pi) (1/r1 + 1/r2),
// which is -rho I / (2 pi r) at d = 0.
//
// rect3d: each electrode a width_mm x length_mm rectangle with uniform current density
// I / (w L).  With a = x - u and b = z - v running over the rectangle as seen from the
// point, R = sqrt(a^2 + b^2 + y^2), and C[f] = f(a2, b2) - f(a1, b2) - f(a2, b1) + f(a1, b1)
// the sum over its corners:
//     Psi      = -K C[G],     G   = a asinh(b / sqrt(a^2 + y^2)) + b asinh(a / sqrt(b^2 + y^2))
//                                   - y atan(a b / (y R))
//     Psi_xx   = -K C[Hxx],   Hxx = -a b / ((a^2 + y^2) R)
//     Psi_zz   = -K C[Hzz],   Hzz = -a b / ((b^2 + y^2) R)
//     Psi_yy   = -K C[Hyy],   Hyy = a b (R^2 + y^2) / (R (a^2 + y^2) (b^2 + y^2))
//     Psi_xz   = -K C[Hxz],   Hxz = 1 / R
// with K = rho I / (2 pi w L).  G is the classical double integral of 1/R over a rectangle;
// Hxx follows from integrating d(1/R)/da = -a/R^3 over b, Hzz likewise, and Hyy from
// differentiating dG/dy = -atan(a b / (y R)) once more.  The three are derived separately,
// so Hxx + Hyy + Hzz = 0 (Laplace) is a check, not an identity of the code
// (docs/model.md).  Hxz is d2G/da db, the integrand itself.
//
// 2-D arrays: pad i centred at (x_i, 0, z_i); the point's offset from it, (x - x_i, y,
// z - z_i), enters as above (b runs over z - z_i -+ L/2; point3d's source lies at
// (x_i, d, z_i)).  Along a horizontal fibre at azimuth (c, 0, s):
//     Psi_ss = c^2 Psi_xx + 2 c s Psi_xz + s^2 Psi_zz,
// and for a point source, Psi_ss = k (r^2 - 3 (e . r)^2) / r^5 for any unit direction e.

#include <cmath>
#include <memory>

#include "core/error.hpp"
#include "model/conductor.hpp"

namespace tp {
namespace {

constexpr double kPi = 3.14159265358979323846;

class Point3d : public Conductor {
 public:
  Point3d(const ElectrodeArray& array, double rho_ohm_m, double plane_z_mm, double depth_mm)
      : x_(array.positions_mm),
        pz_(array.z_mm),
        z_(plane_z_mm),
        d_(depth_mm),
        k_(rho_ohm_m / (4.0 * kPi)) {}
  const char* name() const override { return "point3d"; }
  std::size_t size() const override { return x_.size(); }
  bool planar_harmonic() const override { return false; }
  bool three_d() const override { return true; }
  double buried_source_depth_mm() const override { return d_ > 0.0 ? d_ : 0.0; }

  void unit_potentials_3d(double x_mm, double y_mm, double z_mm, double* psi) const override {
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i], w = z_mm - (pz_.empty() ? 0.0 : pz_[i]);
      const double r1 = std::sqrt(u * u + (y_mm - d_) * (y_mm - d_) + w * w);
      const double r2 = std::sqrt(u * u + (y_mm + d_) * (y_mm + d_) + w * w);
      psi[i] = -k_ * (1.0 / r1 + 1.0 / r2);
    }
  }

  void unit_d2_along(double x_mm, double y_mm, double z_mm, const FibreAxis& e,
                     double* out) const override {
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i], w = z_mm - (pz_.empty() ? 0.0 : pz_[i]);
      double sum = 0.0;
      for (const double v : {y_mm - d_, y_mm + d_}) {  // the source and its image
        const double r2 = u * u + v * v + w * w;
        const double r = std::sqrt(r2);
        const double p = e.vertical ? v : e.cos_az * u + e.sin_az * w;
        sum += (r2 - 3.0 * p * p) / (r2 * r2 * r);
      }
      out[i] = k_ * sum;
    }
  }

  void unit_potentials(double x_mm, double y_mm, double* psi) const override {
    if (!pz_.empty()) return unit_potentials_3d(x_mm, y_mm, z_, psi);
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i];
      const double r1 = std::sqrt(u * u + (y_mm - d_) * (y_mm - d_) + z_ * z_);
      const double r2 = std::sqrt(u * u + (y_mm + d_) * (y_mm + d_) + z_ * z_);
      psi[i] = -k_ * (1.0 / r1 + 1.0 / r2);
    }
  }

  void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const override {
    if (!pz_.empty()) {  // a 2-D array: its section at z = plane_z_mm
      if (xx) unit_d2_along(x_mm, y_mm, z_, FibreAxis{}, xx);
      if (yy) unit_d2_along(x_mm, y_mm, z_, FibreAxis{true, 0.0, 0.0}, yy);
      return;
    }
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i];
      double sxx = 0.0, syy = 0.0;
      for (const double v : {y_mm - d_, y_mm + d_}) {  // the source and its image
        const double r2 = u * u + v * v + z_ * z_;
        const double r = std::sqrt(r2);
        const double r5 = r2 * r2 * r;
        sxx += (r2 - 3.0 * u * u) / r5;  // -d2(1/r)/du2
        syy += (r2 - 3.0 * v * v) / r5;
      }
      if (xx) xx[i] = k_ * sxx;
      if (yy) yy[i] = k_ * syy;
    }
  }

 private:
  std::vector<double> x_, pz_;  // pad centres (pz_: a 2-D array's, else empty)
  double z_, d_, k_;            // k = rho / (4 pi): each of the source and its image
};

class Rect3d : public Conductor {
 public:
  Rect3d(const ElectrodeArray& array, double rho_ohm_m, double plane_z_mm)
      : x_(array.positions_mm),
        pz_(array.z_mm),
        half_w_(0.5 * array.width_mm),
        half_l_(0.5 * array.length_mm),
        z_(plane_z_mm),
        k_(rho_ohm_m / (2.0 * kPi * array.width_mm * array.length_mm)) {
    if (!(array.width_mm > 0.0)) bad_input("rect3d: array.width_mm must be > 0");
    if (!(array.length_mm > 0.0)) bad_input("rect3d: array.length_mm must be > 0");
  }
  const char* name() const override { return "rect3d"; }
  std::size_t size() const override { return x_.size(); }
  bool planar_harmonic() const override { return false; }
  bool three_d() const override { return true; }

  // The mean over the pad of the potential its own uniform current density sets up:
  // rho / (2 pi w^2 L^2) times the fourfold integral of 1 / |r - r'| over the pad twice,
  //     F(w, L) = 2/3 (w^3 + L^3 - d^3) + 2 w^2 L asinh(L / w) + 2 w L^2 asinh(w / L),
  // d = sqrt(w^2 + L^2) (docs/skin.md).  Ohm m over mm is kOhm.
  std::optional<double> spreading_resistance_kohm(std::size_t /*pad*/) const override {
    const double w = 2 * half_w_, l = 2 * half_l_, d = std::hypot(w, l);
    const double f = 2.0 / 3.0 * (w * w * w + l * l * l - d * d * d) +
                     2 * w * w * l * std::asinh(l / w) + 2 * w * l * l * std::asinh(w / l);
    return k_ * f / (w * l);  // k = rho / (2 pi w L)
  }

  void unit_potentials_3d(double x_mm, double y_mm, double z_mm, double* psi) const override {
    // G(a, b): the double integral of 1/R over a corner's quadrant.
    const double y2 = y_mm * y_mm;
    auto g = [&](double a, double b) {
      const double r = std::sqrt(a * a + b * b + y2);
      return a * std::asinh(b / std::sqrt(a * a + y2)) + b * std::asinh(a / std::sqrt(b * b + y2)) -
             y_mm * std::atan(a * b / (y_mm * r));
    };
    for (std::size_t i = 0; i < x_.size(); ++i)
      psi[i] = -k_ * corners3(g, x_mm - x_[i], z_mm - pz(i));
  }

  void unit_d2_along(double x_mm, double y_mm, double z_mm, const FibreAxis& e,
                     double* out) const override {
    const double y2 = y_mm * y_mm;
    const double cc = e.cos_az * e.cos_az, cs2 = 2.0 * e.cos_az * e.sin_az,
                 ss = e.sin_az * e.sin_az;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i], v = z_mm - pz(i);
      const double a[2] = {u - half_w_, u + half_w_};
      const double b[2] = {v - half_l_, v + half_l_};
      double sum = 0.0;
      for (int p = 0; p < 2; ++p) {
        const double aa = a[p] * a[p] + y2;
        for (int q = 0; q < 2; ++q) {
          const double bb = b[q] * b[q] + y2;
          const double r2 = aa + b[q] * b[q];
          const double r = std::sqrt(r2);
          const double ab_r = a[p] * b[q] / r;
          const double sign = p == q ? 1.0 : -1.0;  // + at (a2, b2) and (a1, b1)
          const double h = e.vertical ? ab_r * (r2 + y2) / (aa * bb)
                                      : cc * (-ab_r / aa) + cs2 / r + ss * (-ab_r / bb);
          sum += sign * h;
        }
      }
      out[i] = -k_ * sum;
    }
  }

  void unit_potentials(double x_mm, double y_mm, double* psi) const override {
    if (!pz_.empty()) return unit_potentials_3d(x_mm, y_mm, z_, psi);
    const double y2 = y_mm * y_mm;
    auto g = [&](double a, double b) {
      const double r = std::sqrt(a * a + b * b + y2);
      return a * std::asinh(b / std::sqrt(a * a + y2)) + b * std::asinh(a / std::sqrt(b * b + y2)) -
             y_mm * std::atan(a * b / (y_mm * r));
    };
    for (std::size_t i = 0; i < x_.size(); ++i) psi[i] = -k_ * corners(g, x_mm - x_[i]);
  }

  void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const override {
    if (!pz_.empty()) {  // a 2-D array: its section at z = plane_z_mm
      if (xx) unit_d2_along(x_mm, y_mm, z_, FibreAxis{}, xx);
      if (yy) unit_d2_along(x_mm, y_mm, z_, FibreAxis{true, 0.0, 0.0}, yy);
      return;
    }
    // Hxx and Hyy share ab / R and a^2 + y^2 at each corner; b's terms are the same for
    // every electrode.
    const double y2 = y_mm * y_mm;
    const double b[2] = {z_ - half_l_, z_ + half_l_};
    const double bb[2] = {b[0] * b[0] + y2, b[1] * b[1] + y2};
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double u = x_mm - x_[i];
      const double a[2] = {u - half_w_, u + half_w_};
      double sxx = 0.0, syy = 0.0;
      for (int p = 0; p < 2; ++p) {
        const double aa = a[p] * a[p] + y2;
        for (int q = 0; q < 2; ++q) {
          const double r2 = aa + b[q] * b[q];
          const double ab_r = a[p] * b[q] / std::sqrt(r2);
          const double sign = p == q ? 1.0 : -1.0;  // + at (a2, b2) and (a1, b1)
          sxx += sign * (-ab_r / aa);
          syy += sign * ab_r * (r2 + y2) / (aa * bb[q]);
        }
      }
      if (xx) xx[i] = -k_ * sxx;
      if (yy) yy[i] = -k_ * syy;
    }
  }

  // d2Psi/dz2, for the Laplace check in the tests.
  double unit_zz(std::size_t i, double x_mm, double y_mm) const {
    const double y2 = y_mm * y_mm;
    auto hzz = [&](double a, double b) {
      return -a * b / ((b * b + y2) * std::sqrt(a * a + b * b + y2));
    };
    return -k_ * corners3(hzz, x_mm - x_[i], z_ - pz(i));
  }
  // d2Psi/dz2 at a 3-D point (the tests' Laplace check on 2-D arrays).
  double unit_zz_3d(std::size_t i, double x_mm, double y_mm, double z_mm) const {
    const double y2 = y_mm * y_mm;
    auto hzz = [&](double a, double b) {
      return -a * b / ((b * b + y2) * std::sqrt(a * a + b * b + y2));
    };
    return -k_ * corners3(hzz, x_mm - x_[i], z_mm - pz(i));
  }

 private:
  // C[f] over the rectangle seen from a point at lateral offset u from its centre.
  template <class F>
  double corners(F&& f, double u) const {
    const double a1 = u - half_w_, a2 = u + half_w_;
    const double b1 = z_ - half_l_, b2 = z_ + half_l_;
    return f(a2, b2) - f(a1, b2) - f(a2, b1) + f(a1, b1);
  }
  // The same at offsets (u, v) from the pad's centre along x and z.
  template <class F>
  double corners3(F&& f, double u, double v) const {
    const double a1 = u - half_w_, a2 = u + half_w_;
    const double b1 = v - half_l_, b2 = v + half_l_;
    return f(a2, b2) - f(a1, b2) - f(a2, b1) + f(a1, b1);
  }
  double pz(std::size_t i) const { return pz_.empty() ? 0.0 : pz_[i]; }

  std::vector<double> x_, pz_;  // pad centres (pz_: a 2-D array's, else empty)
  double half_w_, half_l_, z_;
  double k_;  // rho / (2 pi w L)
};

}  // namespace

std::unique_ptr<Conductor> make_point3d(const ElectrodeArray& array, double rho_ohm_m,
                                        double plane_z_mm, double source_depth_mm) {
  return std::make_unique<Point3d>(array, rho_ohm_m, plane_z_mm, source_depth_mm);
}

std::unique_ptr<Conductor> make_rect3d(const ElectrodeArray& array, double rho_ohm_m,
                                       double plane_z_mm) {
  return std::make_unique<Rect3d>(array, rho_ohm_m, plane_z_mm);
}

double rect3d_unit_zz(const Conductor& c, std::size_t i, double x_mm, double y_mm) {
  const auto* r = dynamic_cast<const Rect3d*>(&c);
  if (!r) failure("rect3d_unit_zz: not a rect3d conductor");
  return r->unit_zz(i, x_mm, y_mm);
}

double rect3d_unit_zz_3d(const Conductor& c, std::size_t i, double x_mm, double y_mm, double z_mm) {
  const auto* r = dynamic_cast<const Rect3d*>(&c);
  if (!r) failure("rect3d_unit_zz_3d: not a rect3d conductor");
  return r->unit_zz_3d(i, x_mm, y_mm, z_mm);
}

}  // namespace tp
