#include "core/ranges.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp::ranges {

void check(double value, const Range& r, const std::string& what) {
  if (std::isfinite(value) && value >= r.lo && value <= r.hi) return;
  const std::string unit = *r.unit ? std::string(" ") + r.unit : std::string();
  bad_input(what + ": " + number_beside(value, r.lo, r.hi) + unit + " outside [" +
            number_text(r.lo) + ", " + number_text(r.hi) + "]" + unit);
}

}  // namespace tp::ranges
