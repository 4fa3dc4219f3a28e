// A stimulus's checks and its safety figures (pulse/stimulus).
#include <catch2/catch.hpp>

#include <cmath>

#include "core/error.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;

TEST_CASE("stimulus checks (limits, zero sum, balance) and safety figures", "[pulse]") {
  Stimulus s;
  s.currents_mA = {1.0, -0.5, -0.5};
  s.count = 200;
  s.shape.balance_width_us = 400;  // longer and lower: -0.5x for 400 us
  CHECK_NOTHROW(check_stimulus(s, StimulusLimits{}));
  const SafetyFigures f = safety_figures(s);
  CHECK(f.peak_current_mA == 1.0);
  CHECK(f.max_charge_per_phase_nC == Approx(200.0));  // 1 mA x 200 us
  CHECK(f.max_net_charge_nC < 1e-12);
  CHECK(f.max_charge_density_uC_per_cm2 == Approx(200.0 / 5.0 * 0.1));  // 200 nC over 5 mm^2
  CHECK(f.max_rms_current_mA == Approx(std::sqrt((1.0 * 200 + 0.25 * 400) / 5000.0)));
  Stimulus bad = s;
  bad.currents_mA = {2.5, -2.5, 0};
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
  bad.currents_mA = {1.0, -0.9, 0};
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
  bad = s;
  bad.shape.frequency_hz = 2000;
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
  bad = s;
  bad.shape.width_us = 900;
  bad.shape.balance_width_us = 4500;  // does not fit a 5 ms period
  CHECK_THROWS_AS(check_stimulus(bad, StimulusLimits{}), Error);
}
