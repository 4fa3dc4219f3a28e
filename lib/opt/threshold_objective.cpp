// Nelder-Mead over the weights' zero-sum subspace (threshold_objective.hpp).

#include "opt/threshold_objective.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "core/error.hpp"
#include "core/number.hpp"
#include "model/conductor.hpp"
#include "opt/nelder_mead.hpp"
#include "opt/threshold_standin.hpp"

namespace tp::fibre {

namespace {
// The objective of thresholds t_mA (+infinity: none): the target's over the lowest other's,
// a missing other counting as max_mA, a missing target as +infinity.
double objective_of(const std::vector<double>& t_mA, std::size_t target, double max_mA) {
  if (!std::isfinite(t_mA[target])) return std::numeric_limits<double>::infinity();
  double other = max_mA;
  for (std::size_t k = 0; k < t_mA.size(); ++k)
    if (k != target) other = std::min(other, t_mA[k]);
  return t_mA[target] / other;
}
}  // namespace

double threshold_objective(const ThresholdReport& r, std::size_t target, double max_mA) {
  std::vector<double> t;
  for (const ReceptorThreshold& x : r.receptors)
    t.push_back(x.threshold_mA.value_or(std::numeric_limits<double>::infinity()));
  return objective_of(t, target, max_mA);
}

namespace {
std::string objective_text(const ThresholdReport& r, std::size_t target, double max_mA) {
  const double f = threshold_objective(r, target, max_mA);
  if (!std::isfinite(f)) return "none";
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", f);
  return b;
}
}  // namespace

std::string threshold_search_summary(const ThresholdOptimum& t, std::size_t target, double max_mA) {
  const std::string& name = t.report.receptors[target].receptor;
  const std::string result = objective_text(t.report, target, max_mA);
  const std::string start = objective_text(t.start, target, max_mA);
  const std::string none = name + " has no threshold below " + number_text(max_mA) + " mA";
  if (result == "none") return name + " threshold ratio none (" + none + ", nor at the AF optimum)";
  return name + " threshold ratio " + result + " (AF optimum: " + start +
         (start == "none" ? ", where " + none : std::string()) + ")";
}


void check_search_work(const Setup& setup, const FibreModel& model, const PulseSpec& pulse,
                       const ThresholdSettings& settings, const ThresholdSearchOptions& opt) {
  // The whole search's work, bounded before any of it: every evaluation is one
  // compute_thresholds() of the same fibres.
  check_threshold_work(
      thresholds_work(setup, model, pulse, settings) *
          static_cast<double>(std::max<std::size_t>(opt.max_evaluations, 1)),
      kMaxSearchWork,
      "--objective threshold (" + std::to_string(opt.max_evaluations) + " evaluations)",
      "fewer --max-evaluations, a larger --tolerance, fewer --offsets, a shorter array, margin "
      "or pulse");
}

namespace {

// Stand-in evaluations per free weight in a round (optimize_threshold).
constexpr std::size_t kGuesses = 30;

}  // namespace

ThresholdOptimum optimize_threshold(const Setup& setup, std::size_t target,
                                    const std::vector<double>& af, const FibreModel& model,
                                    const PulseSpec& pulse, const ThresholdSettings& settings,
                                    const ThresholdSearchOptions& opt) {
  const std::size_t n = af.size();
  if (n < 2) bad_input("array: optimisation needs at least 2 electrodes");
  check_search_work(setup, model, pulse, settings, opt);
  PotentialCache cache;
  ThresholdOptimum out;
  out.start = compute_thresholds(setup, af, model, pulse, settings, &cache);
  out.evaluations = 1;
  if (opt.progress) opt.progress(out.evaluations);
  const double f0 = threshold_objective(out.start, target, settings.max_mA);
  // The best weights a whole search has seen (z: the free weights).
  std::vector<double> best_z(af.begin(), af.end() - 1), best_w = af;
  ThresholdReport best_r = out.start;
  double best_f = f0;
  // A whole search at z, started from the best's thresholds (nearby weights, nearby
  // thresholds: less work, the same answer); keeps the best.
  auto search = [&](const std::vector<double>& z, ThresholdReport& r) {
    const std::vector<double> w = zero_sum_weights(z);
    if (w.empty()) return std::numeric_limits<double>::infinity();
    ThresholdSettings near = settings;
    near.start_mA.clear();
    for (const ReceptorThreshold& t : best_r.receptors)
      near.start_mA.push_back(t.threshold_mA.value_or(0.0));
    r = compute_thresholds(setup, w, model, pulse, near, &cache);
    r.settings.start_mA.clear();
    ++out.evaluations;
    if (opt.progress) opt.progress(out.evaluations);
    const double f = threshold_objective(r, target, settings.max_mA);
    if (f < best_f) {
      best_f = f;
      best_z = z;
      best_w = w;
      best_r = r;
    }
    return f;
  };

  // 1. Rounds on the stand-ins (threshold_standin.hpp: LinearStandIn), each calibrated by
  //    the whole searches so far: Nelder-Mead on the stand-ins' ratio from the best
  //    (kGuesses x n - 1 stand-in evaluations at most), then a whole search at its best.  A
  //    round that finds nothing better halves the first simplex's step; the rounds end
  //    below 1/16 of it.
  const std::size_t m = setup.receptors.size();
  const auto conductor = make_conductor(setup.conductor, setup.array);
  const Waveform waveform = waveform_of(pulse, settings.delay_ms);
  ThresholdSettings fine = settings;
  fine.dt_ms = 0.005;  // as compute_thresholds()
  std::vector<LinearStandIn> stand;
  for (std::size_t k = 0; k < m; ++k)
    stand.emplace_back(model, setup, *conductor, setup.receptors[k], waveform, fine);
  auto calibrate = [&](const ThresholdReport& r, const std::vector<double>& w) {
    for (std::size_t k = 0; k < m; ++k) stand[k].calibrate(r.receptors[k], w, cache);
  };
  calibrate(out.start, af);
  std::size_t guesses = 0;
  std::vector<double> guide_z;
  double guide_f = 0.0;
  auto guess = [&](const std::vector<double>& z) {
    ++guesses;
    const std::vector<double> w = zero_sum_weights(z);
    if (w.empty()) return std::numeric_limits<double>::infinity();
    std::vector<double> t(m);
    for (std::size_t k = 0; k < m; ++k) t[k] = stand[k].threshold_mA(w);
    // A stand-in's target above max_mA: none, as a whole search would find.
    if (!(t[target] <= settings.max_mA)) t[target] = std::numeric_limits<double>::infinity();
    const double f = objective_of(t, target, settings.max_mA);
    if (f < guide_f) {
      guide_f = f;
      guide_z = z;
    }
    return f;
  };
  auto guessed = [&] { return guesses; };
  for (double step = opt.initial_step;
       out.evaluations < opt.max_evaluations && step >= opt.initial_step / 16;) {
    guesses = 0;
    guide_z = best_z;
    guide_f = std::numeric_limits<double>::infinity();
    nelder_mead(best_z, guess(best_z), step, kGuesses * (n - 1), guess, guessed);
    if (guide_z == best_z) {
      step /= 2;
      continue;
    }
    const std::vector<double> z = guide_z;
    ThresholdReport r;
    const double before = best_f;
    search(z, r);
    ++out.rounds;
    calibrate(r, zero_sum_weights(z));
    if (!(best_f < before)) step /= 2;
  }

  // 2. Nelder-Mead on whole searches from the best, with the evaluations left (at least a
  //    first simplex's worth).
  if (out.evaluations + n <= opt.max_evaluations) {
    const std::vector<double> z0 = best_z;
    ThresholdReport scratch;
    nelder_mead(
        z0, best_f, opt.initial_step, opt.max_evaluations,
        [&](const std::vector<double>& z) { return search(z, scratch); },
        [&] { return out.evaluations; });
  }
  out.improved = best_f < f0;
  out.weights = out.improved ? best_w : af;
  out.report = out.improved ? std::move(best_r) : out.start;
  return out;
}

}  // namespace tp::fibre
