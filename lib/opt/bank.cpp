#include "opt/bank.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "opt/lp.hpp"

namespace tp {
namespace {

// The pad at (x, z) (to 1e-9 mm), or -1.
long pad_at(const ElectrodeArray& a, double x, double z) {
  for (std::size_t j = 0; j < a.size(); ++j)
    if (std::fabs(a.positions_mm[j] - x) < 1e-9 && std::fabs(a.z_of(j) - z) < 1e-9)
      return static_cast<long>(j);
  return -1;
}

// The pad at the reflection of pad i's place through (ox, oz), or -1.
long mirrored(const ElectrodeArray& a, std::size_t i, bool mx, bool mz, double ox, double oz) {
  return pad_at(a, mx ? 2 * ox - a.positions_mm[i] : a.positions_mm[i],
                mz ? 2 * oz - a.z_of(i) : a.z_of(i));
}

// A reflection through (ox, oz) maps the pads onto themselves.
bool symmetric(const ElectrodeArray& a, bool mx, bool mz, double ox, double oz) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (mirrored(a, i, mx, mz, ox, oz) < 0) return false;
  return true;
}

// A distinct problem: a window's size and the focus's place in it, reflected into the
// quadrant x <= centre, z <= centre where the window admits it.
struct Problem {
  BankWindow window;
  std::string mode;
  FocusOptions focus;  // in the window's coordinates
  std::size_t first;   // the first pattern that needs it
  FocusResult result;
  bool feasible = true;
  FocusFailure why;  // in the window's coordinates
};

// The bank's plan: its patterns (pixel-major), each one's problem and window.
struct Plan {
  std::vector<Problem> problems;
  std::vector<std::size_t> problem_of;  // per pattern
  std::vector<BankWindow> windows;      // per pattern
};

// The modes, checked against the options and the array (bad input).
std::vector<std::string> checked_modes(const Setup& setup, const BankOptions& opt) {
  const ElectrodeArray& a = setup.array;
  const int k = opt.neighbourhood;
  if (k != 0 && !a.grid())
    bad_input("--neighbourhood: needs a grid (array.grid); " + a.describe() + " is not one");
  if (k != 0 && (k < 3 || k >= ranges::max_grid_side || k % 2 == 0))
    bad_input("--neighbourhood: " + std::to_string(k) + " is not odd within [3, " +
              std::to_string(ranges::max_grid_side - 1) +
              "] (K x K pads centred on the focus's pad; 0: every pad)");
  if (a.size() < 2) bad_input("optimisation needs at least 2 electrodes");
  std::vector<std::string> modes = opt.modes;
  if (modes.empty())
    for (const Receptor& r : setup.receptors) modes.push_back(r.name);
  for (const std::string& m : modes) receptor_index(setup, m);
  return modes;
}

// The bank's pixels (every pad's centre, or opt.at) and their pads, each focus checked
// (bad input), the patterns at most kMaxBankPatterns.
void place_pixels(const Setup& setup, const BankOptions& opt, std::size_t modes, Bank& bank) {
  const ElectrodeArray& a = setup.array;
  if (opt.at.empty()) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      bank.pixels.emplace_back(a.positions_mm[i], a.z_of(i));
      bank.pads.push_back(static_cast<long>(i));
    }
  } else {
    bank.pixels = opt.at;
    for (const auto& [x, z] : opt.at) bank.pads.push_back(pad_at(a, x, z));
  }
  const double count = static_cast<double>(bank.pixels.size()) * static_cast<double>(modes);
  if (count > static_cast<double>(kMaxBankPatterns))
    bad_input("bank: " + number_text(count) + " patterns (" + std::to_string(bank.pixels.size()) +
              " pixels x " + std::to_string(modes) + " modes), more than " +
              std::to_string(kMaxBankPatterns));
  FocusOptions f;
  f.radius_mm = opt.radius_mm;
  f.spill = opt.spill;
  f.max_current_mA = opt.max_current_mA;
  for (const auto& [x, z] : bank.pixels) {
    f.x_mm = x;
    f.z_mm = z;
    check_focus(setup, f);
  }
}

