#include "model/field.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "io/number.hpp"

namespace tp {

void refuse_sample_count(const char* what, double count) {
  bad_input(std::string(what) + ": " + number_text(count) + " samples, more than the cap of " +
            number_text(kMaxSamples) + " (a depth, margin or array span out of range)");
}

Region fibre_region(const Setup& setup, const Receptor& r) {
  return {setup.array.x_min_mm() - setup.lateral_margin_mm,
          setup.array.x_max_mm() + setup.lateral_margin_mm, r.depth_min_mm, r.depth_max_mm};
}

Field::Field(const Setup& setup, std::vector<double> currents_mA)
    : setup_(setup),
      conductor_(make_conductor(setup.conductor, setup.array)),
      currents_(std::move(currents_mA)),
      scratch_(2 * setup.array.size()) {
  if (currents_.size() != setup.array.size())
    bad_input("weights: expected " + std::to_string(setup.array.size()) + " values, got " +
              std::to_string(currents_.size()));
  for (double c : currents_)
    if (!std::isfinite(c)) bad_input("weights: non-finite value");
}

void Field::second_derivatives(double x_mm, double y_mm, double& xx, double& yy) const {
  const std::size_t n = currents_.size();
  double* bx = scratch_.data();
  double* by = bx + n;
  conductor_->unit_second_derivatives(x_mm, y_mm, bx, by);
  xx = 0.0;
  yy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    xx += currents_[i] * bx[i];
    yy += currents_[i] * by[i];
  }
}

double Field::af(const Fibre& fibre, double x_mm, double y_mm) const {
  // Only the derivative along the fibre.
  const bool horizontal = fibre.orientation == Orientation::horizontal;
  double* b = scratch_.data();
  conductor_->unit_second_derivatives(x_mm, y_mm, horizontal ? b : nullptr,
                                      horizontal ? nullptr : b);
  double d = 0.0;
  for (std::size_t i = 0; i < currents_.size(); ++i) d += currents_[i] * b[i];
  return fibre_factor_mm2_per_ms(fibre) * d;
}

Peak Field::peak(const Receptor& r) const {
  const Region reg = fibre_region(setup_, r);
  // Sampling step: the AF varies on the scale of the depth, so a 50th of it (at most
  // 0.02 mm) resolves every local maximum before refinement.
  const double step = std::min(0.02, reg.y0_mm / 50.0);
  Peak best;
  bool first = true;
  auto consider = [&](double af, double x, double y) {
    if (first || af > best.af) best = {af, x, y};
    first = false;
  };
  auto along_x = [&](double y) {
    auto [x, v] =
        maximize_1d([&](double xv) { return af(r.fibre, xv, y); }, reg.x0_mm, reg.x1_mm, step);
    consider(v, x, y);
  };
  auto along_y = [&](double x) {
    auto [y, v] =
        maximize_1d([&](double yv) { return af(r.fibre, x, yv); }, reg.y0_mm, reg.y1_mm, step);
    consider(v, x, y);
  };
  along_x(reg.y0_mm);
  if (reg.y1_mm > reg.y0_mm) {
    if (!conductor_->planar_harmonic())
      bad_input("conductor '" + std::string(conductor_->name()) +
                "' cannot evaluate depth ranges (no maximum principle)");
    // The AF is harmonic in the plane (Eq. 28-30), so its maximum over the rectangle of
    // fibres lies on the rectangle's boundary (maximum principle, Sec. 5.3).
    along_x(reg.y1_mm);
    along_y(reg.x0_mm);
    along_y(reg.x1_mm);
  }
  return best;
}

std::optional<double> mode_ratio(const std::vector<std::pair<std::string, Peak>>& peaks,
                                 const std::string& mode) {
  const Peak* target = nullptr;
  double off = -INFINITY;
  for (const auto& [name, p] : peaks) {
    if (name == mode)
      target = &p;
    else
      off = std::max(off, p.af);
  }
  if (!target) bad_input("unknown mode '" + mode + "'");
  if (!(target->af > 0.0) || peaks.size() < 2) return std::nullopt;
  return off / target->af;
}

Summary summarize(const Setup& setup, const std::vector<double>& currents_mA) {
  Field field(setup, currents_mA);
  Summary s;
  for (const auto& r : setup.receptors) s.peaks.emplace_back(r.name, field.peak(r));
  for (const auto& r : setup.receptors) s.ratios.emplace_back(r.name, mode_ratio(s.peaks, r.name));
  return s;
}

}  // namespace tp
