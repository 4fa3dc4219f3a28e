#pragma once
// A bank of pixels (issue 21): every pad centre's (or every given place's) focal pattern of
// each mode, the table a display renders from.
//
// Each pattern is a pixel (opt/focus.hpp) solved in a window of the array: the whole array,
// or with a neighbourhood of K (odd) the K x K pads centred on the pad nearest the focus
// (shifted to stay inside the array; the other pads carry nothing).  Windows of a uniform grid are
// alike up to translation, and a window symmetric under a mirror through its centre gives
// the mirror image's pattern for free: a pattern is solved once per distinct problem (its
// window's size and the focus's place in the window, up to those mirrors) and the others
// are derived from it by translation and reflection.  Every pattern, solved or derived, is
// then judged on the whole array (evaluate_focus): its ratio, peak and spill are those of
// the pattern as printed.

#include <functional>
#include <string>
#include <vector>

#include "opt/focus.hpp"

namespace tp {

// How far a bank has come: its distinct problems solved, then its patterns judged on the
// whole array (BankOptions::progress).
struct BankProgress {
  std::size_t solved = 0, problems = 0;
  std::size_t judged = 0, patterns = 0;
};

struct BankOptions {
  double radius_mm = 0.0;  // 0: one pitch
  double spill = 0.3;
  double max_current_mA = 2.0;
  std::vector<std::string> modes;  // empty: every receptor's
  // The foci (x_mm, z_mm); empty: every pad's centre.
  std::vector<std::pair<double, double>> at;
  int neighbourhood = 0;  // K (a grid; odd, 3 to 255); 0: every pad
  unsigned threads = 0;   // 0: every core
  // Called as each problem is solved and each pattern judged, one call at a time (from the
  // solving threads): a program's progress line.  Empty: none.
  std::function<void(const BankProgress&)> progress;
};

struct BankPattern {
  std::size_t pixel = 0;  // index into Bank::pixels
  std::string mode;
  bool feasible = true;  // else `reason` says why no weights satisfy the focus
  std::string reason;
  FocusResult result;                       // judged on the whole array (weights over every pad)
  bool solved = false;                      // else derived from pattern `from`'s solution
  std::size_t from = 0;                     // the pattern solved for this one's problem
  bool mirror_x = false, mirror_z = false;  // the reflections of the problem's solution
};

struct Bank {
  std::vector<std::pair<double, double>> pixels;  // the foci, mm
  std::vector<long> pads;                         // each focus's pad (-1: not a pad centre)
  std::vector<BankPattern> patterns;              // pixel-major, modes in the order given
  int solves = 0;                                 // problems solved
};

// Bad input (exit 2) for a focus check_focus() refuses, a neighbourhood on an array that
// is not a grid or not odd within [3, 255], more than kMaxBankPatterns patterns; a pattern whose
// focus no weights satisfy is reported (feasible = false), not thrown.
Bank optimize_bank(const Setup& setup, const BankOptions& opt);

inline constexpr std::size_t kMaxBankPatterns = 4096;

// optimize_bank's steps, exposed for the unit tests.

// The part of the array a pattern may use, and how a focus sits in it.
struct BankWindow {
  Setup setup;                // the window's pads alone (a sub-grid centred on (0, 0))
  int c0 = 0, r0 = 0;         // its first column and row in the grid
  double wx = 0.0, wz = 0.0;  // its centre, in the array's coordinates
  double ox = 0.0, oz = 0.0;  // its centre, in its own coordinates
  bool mirror_x = false, mirror_z = false;  // reflections through its centre it admits
  bool sub_grid = false;                    // K x K pads of a grid, else the whole array
};

// The window of a focus at (x_mm, z_mm): the whole array (neighbourhood 0), or the K x K
// pads (fewer where the grid has fewer) centred on the pad nearest the focus, shifted to
// stay inside the grid.  It admits a mirror when the reflection through its centre maps
// its pads onto themselves and every receptor's fibres are vertical or run along x or z.
BankWindow bank_window(const Setup& setup, int neighbourhood, double x_mm, double z_mm);

// A window's weights (one per window pad) on the whole array: reflected through the
// window's centre (mirror_x, mirror_z), each at its pad of the array, zero elsewhere.
std::vector<double> weights_on_array(const ElectrodeArray& array, const BankWindow& w,
                                     bool mirror_x, bool mirror_z,
                                     const std::vector<double>& window_weights);

}  // namespace tp
