#include "model/primaries.hpp"

#include "core/error.hpp"

namespace tp {

int primary_index(const std::string& name, const std::string& what) {
  for (std::size_t i = 0; i < kPrimaries.size(); ++i)
    if (name == kPrimaries[i]) return static_cast<int>(i);
  bad_input(what + ": '" + name + "' is not a primary (RA, SAI or PC)");
}

}  // namespace tp
