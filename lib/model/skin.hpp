#pragma once
// Skin files: the layers of the `layered` conductor model (format in docs/document-format.md,
// "Skin files"; values and their sources in data/skin/*.json and docs/model.md).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/layered.hpp"

namespace tp {

struct Skin {
  std::string name;                      // "fingertip", a file's own name, ...
  std::vector<Layer> layers;             // from the surface down; the last is semi-infinite
  std::vector<std::string> layer_names;  // one per layer
  double valid_to_mm = 0.0;              // the deepest depth the half-space stands for
};

// The ranges of a skin file's values (bad input outside, named with the range).
namespace skin_ranges {
inline constexpr double min_thickness_mm = 0.005, max_thickness_mm = 50.0;
}

// Parses a skin document; `where` names it in messages ("--skin fingertip.json").
Skin skin_from_json(const nlohmann::ordered_json& j, const std::string& where);
// The document form (the notes are not kept): {"name", "valid_to_mm", "layers"}.
nlohmann::ordered_json skin_to_json(const Skin& s);

// The skins shipped in data/skin (compiled in): "fingertip" (hydrated, electrode gel) and
// "fingertip-dry".  Bad input for another name.
const Skin& builtin_skin(const std::string& name);
const std::vector<std::string>& builtin_skin_names();

// The skin a conductor's parameters stand for: theirs, or the built-in "fingertip".
struct ConductorParams;
const Skin& effective_skin(const ConductorParams& p);

// A built-in name, or else a path to a skin file (- for stdin).
Skin load_skin(const std::string& spec, const std::string& what);

}  // namespace tp
