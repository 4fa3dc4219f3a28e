#include "psych/pulse_train.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/number.hpp"
#include "psych/profile.hpp"

namespace tp {

void check_whole_us(double v, double lo, double hi, const char* flag) {
  if (!(v >= lo && v <= hi && v == std::floor(v)))
    bad_input(std::string(flag) + ": " + number_beside(v, lo, hi) +
              " us is not a whole number in [" + number_text(lo) + ", " + number_text(hi) +
              "] us");
}

void check_pulse_train(const std::array<double, 3>& rate_hz, double width_us, double interphase_us,
                       double balance_width_us, const StimulusLimits& l) {
  for (std::size_t p = 0; p < 3; ++p)
    if (!(rate_hz[p] >= l.min_frequency_hz && rate_hz[p] <= l.max_frequency_hz))
      bad_input(std::string("--rates: ") + kPrimaries[p] + " " +
                number_beside(rate_hz[p], l.min_frequency_hz, l.max_frequency_hz) +
                " Hz outside [" + number_text(l.min_frequency_hz) + ", " +
                number_text(l.max_frequency_hz) + "] Hz");
  check_whole_us(width_us, l.min_width_us, l.max_width_us, "--width");
  check_whole_us(interphase_us, 0, 1000, "--interphase");
  check_whole_us(balance_width_us, width_us, l.max_balance_width_us, "--balance-width");
}

}  // namespace tp
