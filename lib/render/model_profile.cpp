#include "render/model_profile.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "fibre/models.hpp"
#include "core/number.hpp"

namespace tp {

ModelProfile model_profile(const PixelBank& bank, const ModelProfileOptions& o) {
  if (!(o.comfort_factor >= 1.1 && o.comfort_factor <= 10))
    bad_input("--comfort-factor: " + number_beside(o.comfort_factor, 1.1, 10) +
              " outside [1.1, 10]");
  const std::unique_ptr<fibre::FibreModel> model = fibre::make_fibre_model(o.fibre_model);
  const ElectrodeArray& array = bank.doc.setup.array;
  const std::size_t centre = array.centre_index();
  ModelProfile out;
  for (std::size_t p = 0; p < kPrimaries.size(); ++p) {
    // The feasible pattern nearest the centre pad (the lowest index of a tie).
    long pad = -1;
    double best = std::numeric_limits<double>::infinity();
    bool present = false;
    for (std::size_t k = 0; k < bank.pads(); ++k) {
      const BankEntry& e = bank.entry[k][p];
      present = present || e.present;
      if (!e.present || !e.feasible) continue;
      const double d = std::hypot(array.positions_mm[k] - array.positions_mm[centre],
                                  array.z_of(k) - array.z_of(centre));
      if (d < best) {
        best = d;
        pad = static_cast<long>(k);
      }
    }
    if (!present) continue;
    if (pad < 0)
      bad_input(std::string("bank: no feasible ") + kPrimaries[p] +
                " pattern to take the model's threshold from: give a --profile");
    const BankEntry& e = bank.entry[static_cast<std::size_t>(pad)][p];
    Setup setup = bank.doc.setup;
    std::vector<Receptor> only;
    for (const Receptor& r : setup.receptors)
      if (r.name == kPrimaries[p]) only.push_back(r);
    if (only.empty())
      bad_input(std::string("bank: no receptor ") + kPrimaries[p] + " for the model's threshold");
    setup.receptors = only;
    fibre::ThresholdSettings s;
    s.max_mA = o.max_current_mA;
    s.through_mm = std::array<double, 2>{e.peak_x_mm, e.peak_z_mm};
    const fibre::ThresholdReport rep =
        fibre::compute_thresholds(setup, e.weights, *model, o.pulse, s);
    const std::optional<double>& t = rep.receptors[0].threshold_mA;
    if (!t || !(*t >= kMinProfile_mA))
      bad_input(std::string("the model gives ") + kPrimaries[p] + " no threshold within " +
                number_text(o.max_current_mA) + " mA (" +
                (t ? "below the profile's floor" : rep.receptors[0].reason) +
                "): give a --profile (calibrate)");
    PrimaryRange r;
    r.threshold_mA = *t;
    r.comfort_mA = std::min(o.max_current_mA, o.comfort_factor * *t);
    out.capped[p] = o.comfort_factor * *t > o.max_current_mA;
    out.profile.primary[p] = r;
    out.pixel[p] = pad;
  }
  out.profile.carried["source"] = "model";
  return out;
}

}  // namespace tp
