#include "opt/focus.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "core/error.hpp"
#include "core/number.hpp"
#include "opt/focus_check.hpp"
#include "opt/focus_solver.hpp"

namespace tp {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

double nominal_pitch_mm(const ElectrodeArray& a) {
  if (a.pitch_mm) return a.grid() ? std::min(*a.pitch_mm, a.row_pitch_mm) : *a.pitch_mm;
  double best = kInf;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j)
      best =
          std::min(best, std::hypot(a.positions_mm[i] - a.positions_mm[j], a.z_of(i) - a.z_of(j)));
  return std::isfinite(best) ? best : std::max(0.01, a.width_mm);
}

void check_focus(const Setup& s, const FocusOptions& o) {
  const ElectrodeArray& a = s.array;
  const double p = nominal_pitch_mm(a);
  if (!std::isfinite(o.x_mm) || !std::isfinite(o.z_mm)) bad_input("--at: not finite");
  if (o.x_mm < a.x_min_mm() - p || o.x_mm > a.x_max_mm() + p ||
      (a.two_d() && (o.z_mm < a.z_min_mm() - p || o.z_mm > a.z_max_mm() + p)))
    bad_input("--at: (" + number_text(o.x_mm) + (a.two_d() ? ", " + number_text(o.z_mm) : "") +
              ") mm lies outside the array's extent plus one pitch (x " +
              number_text(a.x_min_mm() - p) + " to " + number_text(a.x_max_mm() + p) +
              (a.two_d()
                   ? ", z " + number_text(a.z_min_mm() - p) + " to " + number_text(a.z_max_mm() + p)
                   : "") +
              " mm)");
  if (!(o.spill > 0.0 && o.spill <= 1.0))
    bad_input("--spill: " + number_beside(o.spill, 0.0, 1.0) + " outside (0, 1]");
  if (!(o.radius_mm >= 0.0 && o.radius_mm <= 1000.0))
    bad_input("--radius: " + number_beside(o.radius_mm, 0.0, 1000.0) + " mm outside (0, 1000] mm");
  if (o.radius_mm > 0.0 && !(o.radius_mm > p / 4))
    bad_input("--radius: " + number_beside(o.radius_mm, p / 4) +
              " mm is not beyond a quarter pitch (" + number_text(p / 4) +
              " mm), where the target's peak may lie");
}

std::string focus_failure_text(const Setup& setup, const std::string& mode, const FocusOptions& opt,
                               const FocusFailure& why) {
  const bool two_d = setup.array.two_d();
  const double radius = opt.radius_mm > 0.0 ? opt.radius_mm : nominal_pitch_mm(setup.array);
  const std::string place =
      "(" + number_text(opt.x_mm) + (two_d ? ", " + number_text(opt.z_mm) : "") + ") mm";
  const std::string no_weights = "no weights put receptor " + mode + "'s largest AF at the focus " +
                                 place + " with a spill of at most " + number_text(opt.spill) +
                                 " beyond " + number_text(radius) + " mm";
  switch (why.kind) {
    case FocusFailure::Kind::nowhere:
      return no_weights + ": no weights put its peak there at all";
    case FocusFailure::Kind::impossible:
      return no_weights + ": no spill up to 1 is possible (the least on the samples is " +
             number_text(why.value) + ": the peak itself cannot sit there)";
    case FocusFailure::Kind::least_spill:
      return no_weights + ": the least spill reachable is " + number_text(why.value) +
             " (on the samples: a lower bound)";
    case FocusFailure::Kind::caps:
      return no_weights + " on the continuous fibres: the least reached is " +
             number_text(why.value);
    case FocusFailure::Kind::rounds:
      break;
  }
  return "receptor " + mode + "'s pixel at " + place + ": after " + std::to_string(why.rounds) +
         " rounds its peak lies at (" + number_text(why.peak_x_mm) +
         (two_d ? ", " + number_text(why.peak_z_mm) : "") + ") mm and its spill is " +
         number_text(why.value) + " (at most " + number_text(opt.spill) +
         " asked); a larger --spill or --radius";
}

FocusResult optimize_focus(const Setup& setup, const std::string& mode, const FocusOptions& opt) {
  FocusFailure why;
  auto r = try_optimize_focus(setup, mode, opt, why);
  if (!r) failure(focus_failure_text(setup, mode, opt, why));
  return std::move(*r);
}

std::optional<FocusResult> try_optimize_focus(const Setup& setup, const std::string& mode,
                                              const FocusOptions& opt, FocusFailure& why) {
  const auto t0 = std::chrono::steady_clock::now();
  focus::Solver solver(setup, mode, opt);
  std::optional<FocusResult> res = solver.run(why);
  if (res)
    res->time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

FocusResult evaluate_focus(const Setup& setup, const std::string& mode, const FocusOptions& opt,
                           const std::vector<double>& weights) {
  const auto t0 = std::chrono::steady_clock::now();
  check_focus(setup, opt);
  const std::size_t target = receptor_index(setup, mode);
  const bool two_d = setup.array.two_d();
  FocusResult res;
  res.mode = mode;
  res.pitch_mm = nominal_pitch_mm(setup.array);
  res.radius_mm = opt.radius_mm > 0.0 ? opt.radius_mm : res.pitch_mm;
  res.weights = weights;
  for (double v : weights) res.currents_mA.push_back(v * opt.max_current_mA);
  {
    const auto c = make_conductor(setup.conductor, setup.array);
    check_fibre_reach(setup, *c);  // before any work
  }
  const auto [sum, far] =
      focus::check_pattern(setup, res.currents_mA, setup.receptors[target], opt, res.radius_mm);
  res.summary = sum;
  const Peak& tp_ = res.summary.peaks[target].second;
  res.target_max_af = tp_.af;
  res.target_depth_mm = tp_.y_mm;
  res.spill = res.target_max_af > 0.0 ? std::max(0.0, far.af) / res.target_max_af : kInf;
  const auto ratio = mode_ratio(res.summary.peaks, mode);
  res.ratio = ratio ? *ratio : kInf;
  res.bounds_hold = focus::lateral(opt, two_d, tp_.x_mm, tp_.z_mm) <= res.pitch_mm / 4.0 &&
                    res.spill <= opt.spill * (1 + focus::kCheckSpill);
  res.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace tp
