#include "requests/checks.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tp {

void check_whole(const std::string& flag, long value, long lo, long hi) {
  if (!(value >= lo && value <= hi))
    bad_input(flag + ": " + std::to_string(value) + " outside [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "]");
}

void check_finite(const std::string& flag, std::optional<double> value) {
  if (value && !std::isfinite(*value))
    bad_input(flag + ": non-finite number '" +
              (std::isnan(*value) ? "nan" : *value > 0 ? "inf" : "-inf") + "'");
}

}  // namespace tp
