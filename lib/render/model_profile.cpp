#include "render/model_profile.hpp"

#include <cmath>
#include <exception>
#include <limits>

#include "core/error.hpp"
#include "fibre/models.hpp"
#include "core/number.hpp"

namespace tp {

long centre_pattern(const PixelBank& bank, std::size_t primary) {
  const ElectrodeArray& array = bank.doc.setup.array;
  const std::size_t centre = array.centre_index();
  long pad = -1;
  double best = std::numeric_limits<double>::infinity();
  bool present = false;
  for (std::size_t k = 0; k < bank.pads(); ++k) {
    const BankEntry& e = bank.entry[k][primary];
    present = present || e.present;
    if (!e.present || !e.feasible) continue;
    const double d = std::hypot(array.positions_mm[k] - array.positions_mm[centre],
                                array.z_of(k) - array.z_of(centre));
    if (d < best) {
      best = d;
      pad = static_cast<long>(k);
    }
  }
  return present ? pad : kNoMode;
}

PatternThreshold pattern_threshold(const PixelBank& bank, long pad, std::size_t primary,
                                   const fibre::FibreModel& model, const PulseSpec& pulse,
                                   double max_mA) {
  const BankEntry& e = bank.entry[static_cast<std::size_t>(pad)][primary];
  Setup setup = bank.doc.setup;
  std::vector<Receptor> only;
  for (const Receptor& r : setup.receptors)
    if (r.name == kPrimaries[primary]) only.push_back(r);
  if (only.empty())
    bad_input(std::string("bank: no receptor ") + kPrimaries[primary] + " for the model's threshold");
  setup.receptors = only;
  fibre::ThresholdSettings s;
  s.max_mA = max_mA;
  s.through_mm = std::array<double, 2>{e.peak_x_mm, e.peak_z_mm};
  const fibre::ThresholdReport rep = fibre::compute_thresholds(setup, e.weights, model, pulse, s);
  return {rep.receptors[0].threshold_mA, rep.receptors[0].reason};
}

std::vector<std::string> add_model_thresholds(Profile& profile, const PixelBank& bank,
                                              const std::string& fibre_model,
                                              const PulseSpec& pulse, double max_mA) {
  const std::unique_ptr<fibre::FibreModel> model = fibre::make_fibre_model(fibre_model);
  std::vector<std::string> notes;
  if (bank.doc.setup.array.size() != bank.pads() || bank.pads() == 0) return notes;
  for (std::size_t p = 0; p < kPrimaries.size(); ++p) {
    if (!profile.primary[p]) continue;
    const long pad = centre_pattern(bank, p);
    if (pad < 0) continue;
    PatternThreshold t;
    try {  // a prediction only: the person's profile stands without it
      t = pattern_threshold(bank, pad, p, *model, pulse, max_mA);
    } catch (const std::exception& e) {
      t.reason = e.what();
    }
    if (t.threshold_mA)
      profile.primary[p]->model_threshold_mA = *t.threshold_mA;
    else
      notes.push_back(std::string("the model gives ") + kPrimaries[p] + " no threshold within " +
                      number_text(max_mA) + " mA (" + t.reason + "): no model_threshold_mA");
  }
  return notes;
}

ModelProfile model_profile(const PixelBank& bank, const ModelProfileOptions& o) {
  if (!(o.comfort_factor >= 1.1 && o.comfort_factor <= 10))
    bad_input("--comfort-factor: " + number_beside(o.comfort_factor, 1.1, 10) +
              " outside [1.1, 10]");
  const std::unique_ptr<fibre::FibreModel> model = fibre::make_fibre_model(o.fibre_model);
  ModelProfile out;
  for (std::size_t p = 0; p < kPrimaries.size(); ++p) {
    const long pad = centre_pattern(bank, p);
    if (pad == kNoMode) continue;
    if (pad < 0)
      bad_input(std::string("bank: no feasible ") + kPrimaries[p] +
                " pattern to take the model's threshold from: give a --profile");
    const PatternThreshold t = pattern_threshold(bank, pad, p, *model, o.pulse, o.max_current_mA);
    if (!t.threshold_mA || !(*t.threshold_mA >= kMinProfile_mA))
      bad_input(std::string("the model gives ") + kPrimaries[p] + " no threshold within " +
                number_text(o.max_current_mA) + " mA (" +
                (t.threshold_mA ? "below the profile's floor" : t.reason) +
                "): give a --profile (calibrate)");
    PrimaryRange r;
    r.threshold_mA = *t.threshold_mA;
    r.comfort_mA = std::min(o.max_current_mA, o.comfort_factor * *t.threshold_mA);
    out.capped[p] = o.comfort_factor * *t.threshold_mA > o.max_current_mA;
    out.profile.primary[p] = r;
    out.pixel[p] = pad;
  }
  out.profile.carried["source"] = "model";
  return out;
}

}  // namespace tp
