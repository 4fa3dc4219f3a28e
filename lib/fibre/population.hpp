#pragma once
// Populations of afferents (issue 24; docs/fibres.md, "Populations and recruitment"): N
// afferents of each class sampled over the array and its margin, each one fibre with its
// own diameter, depth and place, each its own threshold; the fraction of each class
// recruited at a current, and a selectivity index per mode.
//
// A threshold is linear in the weights' scale (the lattice, threshold.hpp), so one search
// per fibre serves every amplitude: the recruitment curve at any current is read off the
// thresholds.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fibre/models.hpp"
#include "fibre/report.hpp"
#include "model/field.hpp"

namespace tp::fibre {

// What is sampled for one class of afferent, and from where.
struct AfferentClass {
  std::string receptor;  // the setup's receptor: its orientation (and the vertical bottom)
  double density_per_cm2 = 0;
  double diameter_min_um = 0, diameter_max_um = 0;
  double depth_min_mm = 0, depth_max_mm = 0;  // horizontal: the depth; vertical: the top
};

// The defaults for RA, SAI and PC (docs/fibres.md cites each):
//  - densities at the fingertip, units per cm^2: RA 140, SAI 70, PC 25 (Johansson and
//    Vallbo, J. Physiol. 286:283-300, 1979, as issue 24 and TouchSim use them);
//  - fibre diameters, um: RA 3 to 5, SAI 7 to 12, PC 5 to 13 (the seed paper's Table 1);
//  - depths, mm: RA's top 0.7 and SAI 0.9 (Table 1, one value each); PC 2.0 to 3.0 (Table 1
//    gives "2.0 ~", from 2.0 down; 3.0 is our assumption, within the subcutis).
std::vector<AfferentClass> default_afferent_classes();

// The most afferents of a class (fiber-threshold --population); the work bound
// (kMaxThresholdWork) may refuse fewer.
inline constexpr long kMaxPopulation = 10000;

// What one population's searches leave for the next over the same afferents (a design that
// evaluates many weights and pulses on one population): each afferent's unit potentials
// (they do not depend on the weights or the pulse) and its last threshold, where the next
// search starts (the answer does not depend on it, only the work does).
struct PopulationMemo {
  std::vector<PotentialCache> caches;  // per afferent; sized by the first use
  std::vector<double> start_mA;        // per afferent; 0: none
};

struct PopulationOptions {
  std::size_t per_class = 100;  // 1 to kMaxPopulation
  std::uint64_t seed = 1;
  unsigned threads = 0;  // fibres searched at once; 0: every core
  // Called as each afferent's search ends, with the number ended and the number in all,
  // one call at a time (from the searching threads): a program's progress line.
  std::function<void(std::size_t done, std::size_t total)> progress;
  // Kept between calls with the same setup, seed and classes (each afferent the same
  // fibre); null: none.
  PopulationMemo* memo = nullptr;
  // 2-D arrays: where the afferents are placed, x0, x1, z0, z1 (mm; x0 < x1, z0 < z1), in
  // place of the pads and the margin (a pixel's recruitment: the pitch around it, the bank's
  // colours, render/recruitment.hpp).  Bad input on a 1-D array.
  std::optional<std::array<double, 4>> region_mm;
};

struct Afferent {
  std::string receptor;
  bool vertical = false;
  double x_mm = 0;       // vertical: where the fibre is (horizontal: not used)
  double offset_mm = 0;  // horizontal: its nodes' alignment, [0, internode)
  double depth_mm = 0;   // horizontal: its depth; vertical: its top
  double diameter_um = 0;
  double z_mm =
      0;  // under a 2-D array: the fibre's z (a vertical one's place, a horizontal one's row)
  int stem = 0;
  bool at_cut_end =
      false;  // fired first at a cut end of its simulated fibre (threshold.hpp)  // an afferent
              // (ThresholdSettings::geometry): its stem toward -x (-1) or +x (+1)
  std::optional<double> threshold_mA;  // none: does not fire below max_mA
};

struct Population {
  std::vector<Afferent> afferents;  // per_class of each class, in the setup's receptor order
  std::vector<std::string> classes;
  double area_cm2 = 0;           // where they were placed
  bool two_d = false;            // over a 2-D array (x and z), else along a 1-D one
  std::vector<double> expected;  // each class's density x area
};

// Samples the afferents (a splitmix64 stream from `seed`: the same seed gives the same
// population on every machine) and finds each one's threshold for the weights (|w| = 1
// carries the amplitude).  1-D arrays only; bad input, before any work, when a class names
// no receptor of the setup, a range is empty or out of the model's range, or the work is
// beyond kMaxThresholdWork.
Population sample_population(const Setup& setup, const std::vector<double>& weights,
                             const FibreModel& model, const PulseSpec& pulse,
                             const ThresholdSettings& settings,
                             const std::vector<AfferentClass>& classes, const PopulationOptions& o);

// The estimated work of sample_population()'s searches (threshold_work()), with the same
// checks before it; no search.
double population_work(const Setup& setup, const FibreModel& model, const PulseSpec& pulse,
                       const ThresholdSettings& settings, const std::vector<AfferentClass>& classes,
                       const PopulationOptions& o);

// The recruitment curves: one row at 0 and at each distinct threshold (ascending), each
// class's fraction recruited at that current (threshold <= current), then each class's
// selectivity index there, SI_M = f_M - mean over the other classes of f_K (the index
// nerve-interface models report for a target fascicle against the others; docs/fibres.md
// says where it comes from).  Header:
// current_mA,recruited_<C>...,si_<C>...
std::string recruitment_csv(const Population& p);
// A mode's selectivity where half its target class is recruited (issue 40, item 3's
// objective; docs/fibres.md, "Selectivity at half recruitment"): I50 is the least current
// that recruits at least half of the target's afferents (a median of their thresholds),
// f_K each class's fraction recruited there, and the index 1 - 2 max over the other
// classes of f_K: 1 when no other afferent fires below I50 (the target fires first), 0
// when half of some other class does, -1 when all of one does.  The worst non-target
// (not the mean, as the recruitment curves' si_ columns) because "fires first" is lost to
// any one class.  None when fewer than half of the target fire, or it is not a class.
struct HalfSelectivity {
  double i50_mA = 0;
  std::vector<double> fraction;  // per class, at I50
  double index = 0;
  std::string worst;             // the non-target class most recruited at I50
};
std::optional<HalfSelectivity> selectivity_at_half(const Population& p, const std::string& target);

// The afferents, one row each: class,x_mm,offset_mm,depth_mm,diameter_um,threshold_mA
// (x_mm empty for horizontal fibres, offset_mm for vertical ones, threshold_mA when none).
std::string population_csv(const Population& p);

}  // namespace tp::fibre
