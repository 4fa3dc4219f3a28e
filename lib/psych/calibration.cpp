#include "psych/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "psych/pulse_train.hpp"

namespace tp {

void check_calibration_options(const CalibrationOptions& o, const PixelBank& bank) {
  check_staircase_options(o.staircase);
  if (!(o.trial_s >= 0.05 && o.trial_s <= 10))
    bad_input("--trial-duration: " + number_beside(o.trial_s, 0.05, 10) +
              " s outside [0.05, 10] s");
  // The rates and the phases as render-tactile checks them (its --interphase: 0).
  check_pulse_train(o.rate_hz, o.width_us, 0.0, o.balance_width_us, StimulusLimits{});
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
  primaries_ = o.primaries;
  if (primaries_.empty()) primaries_ = {0, 1, 2};
  for (const long pad : o.pads)
    for (const int p : primaries_) {
      const BankEntry& e = bank.entry[static_cast<std::size_t>(pad)][static_cast<std::size_t>(p)];
      const std::string where = this->where({pad, p, false, PrimaryRange{}});
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

void Calibration::measured(const std::vector<double>& impedance_kohm) {
  if (done() || comfort_) return;  // the threshold's trials only
  if (z_sum_.size() < impedance_kohm.size()) {
    z_sum_.resize(impedance_kohm.size(), 0.0);
    z_count_.resize(impedance_kohm.size(), 0);
  }
  for (std::size_t c = 0; c < impedance_kohm.size(); ++c)
    if (impedance_kohm[c] > 0) {
      z_sum_[c] += impedance_kohm[c];
      ++z_count_[c];
    }
}

void Calibration::start_threshold() {
  comfort_ = false;
  unit_trials_ = 0;
  z_sum_.clear();
  z_count_.clear();
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
  if (comfort_)
    finish_comfort();
  else
    finish_threshold();
}

std::string Calibration::where(const Unit& u) const {
  return std::string(kPrimaries[static_cast<std::size_t>(u.primary)]) + " at pixel (" +
         std::to_string(u.pad % bank_.columns) + ", " + std::to_string(u.pad / bank_.columns) + ")";
}

// What ended the staircase without a level, in the question's words.
std::string Calibration::end_text() const {
  const StaircaseOptions& o = o_.staircase;
  const std::string ceiling = number_text(o.ceiling_mA) + " mA";
  switch (stair_.end()) {
    case StaircaseEnd::ceiling:
      return std::string(comfort_ ? "never too strong" : "not felt") + " up to the ceiling, " +
             ceiling;
    case StaircaseEnd::no_at_ceiling:
      return std::string(comfort_ ? "not too strong" : "not felt") + " " +
             std::to_string(kNoAtCeiling) + " times in a row at the ceiling, " + ceiling +
             ", after a " + (comfort_ ? "\"too strong\"" : "\"felt\"") + " below it";
    case StaircaseEnd::yes_at_floor:
      return std::string(comfort_ ? "too strong" : "felt") + " " + std::to_string(kYesAtFloor) +
             " times in a row at the floor, " + number_text(kMinLevel_mA) +
             " mA, the least level calibrate gives";
    case StaircaseEnd::trials:
      return "no " + std::string(comfort_ ? "comfort limit" : "threshold") + " within " +
             std::to_string(o.max_trials) +
             " trials (--max-trials): " + std::to_string(stair_.reversals()) + " of " +
             std::to_string(o.reversals) + " reversals";
    case StaircaseEnd::reversals:
    case StaircaseEnd::running:
      break;
  }
  return "found";
}

void Calibration::finish_threshold() {
  Unit& u = units_[unit_];
  if (!stair_.found()) {
    notes_.push_back(where(u) + ": " + end_text() + "; no threshold, left out of the profile");
    finish_unit();
    return;
  }
  u.range.threshold_mA = stair_.estimate_mA();
  u.range.threshold_spread_mA = stair_.spread_mA();
  u.range.trials = unit_trials_;
  u.range.impedance_kohm.clear();
  for (std::size_t c = 0; c < z_sum_.size(); ++c)
    u.range.impedance_kohm.push_back(z_count_[c] > 0 ? z_sum_[c] / z_count_[c] : 0.0);
  // The comfort limit, from the threshold up: "too strong?", 1-down-1-up.
  StaircaseOptions c_opt = o_.staircase;
  c_opt.down = 1;
  c_opt.start_mA = std::clamp(u.range.threshold_mA, kMinLevel_mA, c_opt.ceiling_mA);
  comfort_ = true;
  unit_trials_ = 0;
  stair_ = Staircase(c_opt);
}

void Calibration::finish_comfort() {
  Unit& u = units_[unit_];
  u.range.trials += unit_trials_;
  switch (stair_.end()) {
    case StaircaseEnd::reversals:
      u.range.comfort_mA = stair_.estimate_mA();
      u.range.comfort_spread_mA = stair_.spread_mA();
      break;
    case StaircaseEnd::ceiling:  // never too strong up to it: the ceiling bounds it
    case StaircaseEnd::no_at_ceiling:
      u.range.comfort_mA = o_.staircase.ceiling_mA;
      notes_.push_back(where(u) + ": " + end_text() + "; comfort set to the ceiling");
      break;
    default:  // no level the person accepted can be trusted: nothing rendered from it
      notes_.push_back(where(u) + ": " + end_text() +
                       "; no comfort limit, left out of the profile");
      finish_unit();
      return;
  }
  u.found = true;
  if (u.range.comfort_mA < u.range.threshold_mA) {
    notes_.push_back(where(u) + ": comfort " + number_text(u.range.comfort_mA) +
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
    // Each pad's impedance: its mean over the pixels that measured it.
    std::size_t pads = 0;
    for (const PrimaryRange& r : found) pads = std::max(pads, r.impedance_kohm.size());
    for (std::size_t c = 0; c < pads; ++c) {
      double sum = 0;
      int n = 0;
      for (const PrimaryRange& r : found)
        if (c < r.impedance_kohm.size() && r.impedance_kohm[c] > 0) {
          sum += r.impedance_kohm[c];
          ++n;
        }
      m.impedance_kohm.push_back(n > 0 ? sum / n : 0.0);
    }
    p.primary[k] = m;
  }
  p.carried["array"] = {{"columns", bank_.columns}, {"rows", bank_.rows}};
  if (!per_pixel) p.carried["pixel"] = o_.pads[0];
  p.carried["ceiling_mA"] = o_.staircase.ceiling_mA;
  return p;
}

void Calibration::check_trials(const std::function<void(const Mix&)>& check) const {
  const double ceiling = o_.staircase.ceiling_mA;
  for (std::size_t u = 0; u < units_.size(); ++u) {
    auto passes = [&](double level, std::string* why) {
      try {
        check(trial_stimulus(u, level));
        return true;
      } catch (const Error& e) {
        if (e.code() != ExitCode::bad_input) throw;
        if (why) *why = e.what();
        return false;
      }
    };
    std::string why;
    if (passes(ceiling, &why)) continue;
    if (!passes(kMinLevel_mA, nullptr))
      bad_input(where(units_[u]) + ": the device cannot deliver its trials at any level: " + why +
                "; nothing was sent");
    // Every limit grows with the level: the highest that passes, by bisection, in whole uA.
    double lo = kMinLevel_mA, hi = ceiling;
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      (passes(mid, nullptr) ? lo : hi) = mid;
    }
    const double most = std::max(kMinLevel_mA, std::floor(lo * 1000 + 1e-9) / 1000);
    bad_input("--ceiling " + number_text(ceiling) + " mA: the device cannot deliver " +
              where(units_[u]) + " at it (" + why + "); lower --ceiling to " + number_text(most) +
              " mA or less; nothing was sent");
  }
}

CalibrationLength Calibration::length() const {
  const StaircaseOptions& o = o_.staircase;
  const double threshold = std::sqrt(o.start_mA * o.ceiling_mA);
  StaircaseOptions c_opt = o;
  c_opt.down = 1;
  c_opt.start_mA = threshold;
  const int per_unit =
      typical_trials(o, threshold) + typical_trials(c_opt, std::sqrt(threshold * o.ceiling_mA));
  CalibrationLength n;
  const int units = static_cast<int>(units_.size());
  n.staircases = 2 * units;
  n.typical = units * per_unit;
  n.most = n.staircases * o.max_trials;
  return n;
}

std::string Calibration::length_text() const {
  const CalibrationLength n = length();
  std::string names;
  for (std::size_t k = 0; k < primaries_.size(); ++k)
    names += (k == 0                       ? ""
              : k + 1 == primaries_.size() ? " and "
                                           : ", ") +
             std::string(kPrimaries[static_cast<std::size_t>(primaries_[k])]);
  const std::size_t pixels = o_.pads.size();
  return names + " at " + std::to_string(pixels) + (pixels == 1 ? " pixel: " : " pixels: ") +
         std::to_string(n.staircases) + " staircases, about " + std::to_string(n.typical) +
         " trials of " + number_text(o_.trial_s) + " s, at most " + std::to_string(n.most);
}

std::string Calibration::stage_text() const {
  if (done() || unit_trials_ != 0) return "";
  const Unit& u = units_[unit_];
  const auto p = std::find(primaries_.begin(), primaries_.end(), u.primary) - primaries_.begin();
  const auto q = std::find(o_.pads.begin(), o_.pads.end(), u.pad) - o_.pads.begin();
  return std::string(kPrimaries[static_cast<std::size_t>(u.primary)]) + ", primary " +
         std::to_string(p + 1) + " of " + std::to_string(primaries_.size()) + ", at pixel (" +
         std::to_string(u.pad % bank_.columns) + ", " + std::to_string(u.pad / bank_.columns) +
         "), " + std::to_string(q + 1) + " of " + std::to_string(o_.pads.size()) +
         (comfort_ ? ": the comfort limit, too strong?" : ": the threshold, felt it?");
}

std::string Calibration::summary() const {
  const Profile p = profile();
  auto mA = [](double v) { return number_text(std::round(v * 1e4) / 1e4) + " mA"; };
  std::string s = std::to_string(trials_.size()) + " trials";
  for (const int k : primaries_) {
    const auto& r = p.primary[static_cast<std::size_t>(k)];
    s += std::string("; ") + kPrimaries[static_cast<std::size_t>(k)];
    s += r ? " threshold " + mA(r->threshold_mA) + ", comfort " + mA(r->comfort_mA) : " not found";
  }
  if (o_.pads.size() > 1) s += " (the medians of " + std::to_string(o_.pads.size()) + " pixels)";
  return s;
}

std::string calibration_log_header() {
  return "trial,primary,pad,column,row,question,level_mA,phase,response,reversal,pulses,peak_mA";
}

std::string calibration_log_row(const CalibrationTrial& t, int columns, std::uint32_t pulses,
                                double peak_mA) {
  return std::to_string(t.n) + "," + kPrimaries[static_cast<std::size_t>(t.primary)] + "," +
         std::to_string(t.pad) + "," + std::to_string(t.pad % columns) + "," +
         std::to_string(t.pad / columns) + "," + (t.comfort ? "too strong" : "felt") + "," +
         number_text(t.level_mA) + "," + (t.ascending ? "ascending" : "staircase") + "," +
         (t.yes ? "yes" : "no") + "," + (t.reversal ? "1" : "0") + "," + std::to_string(pulses) +
         "," + number_text(peak_mA);
}

}  // namespace tp