// Every pattern (bank.patterns filled) and the distinct problems they need.
Plan plan_problems(const Setup& setup, const BankOptions& opt,
                   const std::vector<std::string>& modes, const FocusOptions& base, Bank& bank) {
  Plan plan;
  std::map<std::tuple<std::string, int, int, long long, long long>, std::size_t> index;
  for (std::size_t p = 0; p < bank.pixels.size(); ++p) {
    const auto [x, z] = bank.pixels[p];
    for (const std::string& mode : modes) {
      BankWindow w = bank_window(setup, opt.neighbourhood, x, z);
      // The focus relative to the window's centre (a rounding's worth from it: on it).
      double fx = x - w.wx, fz = z - w.wz;
      if (std::fabs(fx) < 1e-9) fx = 0.0;
      if (std::fabs(fz) < 1e-9) fz = 0.0;
      BankPattern pat;
      pat.pixel = p;
      pat.mode = mode;
      pat.mirror_x = w.mirror_x && fx > 1e-9;
      pat.mirror_z = w.mirror_z && fz > 1e-9;
      if (pat.mirror_x) fx = -fx;
      if (pat.mirror_z) fz = -fz;
      const auto key = std::make_tuple(mode, w.setup.array.columns, w.setup.array.rows,
                                       std::llround(fx * 1e9), std::llround(fz * 1e9));
      const auto it = index.find(key);
      if (it == index.end()) {
        Problem pr;
        pr.window = w;
        pr.mode = mode;
        pr.focus = base;
        pr.focus.x_mm = w.ox + fx;
        pr.focus.z_mm = w.oz + fz;
        pr.first = bank.patterns.size();
        index.emplace(key, plan.problems.size());
        plan.problem_of.push_back(plan.problems.size());
        plan.problems.push_back(std::move(pr));
        pat.solved = true;
      } else {
        plan.problem_of.push_back(it->second);
      }
      pat.from = plan.problems[plan.problem_of.back()].first;
      plan.windows.push_back(std::move(w));
      bank.patterns.push_back(std::move(pat));
    }
  }
  return plan;
}

// Pattern `pat`: its problem's solution reflected and placed in its window, judged on the
// whole array (or the reason it has none, named at the pixel's own place).
void judge_pattern(const Setup& setup, const FocusOptions& base, const Problem& pr,
                   const BankWindow& w, const std::pair<double, double>& pixel, BankPattern& pat) {
  FocusOptions f = base;
  f.x_mm = pixel.first;
  f.z_mm = pixel.second;
  if (!pr.feasible) {
    pat.feasible = false;
    FocusFailure why = pr.why;
    // The peak's place in the window's coordinates, in the array's (reflected as the
    // pattern is).
    why.peak_x_mm = w.wx + (pat.mirror_x ? -(why.peak_x_mm - w.ox) : why.peak_x_mm - w.ox);
    why.peak_z_mm = w.wz + (pat.mirror_z ? -(why.peak_z_mm - w.oz) : why.peak_z_mm - w.oz);
    pat.reason = focus_failure_text(setup, pat.mode, f, why);
    return;
  }
  const std::vector<double> weights =
      weights_on_array(setup.array, w, pat.mirror_x, pat.mirror_z, pr.result.weights);
  if (pat.solved && !w.sub_grid && !pat.mirror_x && !pat.mirror_z) {
    pat.result = pr.result;  // solved on the array itself, as it is: its own check
    return;
  }
  pat.result = evaluate_focus(setup, pat.mode, f, weights);
  if (pat.solved) {  // the solver's account of the window's problem
    pat.result.sampled_optimum = pr.result.sampled_optimum;
    pat.result.samples = pr.result.samples;
    pat.result.lp_solves = pr.result.lp_solves;
    pat.result.rounds = pr.result.rounds;
    pat.result.least_norm = pr.result.least_norm;
  }
}

}  // namespace

