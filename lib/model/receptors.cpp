#include "model/receptors.hpp"

#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/json.hpp"
#include "core/ranges.hpp"

namespace tp {

extern const char* const kDefaultReceptorsJson;  // generated from data/receptors.json

namespace {

Receptor receptor_from_json(const nlohmann::ordered_json& j, std::size_t index) {
  const std::string where = "receptors[" + std::to_string(index) + "]";
  if (!j.is_object()) bad_input(where + ": expected an object");
  static const std::set<std::string> known = {
      "name", "orientation", "depth_mm", "diameter_um", "myelinated", "azimuth_deg", "note"};
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!known.count(it.key())) bad_input(where + ": unknown key " + quoted_text(it.key()));
  Receptor r;
  if (!j.contains("name") || !j["name"].is_string() || j["name"].get<std::string>().empty())
    bad_input(where + ": 'name' must be a non-empty string");
  r.name = j["name"].get<std::string>();
  // A name is also a mode name and a CSV column (max_af_NAME): no commas, quotes or breaks.
  if (r.name.size() > 32 ||
      r.name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                               "abcdefghijklmnopqrstuvwxyz0123456789_.-") != std::string::npos)
    bad_input(where + ": 'name' must be 1 to 32 of A-Z a-z 0-9 _ . -");
  const std::string at = "receptor " + r.name;

  if (!j.contains("orientation") || !j["orientation"].is_string())
    bad_input(at + ": 'orientation' must be \"horizontal\" or \"vertical\"");
  const std::string o = j["orientation"].get<std::string>();
  if (o == "horizontal")
    r.fibre.orientation = Orientation::horizontal;
  else if (o == "vertical")
    r.fibre.orientation = Orientation::vertical;
  else
    bad_input(at + ": 'orientation' must be \"horizontal\" or \"vertical\", got " + quoted_text(o));

  if (!j.contains("depth_mm")) bad_input(at + ": missing 'depth_mm'");
  const auto& d = j["depth_mm"];
  if (d.is_array()) {
    if (d.size() != 2) bad_input(at + ": 'depth_mm' range must be [min, max]");
    r.depth_min_mm = json_finite(d[0], at + " depth_mm[0]");
    r.depth_max_mm = json_finite(d[1], at + " depth_mm[1]");
  } else {
    r.depth_min_mm = r.depth_max_mm = json_finite(d, at + " depth_mm");
  }
  ranges::check(r.depth_min_mm, ranges::depth_mm, at + " depth_mm");
  ranges::check(r.depth_max_mm, ranges::depth_mm, at + " depth_mm");
  if (r.depth_max_mm < r.depth_min_mm) bad_input(at + ": depth range has max < min");

  if (!j.contains("diameter_um")) bad_input(at + ": missing 'diameter_um'");
  r.fibre.diameter_um = json_finite(j["diameter_um"], at + " diameter_um");
  ranges::check(r.fibre.diameter_um, ranges::diameter_um, at + " diameter_um");

  if (j.contains("myelinated")) {
    if (!j["myelinated"].is_boolean()) bad_input(at + ": 'myelinated' must be true or false");
    r.fibre.myelinated = j["myelinated"].get<bool>();
  }
  if (j.contains("azimuth_deg")) {
    if (r.fibre.orientation != Orientation::horizontal)
      bad_input(at + ": 'azimuth_deg' applies to horizontal fibres only");
    r.azimuth_deg = json_finite(j["azimuth_deg"], at + " azimuth_deg");
    ranges::check(r.azimuth_deg, ranges::azimuth_deg, at + " azimuth_deg");
  }
  return r;
}

}  // namespace

FibreAxis fibre_axis(const Receptor& r) {
  if (r.fibre.orientation == Orientation::vertical) return FibreAxis{true, 0.0, 0.0};
  if (r.azimuth_deg == 0.0) return FibreAxis{};
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  return FibreAxis{false, std::cos(r.azimuth_deg * kDeg), std::sin(r.azimuth_deg * kDeg)};
}

const char* to_string(Orientation o) {
  return o == Orientation::horizontal ? "horizontal" : "vertical";
}

std::vector<Receptor> receptors_from_json(const nlohmann::ordered_json& j) {
  const nlohmann::ordered_json* list = &j;
  if (j.is_object()) {
    if (!j.contains("receptors")) bad_input("receptor table: missing 'receptors'");
    list = &j["receptors"];
  }
  if (!list->is_array() || list->empty()) bad_input("receptors: expected a non-empty array");
  if (list->size() > 64) bad_input("receptors: at most 64, got " + std::to_string(list->size()));
  std::vector<Receptor> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list->size(); ++i) {
    out.push_back(receptor_from_json((*list)[i], i));
    if (!names.insert(out.back().name).second)
      bad_input("receptors: duplicate name " + quoted_text(out.back().name));
  }
  return out;
}

nlohmann::ordered_json receptors_to_json(const std::vector<Receptor>& receptors) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& r : receptors) {
    nlohmann::ordered_json e;
    e["name"] = r.name;
    e["orientation"] = to_string(r.fibre.orientation);
    if (r.depth_min_mm == r.depth_max_mm)
      e["depth_mm"] = r.depth_min_mm;
    else
      e["depth_mm"] = {r.depth_min_mm, r.depth_max_mm};
    e["diameter_um"] = r.fibre.diameter_um;
    e["myelinated"] = r.fibre.myelinated;
    if (r.azimuth_deg != 0.0) e["azimuth_deg"] = r.azimuth_deg;
    list.push_back(std::move(e));
  }
  return list;
}

const std::vector<Receptor>& default_receptors() {
  static const std::vector<Receptor> table =
      receptors_from_json(nlohmann::ordered_json::parse(kDefaultReceptorsJson));
  return table;
}

}  // namespace tp
