#pragma once
// The activating function (AF) of a current pattern, and each receptor's largest AF.

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/number.hpp"
#include "model/conductor.hpp"
#include "model/receptors.hpp"
#include "model/setup.hpp"

namespace tp {

// The most pad evaluations one receptor's search under a 2-D array may take (about 20 s
// of rect3d on one core); more is bad input, named before any work.
inline constexpr double kMaxFieldWork = 2e9;

struct Peak {
  double af = 0.0;  // V/ms, largest AF over the receptor's fibres
  double x_mm = 0.0;
  double y_mm = 0.0;
  double z_mm = 0.0;  // 2-D arrays (a 1-D array's fibres lie in the plane z = plane_z_mm)
};

// A function's values on a grid: v[j * s.size() + i] = f(s[i], t[j]), s and t increasing
// (at least one point each), about hs and ht apart.
struct GridValues {
  std::vector<double> s, t, v;
  double hs = 0.0, ht = 0.0;
};

class Field {
 public:
  // currents_mA: one per electrode, positive = cathodic.
  Field(const Setup& setup, std::vector<double> currents_mA);

  const Conductor& conductor() const { return *conductor_; }
  const std::vector<double>& currents_mA() const { return currents_; }

  // d2Psi/dx2 and d2Psi/dy2 (V/mm^2) at a point.
  void second_derivatives(double x_mm, double y_mm, double& xx, double& yy) const;
  // AF (V/ms) of a fibre at a point: fibre factor times d2Psi/ds2 along the fibre.
  double af(const Fibre& fibre, double x_mm, double y_mm) const;
  // The same at a 3-D point for a fibre along `axis` (3-D models).
  double af_3d(const Fibre& fibre, const FibreAxis& axis, double x_mm, double y_mm,
               double z_mm) const;

  // Largest AF over the receptor's fibres, and where it occurs.
  Peak peak(const Receptor& r) const;

  // A 2-D array's: the AF (V/ms) of receptor r's fibres over the plane y = y_mm of its
  // region, at points at most step_mm apart (s along x, t along z): on a grid, a lattice
  // its pads' centres lie on, with the region's edges (model/lattice.hpp); else the
  // uniform grid maximize_2d() samples.
  GridValues plane_af(const Receptor& r, double y_mm, double step_mm) const;
  // The same over a wall of the region: the plane z = fixed_mm (along_x: s along x) or
  // x = fixed_mm (s along z), t the depth from the region's top to its bottom; s on the
  // lattice as plane_af's, t uniform at most step_mm apart (as maximize_2d samples it).
  GridValues wall_af(const Receptor& r, bool along_x, double fixed_mm, double step_mm) const;

 private:
  Peak peak_3d(const Receptor& r) const;  // a 2-D array's: over the box of fibres
  // The AF from every pad's response k (as the array's index): sum of currents x k, times
  // the fibre factor ff.
  double from_pads(const std::vector<double>& k, double ff) const;

  const Setup& setup_;
  std::unique_ptr<Conductor> conductor_;
  std::vector<double> currents_;
  // A 2-D array's pads that carry current, when some do not (a pattern on a neighbourhood
  // of pads): af_3d() evaluates those alone.
  std::unique_ptr<Conductor> active_conductor_;
  std::vector<double> active_currents_;
  mutable std::vector<double> scratch_;
};

// Largest AF per receptor and the selectivity ratio of each mode (Eq. 32-34):
// ratio[M] = largest off-target AF / largest AF of receptor M.  No value when the target's
// largest AF is not positive (the target is never depolarised).
struct Summary {
  std::vector<std::pair<std::string, Peak>> peaks;  // in receptor-table order
  std::vector<std::pair<std::string, std::optional<double>>> ratios;
};
Summary summarize(const Setup& setup, const std::vector<double>& currents_mA);
// The Summary of given peaks, one per receptor in table order (their ratios added).
Summary summary_of(const Setup& setup, const std::vector<Peak>& peaks);

// The index of the receptor named `mode`; bad input naming the known ones otherwise.
std::size_t receptor_index(const Setup& setup, const std::string& mode);

std::optional<double> mode_ratio(const std::vector<std::pair<std::string, Peak>>& peaks,
                                 const std::string& mode);

// Maximises f on [a, b]: dense sampling at `step`, then every sampled local maximum refined
// by Brent's search (brent_max).  Returns (argmax, max).
template <class F>
std::pair<double, double> maximize_1d(F&& f, double a, double b, double step);

// Maximises f(s, t) on [s0, s1] x [t0, t1]: a grid at most `step` apart, then every grid
// point at least as high as its neighbours refined by alternating line searches along s and
// t (a scan within a grid step and Brent's search, then Brent's search within a quarter
// step).  Returns (s, t, max).
struct Max2d {
  double s, t, value;
};
template <class F>
Max2d maximize_2d(F&& f, double s0, double s1, double t0, double t1, double step);

// The same from f's values on a grid already evaluated (GridValues), each local maximum
// refined within (hs, ht) of it.  uniform_grid(): maximize_2d()'s grid, without values
// (bad input beyond kMaxSamples points).
template <class F>
Max2d maximize_2d_grid(F&& f, const GridValues& grid);
GridValues uniform_grid(double s0, double s1, double t0, double t1, double step);

}  // namespace tp

#include "model/maximize_impl.hpp"
