#include "model/skin.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/json.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"

namespace tp {

extern const char* const kSkinFingertipJson;     // generated from data/skin/fingertip.json
extern const char* const kSkinFingertipDryJson;  // and data/skin/fingertip-dry.json

namespace {

constexpr const char* kSkinFormat = "tactile-primaries/skin/1";

}  // namespace

Skin skin_from_json(const Json& j, const std::string& where) {
  if (!j.is_object()) bad_input(where + ": expected a JSON object");
  // electrode, overrides and events are an emulator's (host/skin_file.hpp; docs/skin.md).
  reject_unknown(j, {"format", "name", "description", "valid_to_mm", "layers", "note",
                     "electrode", "overrides", "events"},
                 where);
  if (j.contains("format") &&
      (!j["format"].is_string() || j["format"].get<std::string>() != kSkinFormat))
    bad_input(where + ": 'format' must be \"" + kSkinFormat + "\"");
  Skin s;
  if (j.contains("name")) {
    if (!j["name"].is_string()) bad_input(where + ": 'name' must be a string");
    s.name = j["name"].get<std::string>();
  }
  if (!j.contains("valid_to_mm")) bad_input(where + ": missing 'valid_to_mm'");
  s.valid_to_mm = json_finite(j["valid_to_mm"], where + " valid_to_mm");
  ranges::check(s.valid_to_mm, ranges::depth_mm, where + " valid_to_mm");
  if (!j.contains("layers") || !j["layers"].is_array() || j["layers"].empty())
    bad_input(where + ": 'layers' must be a non-empty array (no layers given)");
  const Json& list = j["layers"];
  if (list.size() > LayeredHalfSpace::kMaxLayers)
    bad_input(where + ": at most " + std::to_string(LayeredHalfSpace::kMaxLayers) +
              " layers, got " + std::to_string(list.size()));
  double depth = 0.0;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Json& l = list[i];
    const std::string at = where + " layers[" + std::to_string(i) + "]";
    if (!l.is_object()) bad_input(at + ": expected an object");
    reject_unknown(l, {"name", "thickness_mm", "resistivity_ohm_m", "note"}, at);
    std::string name = "layer " + std::to_string(i + 1);
    if (l.contains("name")) {
      if (!l["name"].is_string()) bad_input(at + ".name: must be a string");
      name = l["name"].get<std::string>();
    }
    Layer layer;
    const bool last = i + 1 == list.size();
    if (last) {
      if (l.contains("thickness_mm"))
        bad_input(at + ".thickness_mm: the last layer is semi-infinite; give no thickness");
    } else {
      if (!l.contains("thickness_mm")) bad_input(at + ": missing 'thickness_mm'");
      layer.thickness_mm = json_finite(l["thickness_mm"], at + ".thickness_mm");
      if (!(layer.thickness_mm > 0.0))
        bad_input(at + ".thickness_mm: must be > 0, got " + number_text(layer.thickness_mm));
      ranges::check(layer.thickness_mm,
                    {skin_ranges::min_thickness_mm, skin_ranges::max_thickness_mm, "mm"},
                    at + ".thickness_mm");
      depth += layer.thickness_mm;
    }
    if (!l.contains("resistivity_ohm_m")) bad_input(at + ": missing 'resistivity_ohm_m'");
    layer.resistivity_ohm_m = json_finite(l["resistivity_ohm_m"], at + ".resistivity_ohm_m");
    if (!(layer.resistivity_ohm_m > 0.0))
      bad_input(at + ".resistivity_ohm_m: must be > 0, got " +
                number_text(layer.resistivity_ohm_m));
    ranges::check(layer.resistivity_ohm_m, ranges::resistivity_ohm_m, at + ".resistivity_ohm_m");
    s.layers.push_back(layer);
    s.layer_names.push_back(name);
  }
  if (depth > ranges::depth_mm.hi)
    bad_input(where + ": the layers above the last reach " +
              number_beside(depth, ranges::depth_mm.hi) + " mm, deeper than " +
              number_text(ranges::depth_mm.hi) + " mm");
  return s;
}

Json skin_to_json(const Skin& s) {
  Json j;
  j["name"] = s.name;
  j["valid_to_mm"] = s.valid_to_mm;
  Json list = Json::array();
  for (std::size_t i = 0; i < s.layers.size(); ++i) {
    Json l;
    l["name"] = s.layer_names[i];
    if (i + 1 < s.layers.size()) l["thickness_mm"] = s.layers[i].thickness_mm;
    l["resistivity_ohm_m"] = s.layers[i].resistivity_ohm_m;
    list.push_back(std::move(l));
  }
  j["layers"] = std::move(list);
  return j;
}

const std::vector<std::string>& builtin_skin_names() {
  static const std::vector<std::string> names = {"fingertip", "fingertip-dry"};
  return names;
}

const Skin& builtin_skin(const std::string& name) {
  static const std::map<std::string, Skin> skins = [] {
    std::map<std::string, Skin> m;
    m["fingertip"] = skin_from_json(Json::parse(kSkinFingertipJson), "data/skin/fingertip.json");
    m["fingertip-dry"] =
        skin_from_json(Json::parse(kSkinFingertipDryJson), "data/skin/fingertip-dry.json");
    return m;
  }();
  const auto it = skins.find(name);
  if (it == skins.end())
    bad_input("skin " + quoted_text(name) +
              ": not a built-in skin (fingertip or fingertip-dry) or a file");
  return it->second;
}

Skin load_skin(const std::string& spec, const std::string& what) {
  for (const auto& n : builtin_skin_names())
    if (spec == n) return builtin_skin(n);
  if (spec.empty()) bad_input(what + ": empty");
  // A bare word that names no file is a mistyped built-in name more often than a path.
  if (spec != "-" && spec.find('/') == std::string::npos && !std::filesystem::exists(spec))
    bad_input(what + ": " + quoted_text(spec) +
              " is neither a built-in skin (fingertip, fingertip-dry) nor a file");
  Skin s = skin_from_json(read_json(spec, what), what + " " + spec);
  if (s.name.empty()) s.name = spec;
  return s;
}

}  // namespace tp
