#include "host/hold.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "device/protocol.hpp"

namespace tp::host {
namespace {

double peak_mA(const Stimulus& s) {
  double peak = 0;
  for (double c : s.currents_mA) peak = std::max(peak, std::fabs(c));
  return peak;
}

void check_references(const Mix& m) {
  for (std::size_t p = 0; p < m.patterns.size(); ++p) {
    const Stimulus& s = m.patterns[p];
    const std::string where = m.single() ? "the stimulus" : "pattern " + std::to_string(p);
    for (std::size_t c = 0; c < s.currents_mA.size(); ++c)
      if (s.currents_mA[c] != 0 &&
          (c >= s.reference_impedance_kohm.size() || !(s.reference_impedance_kohm[c] > 0)))
        bad_input("--hold-sensation: " + where + " has no reference impedance for channel " +
                  std::to_string(c) +
                  " (make-pulse --profile with a profile that calibrate measured on a device "
                  "that measures)");
  }
}

Mix raised(const Mix& m, double factor) {
  Mix out = m;
  for (std::size_t p = 0; p < m.patterns.size(); ++p) {
    Stimulus& s = out.patterns[p];
    const double amplitude = s.amplitude_mA > 0 ? s.amplitude_mA : peak_mA(s);
    for (double& c : s.currents_mA) c *= factor;
    s.amplitude_mA = amplitude * factor;
    if (m.start_amplitudes_mA.empty()) out.start_amplitudes_mA.push_back(amplitude);
  }
  return out;
}

bool passes(const Mix& m, const StimulusLimits& lim) {
  try {
    check_mix(m, lim);
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

Mix hold_ceiling(const Mix& m, const StimulusLimits& lim, double* headroom) {
  check_references(m);
  double hi = kHoldHeadroom;
  for (const Stimulus& s : m.patterns)
    if (peak_mA(s) > 0) hi = std::min(hi, std::min(s.max_current_mA, lim.max_current_mA) / peak_mA(s));
  hi = std::max(hi, 1.0);
  double lo = 1.0;
  if (passes(raised(m, hi), lim)) {
    lo = hi;
  } else {  // the largest factor that passes, to a thousandth
    while (hi - lo > 1e-3) {
      const double mid = 0.5 * (lo + hi);
      (passes(raised(m, mid), lim) ? lo : hi) = mid;
    }
  }
  if (headroom) *headroom = lo;
  return raised(m, lo);
}

std::uint64_t hold_energy(const std::vector<std::int16_t>& codes,
                          const std::vector<double>& reference_kohm) {
  std::uint64_t e = 0;
  for (std::size_t c = 0; c < codes.size() && c < reference_kohm.size(); ++c) {
    if (codes[c] == 0) continue;
    const double ohm = std::min(std::round(reference_kohm[c] * 1000), double{device::kHoldMaxOhm});
    const auto z = static_cast<std::uint64_t>(ohm) / device::kHoldOhmUnit;
    const auto code = static_cast<std::uint64_t>(std::abs(int{codes[c]}));
    e += z * code * code;
  }
  return e;
}

}  // namespace tp::host
