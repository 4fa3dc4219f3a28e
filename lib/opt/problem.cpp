#include "opt/problem.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp {

Eigen::MatrixXd zero_sum_basis(std::size_t n) {
  // Householder QR of the all-ones vector: the remaining columns of Q span its complement.
  const Eigen::MatrixXd ones = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(n), 1);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ones);
  const Eigen::MatrixXd q = qr.householderQ();
  return q.rightCols(static_cast<Eigen::Index>(n) - 1);
}

Eigen::VectorXd unit_af(const Setup& setup, const Conductor& c, const Receptor& r, double x_mm,
                        double y_mm) {
  const auto n = static_cast<Eigen::Index>(setup.array.size());
  Eigen::VectorXd xx(n), yy(n);
  c.unit_second_derivatives(x_mm, y_mm, xx.data(), yy.data());
  const double k = fibre_factor_mm2_per_ms(r.fibre);
  return k * (r.fibre.orientation == Orientation::horizontal ? xx : yy);
}

namespace {

void sample_segment(double x0, double y0, double x1, double y1, double step, std::size_t receptor,
                    std::vector<SamplePoint>& out) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  const double count = std::ceil(len / step);
  if (!(count < kMaxSamples)) refuse_sample_count("a fibre region's boundary", count);
  const auto n = static_cast<std::size_t>(count);
  for (std::size_t i = 0; i <= n; ++i) {
    const double t = n ? static_cast<double>(i) / static_cast<double>(n) : 0.0;
    out.push_back({x0 + t * (x1 - x0), y0 + t * (y1 - y0), receptor});
  }
}

// The boundary of receptor r's region; with `interior` (a model not harmonic in the plane),
// the whole rectangle, row by row at depths `step` apart.
void sample_region(const Setup& s, std::size_t r, double step, bool interior,
                   std::vector<SamplePoint>& out) {
  const Region g = fibre_region(s, s.receptors[r]);
  if (interior && g.y1_mm > g.y0_mm) {
    const double rows = std::ceil((g.y1_mm - g.y0_mm) / step);
    const double cols = std::ceil((g.x1_mm - g.x0_mm) / step) + 1;
    if (!((rows + 1) * cols < kMaxSamples))
      refuse_sample_count("a fibre region", (rows + 1) * cols);
    const auto n = static_cast<std::size_t>(rows);
    for (std::size_t j = 0; j <= n; ++j) {
      const double y =
          j == n ? g.y1_mm
                 : g.y0_mm + (g.y1_mm - g.y0_mm) * static_cast<double>(j) / static_cast<double>(n);
      sample_segment(g.x0_mm, y, g.x1_mm, y, step, r, out);
    }
    return;
  }
  sample_segment(g.x0_mm, g.y0_mm, g.x1_mm, g.y0_mm, step, r, out);
  if (g.y1_mm > g.y0_mm) {
    sample_segment(g.x0_mm, g.y1_mm, g.x1_mm, g.y1_mm, step, r, out);
    sample_segment(g.x0_mm, g.y0_mm, g.x0_mm, g.y1_mm, step, r, out);
    sample_segment(g.x1_mm, g.y0_mm, g.x1_mm, g.y1_mm, step, r, out);
  }
}

Eigen::MatrixXd rows_for(const Setup& s, const Conductor& c, const std::vector<SamplePoint>& pts,
                         const Eigen::MatrixXd& basis) {
  // One conductor call per sample into a small buffer, then straight into z coordinates:
  // no (samples x electrodes) temporary.
  const auto n = static_cast<Eigen::Index>(s.array.size());
  Eigen::MatrixXd out(static_cast<Eigen::Index>(pts.size()), basis.cols());
  Eigen::RowVectorXd g(n);
  std::vector<double> factor(s.receptors.size());
  for (std::size_t r = 0; r < s.receptors.size(); ++r)
    factor[r] = fibre_factor_mm2_per_ms(s.receptors[r].fibre);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const SamplePoint& pt = pts[i];
    const bool horizontal = s.receptors[pt.receptor].fibre.orientation == Orientation::horizontal;
    c.unit_second_derivatives(pt.x_mm, pt.y_mm, horizontal ? g.data() : nullptr,
                              horizontal ? nullptr : g.data());
    out.row(static_cast<Eigen::Index>(i)).noalias() = factor[pt.receptor] * g * basis;
  }
  return out;
}

}  // namespace

ModeProblem make_mode_problem(const Setup& setup, const std::string& mode, double step_mm,
                              bool target_rows) {
  if (setup.array.size() < 2) bad_input("optimisation needs at least 2 electrodes");
  if (setup.receptors.size() < 2) bad_input("optimisation needs at least 2 receptors");
  if (setup.array.two_d())
    bad_input("array: " + setup.array.describe() + " is 2-D: give a pixel's place (--at X,Z)");
  ModeProblem p;
  p.mode = mode;
  p.target = receptor_index(setup, mode);
  p.basis = zero_sum_basis(setup.array.size());
  const auto conductor = make_conductor(setup.conductor, setup.array);
  check_fibre_reach(setup, *conductor);  // every sample can be evaluated: before any work
  const bool interior = !conductor->planar_harmonic();
  for (std::size_t r = 0; r < setup.receptors.size(); ++r)
    sample_region(setup, r, step_mm, interior, r == p.target ? p.target_pts : p.off_pts);
  // The sample matrices hold (samples x electrodes) doubles: bounded, and refused beyond.
  const double entries = static_cast<double>(p.target_pts.size() + p.off_pts.size()) *
                         static_cast<double>(setup.array.size());
  if (entries > kMaxProblemEntries) {
    const Region g = fibre_region(setup, setup.receptors.front());
    bad_input("optimisation problem of " + std::to_string(p.target_pts.size() + p.off_pts.size()) +
              " samples x " + std::to_string(setup.array.size()) +
              " electrodes = " + number_text(entries) + ", more than the cap of " +
              number_text(kMaxProblemEntries) + ": fibres " + number_text(g.x1_mm - g.x0_mm) +
              " mm long sampled every " + number_text(step_mm) + " mm" +
              (interior ? " over each receptor's depth range (" + std::string(conductor->name()) +
                              " is a 3-D model)"
                        : std::string()) +
              ", for this many electrodes (fewer electrodes, a smaller pitch or margin)");
  }
  if (target_rows) p.target_rows = rows_for(setup, *conductor, p.target_pts, p.basis);
  p.off_rows = rows_for(setup, *conductor, p.off_pts, p.basis);
  return p;
}

}  // namespace tp
