#pragma once
// The three primaries of a tactile display: the receptor modes RA, SAI and PC, in an
// image's channel order (R = RA, G = SAI, B = PC).

#include <array>
#include <string>

namespace tp {

inline constexpr std::array<const char*, 3> kPrimaries = {"RA", "SAI", "PC"};
// The index of a primary's name; bad input naming `what` and the known names otherwise.
int primary_index(const std::string& name, const std::string& what);

}  // namespace tp
