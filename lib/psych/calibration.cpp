#include "psych/calibration.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "io/number.hpp"
#include "model/ranges.hpp"

namespace tp {

void check_calibration_options(const CalibrationOptions& o, const PixelBank& bank) {
  check_staircase_options(o.staircase);
  if (!(o.trial_s >= 0.05 && o.trial_s <= 10))
    bad_input("--trial-duration: " + number_beside(o.trial_s, 0.05, 10) +
              " s outside [0.05, 10] s");
  RenderOptions r;  // the rates and widths as render-tactile checks them
  r.rate_hz = o.rate_hz;
  r.width_us = o.width_us;
  r.balance_width_us = o.balance_width_us;
  check_render_options(r);
  if (bank.pads() > static_cast<std::size_t>(ranges::max_channels))
    bad_input("bank: " + std::to_string(bank.pads()) + " pads, more than a stimulator drives (" +
              std::to_string(ranges::max_channels) + ")");
  if (o.pads.empty()) bad_input("calibrate: no pixel to measure");
  for (const long pad : o.pads)
    if (pad < 0 || static_cast<std::size_t>(pad) >= bank.pads())
      bad_input("--pixel: pad " + std::to_string(pad) + " is not one of the bank's " +
                std::to_string(bank.pads()));
  for (const int p : o.primaries)
    if (p < 0 || p > 2) bad_input("--primaries: not a primary");
  if (o.staircase.ceiling_mA > bank.doc.max_current_mA)
    bad_input("--ceiling: " + number_beside(o.staircase.ceiling_mA, bank.doc.max_current_mA) +
              " mA is above the bank's current limit, " + number_text(bank.doc.max_current_mA) +
              " mA");
}

Calibration::Calibration(const PixelBank& bank, const CalibrationOptions& o)
    : bank_(bank), o_(o), stair_(o.staircase) {
  check_calibration_options(o, bank);
  std::vector<int> primaries = o.primaries;
  if (primaries.empty()) primaries = {0, 1, 2};
  for (const long pad : o.pads)
    for (const int p : primaries) {
      const BankEntry& e = bank.entry[static_cast<std::size_t>(pad)][static_cast<std::size_t>(p)];
      const int c = static_cast<int>(pad % bank.columns), r = static_cast<int>(pad / bank.columns);
      const std::string where = std::string(kPrimaries[static_cast<std::size_t>(p)]) +
                                " at pixel (" + std::to_string(c) + ", " + std::to_string(r) + ")";
      if (!e.present) {
        if (!o.primaries.empty()) bad_input(where + ": the bank has no patterns of that mode");
        continue;
      }
      if (!e.feasible) {
        if (o.pads.size() == 1 && !o.primaries.empty())
          bad_input(where + ": the bank could not find its pattern: " + e.reason);
        notes_.push_back(where + ": no pattern in the bank, not measured");
        continue;
      }
      units_.push_back({pad, p, false, PrimaryRange{}});
    }
  if (units_.empty()) bad_input("calibrate: no pattern to measure at the pixels given");
  // Every trial a unit may give, checked before anything is sent: its stimulus at the
  // ceiling (each limit grows with the level: current, charge, RMS and mean).
  for (std::size_t u = 0; u < units_.size(); ++u) trial_stimulus(u, o.staircase.ceiling_mA);
  start_threshold();
}

void Calibration::start_threshold() {
  comfort_ = false;
  unit_trials_ = 0;
  stair_ = Staircase(o_.staircase);
}

Mix Calibration::stimulus() const {
  return trial_stimulus(unit_, stair_.level_mA());
}

Mix Calibration::trial_stimulus(std::size_t unit, double level) const {
  const Unit& u = units_[unit];
  const BankEntry& e =
      bank_.entry[static_cast<std::size_t>(u.pad)][static_cast<std::size_t>(u.primary)];
  Stimulus s;
  for (const double w : e.weights) s.currents_mA.push_back(level * w);
  s.shape.width_us = o_.width_us;
  s.shape.balance_width_us = o_.balance_width_us;
  s.shape.frequency_hz = o_.rate_hz[static_cast<std::size_t>(u.primary)];
  s.count = std::max(1L, std::lround(o_.trial_s * s.shape.frequency_hz));
  s.amplitude_mA = level;
  s.electrode_area_mm2 = bank_.pad_area_mm2;
  StimulusLimits limits;  // the bank's current limit, where it is lower
  limits.max_current_mA = std::min(limits.max_current_mA, bank_.doc.max_current_mA);
  s.max_current_mA = limits.max_current_mA;
  s.carried = {{"primary", kPrimaries[static_cast<std::size_t>(u.primary)]},
               {"pixels", Json::array({u.pad})}};
  Mix m;
  m.patterns.push_back(s);
  check_mix(m, limits);
  return m;
}

void Calibration::respond(bool yes) {
  if (done()) return;
  CalibrationTrial t;
  t.n = static_cast<int>(trials_.size()) + 1;
  t.primary = units_[unit_].primary;
  t.pad = units_[unit_].pad;
  t.comfort = comfort_;
  t.level_mA = stair_.level_mA();
  stair_.respond(yes);
  t.ascending = stair_.trials().back().ascending;
  t.yes = yes;
  t.reversal = stair_.trials().back().reversal;
  trials_.push_back(t);
  ++unit_trials_;
  if (!stair_.done()) return;
  Unit& u = units_[unit_];
  const int c = static_cast<int>(u.pad % bank_.columns),
            r = static_cast<int>(u.pad / bank_.columns);
  const std::string where = std::string(kPrimaries[static_cast<std::size_t>(u.primary)]) +
                            " at pixel (" + std::to_string(c) + ", " + std::to_string(r) + ")";
  if (!comfort_) {
    if (!stair_.found()) {
      notes_.push_back(where + ": no threshold found up to the ceiling, " +
                       number_text(o_.staircase.ceiling_mA) + " mA; left out of the profile");
      finish_unit();
      return;
    }
    u.range.threshold_mA = stair_.estimate_mA();
    u.range.threshold_spread_mA = stair_.spread_mA();
    u.range.trials = unit_trials_;
    // The comfort limit, from the threshold up: "too strong?", 1-down-1-up.
    StaircaseOptions c_opt = o_.staircase;
    c_opt.down = 1;
    c_opt.start_mA = std::clamp(u.range.threshold_mA, kMinLevel_mA, c_opt.ceiling_mA);
    comfort_ = true;
    unit_trials_ = 0;
    stair_ = Staircase(c_opt);
    return;
  }
  u.found = true;
  u.range.trials += unit_trials_;
  if (stair_.found()) {
    u.range.comfort_mA = stair_.estimate_mA();
    u.range.comfort_spread_mA = stair_.spread_mA();
  } else {
    u.range.comfort_mA = o_.staircase.ceiling_mA;
    notes_.push_back(where + ": never too strong up to the ceiling; comfort set to it, " +
                     number_text(o_.staircase.ceiling_mA) + " mA");
  }
  if (u.range.comfort_mA < u.range.threshold_mA) {
    notes_.push_back(where + ": comfort " + number_text(u.range.comfort_mA) +
                     " mA came out below the threshold; set to the threshold");
    u.range.comfort_mA = u.range.threshold_mA;
  }
  finish_unit();
}

void Calibration::finish_unit() {
  ++unit_;
  if (!done()) start_threshold();
}

Profile Calibration::profile() const {
  Profile p;
  const bool per_pixel = o_.pads.size() > 1;
  for (std::size_t k = 0; k < 3; ++k) {
    std::vector<PrimaryRange> found;
    for (const Unit& u : units_)
      if (u.found && static_cast<std::size_t>(u.primary) == k) {
        found.push_back(u.range);
        if (per_pixel) p.pixel[u.pad][k] = u.range;
      }
    if (found.empty()) continue;
    if (found.size() == 1) {
      p.primary[k] = found[0];
      continue;
    }
    // Several pixels: each level's median (the lower middle), trials summed.
    auto median = [&](double PrimaryRange::*f) {
      std::vector<double> v;
      for (const PrimaryRange& r : found) v.push_back(r.*f);
      std::sort(v.begin(), v.end());
      return v[(v.size() - 1) / 2];
    };
    PrimaryRange m;
    m.threshold_mA = median(&PrimaryRange::threshold_mA);
    m.comfort_mA = std::max(median(&PrimaryRange::comfort_mA), m.threshold_mA);
    for (const PrimaryRange& r : found) m.trials += r.trials;
    p.primary[k] = m;
  }
  p.carried["array"] = {{"columns", bank_.columns}, {"rows", bank_.rows}};
  if (!per_pixel) p.carried["pixel"] = o_.pads[0];
  p.carried["ceiling_mA"] = o_.staircase.ceiling_mA;
  return p;
}

}  // namespace tp
