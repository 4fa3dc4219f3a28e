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
#include "io/number.hpp"
#include "model/ranges.hpp"
#include "opt/lp.hpp"

namespace tp {
namespace {

// The part of the array a pattern may use, and how a focus sits in it.
struct Window {
  Setup setup;                // the window's pads alone (a sub-grid centred on (0, 0))
  int c0 = 0, r0 = 0;         // its first column and row in the grid
  double wx = 0.0, wz = 0.0;  // its centre, in the array's coordinates
  double ox = 0.0, oz = 0.0;  // its centre, in its own coordinates
  bool mirror_x = false, mirror_z = false;  // reflections through its centre it admits
};

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

}  // namespace

Bank optimize_bank(const Setup& setup, const BankOptions& opt) {
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

  Bank bank;
  if (opt.at.empty()) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      bank.pixels.emplace_back(a.positions_mm[i], a.z_of(i));
      bank.pads.push_back(static_cast<long>(i));
    }
  } else {
    bank.pixels = opt.at;
    for (const auto& [x, z] : opt.at) bank.pads.push_back(pad_at(a, x, z));
  }
  const double count = static_cast<double>(bank.pixels.size()) * static_cast<double>(modes.size());
  if (count > static_cast<double>(kMaxBankPatterns))
    bad_input("bank: " + number_text(count) + " patterns (" + std::to_string(bank.pixels.size()) +
              " pixels x " + std::to_string(modes.size()) + " modes), more than " +
              std::to_string(kMaxBankPatterns));
  FocusOptions base;
  base.radius_mm = opt.radius_mm;
  base.spill = opt.spill;
  base.max_current_mA = opt.max_current_mA;
  for (const auto& [x, z] : bank.pixels) {
    FocusOptions f = base;
    f.x_mm = x;
    f.z_mm = z;
    check_focus(setup, f);
  }
  // The pitch and radius are the whole array's, whatever the window.
  if (base.radius_mm == 0.0) base.radius_mm = nominal_pitch_mm(a);

  // Reflections keep every receptor's fibres along their axes only when each is vertical or
  // runs along x or z.
  bool axes_ok = true;
  for (const Receptor& r : setup.receptors) {
    const FibreAxis ax = fibre_axis(r);
    if (!ax.vertical && std::fabs(ax.cos_az * ax.sin_az) > 1e-12) axes_ok = false;
  }

  // Each pixel's window.
  auto window_of = [&](double x, double z) {
    Window w;
    if (k == 0) {
      w.setup = setup;
      w.ox = w.wx = 0.5 * (a.x_min_mm() + a.x_max_mm());
      w.oz = w.wz = a.two_d() ? 0.5 * (a.z_min_mm() + a.z_max_mm()) : 0.0;
    } else {
      const int nc = std::min(k, a.columns), nr = std::min(k, a.rows);
      const double pitch = *a.pitch_mm;
      const double x00 = a.positions_mm.front(), z00 = a.z_mm.front();
      const int col =
          std::clamp(static_cast<int>(std::lround((x - x00) / pitch)), 0, a.columns - 1);
      const int row =
          std::clamp(static_cast<int>(std::lround((z - z00) / a.row_pitch_mm)), 0, a.rows - 1);
      w.c0 = std::clamp(col - k / 2, 0, a.columns - nc);
      w.r0 = std::clamp(row - k / 2, 0, a.rows - nr);
      w.setup = setup;
      w.setup.array =
          ElectrodeArray::grid_of(nc, nr, pitch, a.row_pitch_mm, a.width_mm, a.length_mm);
      w.wx = x00 + (w.c0 + 0.5 * (nc - 1)) * pitch;
      w.wz = z00 + (w.r0 + 0.5 * (nr - 1)) * a.row_pitch_mm;
    }
    const ElectrodeArray& wa = w.setup.array;
    w.mirror_x = axes_ok && symmetric(wa, true, false, w.ox, w.oz);
    w.mirror_z = axes_ok && wa.two_d() && symmetric(wa, false, true, w.ox, w.oz);
    return w;
  };

  // The distinct problems: a window's size and the focus's place in it, reflected into the
  // quadrant x <= centre, z <= centre where the window admits it.
  struct Problem {
    Window window;
    std::string mode;
    FocusOptions focus;  // in the window's coordinates
    std::size_t first;   // the first pattern that needs it
    FocusResult result;
    bool feasible = true;
    FocusFailure why;  // in the window's coordinates
  };
  std::vector<Problem> problems;
  std::map<std::tuple<std::string, int, int, long long, long long>, std::size_t> index;
  std::vector<std::size_t> problem_of;
  std::vector<Window> windows;  // per pattern
  for (std::size_t p = 0; p < bank.pixels.size(); ++p) {
    const auto [x, z] = bank.pixels[p];
    for (const std::string& mode : modes) {
      Window w = window_of(x, z);
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
        index.emplace(key, problems.size());
        problem_of.push_back(problems.size());
        problems.push_back(std::move(pr));
        pat.solved = true;
      } else {
        problem_of.push_back(it->second);
      }
      pat.from = problems[problem_of.back()].first;
      windows.push_back(std::move(w));
      bank.patterns.push_back(std::move(pat));
    }
  }
  bank.solves = static_cast<int>(problems.size());
  const unsigned threads =
      opt.threads ? opt.threads : std::max(1u, std::thread::hardware_concurrency());

  // How far it has come, for opt.progress: counted and told one thread at a time.
  BankProgress progress;
  progress.problems = problems.size();
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
      problems.size(), threads,
      [&](std::size_t i) {
        Problem& pr = problems[i];
        auto r = try_optimize_focus(pr.window.setup, pr.mode, pr.focus, pr.why);
        pr.feasible = r.has_value();
        if (r) pr.result = std::move(*r);
        advance(&BankProgress::solved);
      },
      release_lp_thread);

  // Every pattern: the solution reflected and placed in its window, judged on the array.
  parallel_for(bank.patterns.size(), threads, [&](std::size_t i) {
    BankPattern& pat = bank.patterns[i];
    const Problem& pr = problems[problem_of[i]];
    const Window& w = windows[i];
    FocusOptions f = base;
    f.x_mm = bank.pixels[pat.pixel].first;
    f.z_mm = bank.pixels[pat.pixel].second;
    // A place in the window's coordinates, in the array's (reflected as the pattern is).
    auto place = [&](double& x, double& z) {
      x = w.wx + (pat.mirror_x ? -(x - w.ox) : x - w.ox);
      z = w.wz + (pat.mirror_z ? -(z - w.oz) : z - w.oz);
    };
    if (!pr.feasible) {
      pat.feasible = false;
      FocusFailure why = pr.why;
      place(why.peak_x_mm, why.peak_z_mm);
      pat.reason = focus_failure_text(setup, pat.mode, f, why);
      advance(&BankProgress::judged);
      return;
    }
    const ElectrodeArray& wa = w.setup.array;
    std::vector<double> weights(a.size(), 0.0);
    for (std::size_t j = 0; j < wa.size(); ++j) {
      const long mi = mirrored(wa, j, pat.mirror_x, pat.mirror_z, w.ox, w.oz);
      if (mi < 0) failure("bank: a reflection has no pad");  // symmetric() was checked
      const auto m = static_cast<std::size_t>(mi);
      std::size_t full = m;
      if (k != 0) {
        const int c = static_cast<int>(m) % wa.columns, r = static_cast<int>(m) / wa.columns;
        full = static_cast<std::size_t>((w.r0 + r) * a.columns + w.c0 + c);
      }
      weights[full] = pr.result.weights[j];
    }
    if (pat.solved && k == 0 && !pat.mirror_x && !pat.mirror_z) {
      pat.result = pr.result;  // solved on the array itself, as it is: its own check
    } else {
      pat.result = evaluate_focus(setup, pat.mode, f, weights);
      if (pat.solved) {  // the solver's account of the window's problem
        pat.result.sampled_optimum = pr.result.sampled_optimum;
        pat.result.samples = pr.result.samples;
        pat.result.lp_solves = pr.result.lp_solves;
        pat.result.rounds = pr.result.rounds;
        pat.result.least_norm = pr.result.least_norm;
      }
    }
    advance(&BankProgress::judged);
  });
  return bank;
}

}  // namespace tp
