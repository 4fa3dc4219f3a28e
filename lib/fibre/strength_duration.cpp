#include "fibre/strength_duration.hpp"

#include "core/number.hpp"

namespace tp::fibre {

std::optional<WeissFit> weiss_fit(const std::vector<double>& width_us,
                                  const std::vector<double>& threshold_mA) {
  const std::size_t n = width_us.size();
  if (n < 2) return std::nullopt;
  double st = 0, sq = 0, stt = 0, stq = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double q = threshold_mA[k] * width_us[k];
    st += width_us[k];
    sq += q;
    stt += width_us[k] * width_us[k];
    stq += width_us[k] * q;
  }
  const double dn = static_cast<double>(n);
  const double den = dn * stt - st * st;
  if (!(den > 0)) return std::nullopt;
  WeissFit f;
  f.rheobase_mA = (dn * stq - st * sq) / den;
  const double intercept = (sq - f.rheobase_mA * st) / dn;
  if (!(f.rheobase_mA > 0)) return std::nullopt;
  f.chronaxie_us = intercept / f.rheobase_mA;
  return f;
}

PulseSpec pulse_at_width(const PulseSpec& pulse, double width_us) {
  PulseSpec p = pulse;
  p.balance_width_us = pulse.balance_width_us / pulse.width_us * width_us;
  p.width_us = width_us;
  return p;
}

StrengthDuration strength_duration(
    const Setup& setup, const std::vector<double>& weights, const FibreModel& model,
    const PulseSpec& pulse, const ThresholdSettings& settings,
    const std::vector<double>& widths_us,
    const std::function<void(double width_us, std::size_t nth, std::size_t total)>& progress) {
  StrengthDuration sd;
  sd.widths_us = widths_us;
  const std::size_t nr = setup.receptors.size();
  for (const Receptor& r : setup.receptors) sd.receptors.push_back(r.name);
  sd.threshold_mA.resize(nr);
  PotentialCache cache;  // the same fibres for every width
  for (std::size_t q = 0; q < widths_us.size(); ++q) {
    if (progress) progress(widths_us[q], q + 1, widths_us.size());
    const ThresholdReport rep = compute_thresholds(setup, weights, model,
                                                   pulse_at_width(pulse, widths_us[q]), settings,
                                                   &cache);
    for (std::size_t k = 0; k < nr; ++k) sd.threshold_mA[k].push_back(rep.receptors[k].threshold_mA);
  }
  for (std::size_t k = 0; k < nr; ++k) {
    std::vector<double> t, i;
    for (std::size_t q = 0; q < widths_us.size(); ++q)
      if (sd.threshold_mA[k][q]) {
        t.push_back(widths_us[q]);
        i.push_back(*sd.threshold_mA[k][q]);
      }
    sd.fits.push_back(weiss_fit(t, i));
  }
  return sd;
}

std::string strength_duration_csv(const StrengthDuration& sd) {
  std::string out = "receptor,width_us,threshold_mA,charge_nC,rheobase_mA,chronaxie_us\n";
  for (std::size_t k = 0; k < sd.receptors.size(); ++k) {
    const std::optional<WeissFit>& fit = sd.fits[k];
    for (std::size_t q = 0; q < sd.widths_us.size(); ++q) {
      const double w = sd.widths_us[q];
      const std::optional<double>& th = sd.threshold_mA[k][q];
      out += sd.receptors[k] + "," + number_text(w) + ",";
      out += th ? number_text(*th) + "," + number_text(*th * w) : ",";
      out += fit ? "," + number_text(fit->rheobase_mA) + "," + number_text(fit->chronaxie_us)
                 : ",,";
      out += "\n";
    }
  }
  return out;
}

}  // namespace tp::fibre
