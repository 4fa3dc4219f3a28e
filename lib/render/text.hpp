#pragma once
// Counts in messages: "1 slot", "2 slots", "0 frames".

#include <cstddef>
#include <string>

namespace tp {

// n and the noun, plural (noun + "s") unless n is 1.  Every noun render's messages count
// takes an s.
inline std::string count_text(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

}  // namespace tp