BankWindow bank_window(const Setup& setup, int k, double x, double z) {
  const ElectrodeArray& a = setup.array;
  // Reflections keep every receptor's fibres along their axes only when each is vertical or
  // runs along x or z.
  bool axes_ok = true;
  for (const Receptor& r : setup.receptors) {
    const FibreAxis ax = fibre_axis(r);
    if (!ax.vertical && std::fabs(ax.cos_az * ax.sin_az) > 1e-12) axes_ok = false;
  }
  BankWindow w;
  if (k == 0) {
    w.setup = setup;
    w.ox = w.wx = 0.5 * (a.x_min_mm() + a.x_max_mm());
    w.oz = w.wz = a.two_d() ? 0.5 * (a.z_min_mm() + a.z_max_mm()) : 0.0;
  } else {
    if (!a.grid() || !a.pitch_mm) failure("bank: a neighbourhood needs a grid");
    const int nc = std::min(k, a.columns), nr = std::min(k, a.rows);
    const double pitch = *a.pitch_mm;
    const double x00 = a.positions_mm.front(), z00 = a.z_mm.front();
    const int col = std::clamp(static_cast<int>(std::lround((x - x00) / pitch)), 0, a.columns - 1);
    const int row =
        std::clamp(static_cast<int>(std::lround((z - z00) / a.row_pitch_mm)), 0, a.rows - 1);
    w.c0 = std::clamp(col - k / 2, 0, a.columns - nc);
    w.r0 = std::clamp(row - k / 2, 0, a.rows - nr);
    w.setup = setup;
    w.setup.array = ElectrodeArray::grid_of(nc, nr, pitch, a.row_pitch_mm, a.width_mm, a.length_mm);
    w.wx = x00 + (w.c0 + 0.5 * (nc - 1)) * pitch;
    w.wz = z00 + (w.r0 + 0.5 * (nr - 1)) * a.row_pitch_mm;
    w.sub_grid = true;
  }
  const ElectrodeArray& wa = w.setup.array;
  w.mirror_x = axes_ok && symmetric(wa, true, false, w.ox, w.oz);
  w.mirror_z = axes_ok && wa.two_d() && symmetric(wa, false, true, w.ox, w.oz);
  return w;
}

std::vector<double> weights_on_array(const ElectrodeArray& a, const BankWindow& w, bool mirror_x,
                                     bool mirror_z, const std::vector<double>& window_weights) {
  const ElectrodeArray& wa = w.setup.array;
  if (window_weights.size() != wa.size()) failure("bank: weights for another window");
  std::vector<double> weights(a.size(), 0.0);
  for (std::size_t j = 0; j < wa.size(); ++j) {
    const long mi = mirrored(wa, j, mirror_x, mirror_z, w.ox, w.oz);
    if (mi < 0) failure("bank: a reflection has no pad");  // symmetric() was checked
    const auto m = static_cast<std::size_t>(mi);
    std::size_t full = m;
    if (w.sub_grid) {
      const int c = static_cast<int>(m) % wa.columns, r = static_cast<int>(m) / wa.columns;
      full = static_cast<std::size_t>((w.r0 + r) * a.columns + w.c0 + c);
    }
    weights[full] = window_weights[j];
  }
  return weights;
}

Bank optimize_bank(const Setup& setup, const BankOptions& opt) {
  const std::vector<std::string> modes = checked_modes(setup, opt);
  Bank bank;
  place_pixels(setup, opt, modes.size(), bank);
  FocusOptions base;
  base.radius_mm = opt.radius_mm;
  base.spill = opt.spill;
  base.max_current_mA = opt.max_current_mA;
  // The pitch and radius are the whole array's, whatever the window.
  if (base.radius_mm == 0.0) base.radius_mm = nominal_pitch_mm(setup.array);
  Plan plan = plan_problems(setup, opt, modes, base, bank);
  bank.solves = static_cast<int>(plan.problems.size());
  const unsigned threads =
      opt.threads ? opt.threads : std::max(1u, std::thread::hardware_concurrency());

  // How far it has come, for opt.progress: counted and told one thread at a time.
  BankProgress progress;
  progress.problems = plan.problems.size();
  progress.patterns = bank.patterns.size();
  std::mutex progress_mutex;
  auto advance = [&](std::size_t BankProgress::*counter) {
    if (!opt.progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    ++(progress.*counter);
    opt.progress(progress);
  };

  // Solve each problem; one no weights satisfy is reported, not thrown.
  parallel_for(
      plan.problems.size(), threads,
      [&](std::size_t i) {
        Problem& pr = plan.problems[i];
        auto r = try_optimize_focus(pr.window.setup, pr.mode, pr.focus, pr.why);
        pr.feasible = r.has_value();
        if (r) pr.result = std::move(*r);
        advance(&BankProgress::solved);
      },
      release_lp_thread);

  // Every pattern: the solution reflected and placed in its window, judged on the array.
  parallel_for(bank.patterns.size(), threads, [&](std::size_t i) {
    BankPattern& pat = bank.patterns[i];
    judge_pattern(setup, base, plan.problems[plan.problem_of[i]], plan.windows[i],
                  bank.pixels[pat.pixel], pat);
    advance(&BankProgress::judged);
  });
  return bank;
}

}  // namespace tp
