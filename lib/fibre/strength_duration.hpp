#pragma once
// Strength-duration: each receptor's threshold over a range of pulse widths, and Weiss's
// law fitted to it (fiber-threshold --strength-duration; docs/fibres.md).

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fibre/models.hpp"
#include "fibre/report.hpp"
#include "model/field.hpp"

namespace tp::fibre {

// Weiss's law: the threshold charge grows linearly with the width,
// threshold_mA x width_us = rheobase_mA x (width_us + chronaxie_us).
struct WeissFit {
  double rheobase_mA = 0.0;
  double chronaxie_us = 0.0;
};
// The least-squares line through the charges (threshold x width) against the widths: its
// slope is the rheobase, its intercept the rheobase times the chronaxie.  None with fewer
// than two points, with every width the same, or with a rheobase that is not positive.
std::optional<WeissFit> weiss_fit(const std::vector<double>& width_us,
                                  const std::vector<double>& threshold_mA);

// The widths of the table by default, us.
inline const std::vector<double> kStrengthDurationWidths_us = {20, 50, 100, 200, 500, 1000, 2000};

// The pulse with another main phase width; its balancing phase keeps its ratio to the width.
PulseSpec pulse_at_width(const PulseSpec& pulse, double width_us);

struct StrengthDuration {
  std::vector<double> widths_us;  // ascending
  std::vector<std::string> receptors;
  // [receptor][width]: none where the receptor does not fire (below settings.max_mA).
  std::vector<std::vector<std::optional<double>>> threshold_mA;
  std::vector<std::optional<WeissFit>> fits;  // per receptor, over the widths where it fires
};

// Every receptor's thresholds at each width (pulse_at_width of `pulse`; the widths
// ascending and distinct, each pulse checked), the fibres' potentials kept between widths.
// progress (optional) is called before each width with the width and its place (1, 2, ...)
// of all.  Bad input as compute_thresholds() says it, before that width's work.
StrengthDuration strength_duration(
    const Setup& setup, const std::vector<double>& weights, const FibreModel& model,
    const PulseSpec& pulse, const ThresholdSettings& settings,
    const std::vector<double>& widths_us,
    const std::function<void(double width_us, std::size_t nth, std::size_t total)>& progress = {});

// CSV, one row per receptor and width, receptors in the setup's order:
// receptor,width_us,threshold_mA,charge_nC,rheobase_mA,chronaxie_us (threshold and charge
// empty where the receptor does not fire at that width, the fit's columns where it has none).
std::string strength_duration_csv(const StrengthDuration& sd);

}  // namespace tp::fibre
