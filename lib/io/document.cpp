#include "io/document.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/number.hpp"
#include "model/constants.hpp"
#include "core/ranges.hpp"

namespace tp {
namespace {

std::vector<double> finite_list(const Json& j, const std::string& what) {
  if (!j.is_array()) bad_input(what + ": expected an array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < j.size(); ++i)
    out.push_back(json_finite(j[i], what + "[" + std::to_string(i) + "]"));
  return out;
}

// A 2-D array: {"grid": {...}} or {"pads": [...]}, with the pads' width_mm and length_mm.
ElectrodeArray array_2d_from_json(const Json& j) {
  reject_unknown(j, {"electrodes", "grid", "pads", "width_mm", "length_mm"}, "array");
  if (j.contains("grid") && j.contains("pads")) bad_input("array: give 'grid' or 'pads', not both");
  for (const char* key : {"width_mm", "length_mm"})
    if (!j.contains(key))
      bad_input(std::string("array: a 2-D array needs its pads' '") + key + "'");
  const double width = json_finite(j["width_mm"], "array.width_mm");
  const double length = json_finite(j["length_mm"], "array.length_mm");
  ranges::check(width, ranges::width_mm, "array.width_mm");
  ranges::check(length, ranges::length_mm, "array.length_mm");
  ElectrodeArray a;
  if (j.contains("grid")) {
    const Json& g = j["grid"];
    if (!g.is_object()) bad_input("array.grid: expected an object");
    reject_unknown(g, {"columns", "rows", "pitch_mm", "row_pitch_mm"}, "array.grid");
    for (const char* key : {"columns", "rows", "pitch_mm"})
      if (!g.contains(key)) bad_input(std::string("array.grid: missing '") + key + "'");
    const int columns = json_int(g["columns"], "array.grid.columns");
    const int rows = json_int(g["rows"], "array.grid.rows");
    const double pitch = json_finite(g["pitch_mm"], "array.grid.pitch_mm");
    const double row_pitch = g.contains("row_pitch_mm")
                                 ? json_finite(g["row_pitch_mm"], "array.grid.row_pitch_mm")
                                 : pitch;
    a = ElectrodeArray::grid_of(columns, rows, pitch, row_pitch, width, length);
  } else {
    const Json& list = j["pads"];
    if (!list.is_array() || list.empty()) bad_input("array.pads: expected a non-empty array");
    if (list.size() > static_cast<std::size_t>(ranges::max_electrodes))
      bad_input("array.pads: " + std::to_string(list.size()) + " pads, at most " +
                std::to_string(ranges::max_electrodes));
    std::vector<double> x, z;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = "array.pads[" + std::to_string(i) + "]";
      const Json& p = list[i];
      if (!p.is_object()) bad_input(at + ": expected an object {\"x_mm\": X, \"z_mm\": Z}");
      reject_unknown(p, {"x_mm", "z_mm"}, at);
      if (!p.contains("x_mm") || !p.contains("z_mm")) bad_input(at + ": needs 'x_mm' and 'z_mm'");
      x.push_back(json_finite(p["x_mm"], at + ".x_mm"));
      z.push_back(json_finite(p["z_mm"], at + ".z_mm"));
    }
    a = ElectrodeArray::pads(std::move(x), std::move(z), width, length);
  }
  if (j.contains("electrodes") &&
      json_int(j["electrodes"], "array.electrodes") != static_cast<int>(a.size()))
    bad_input("array: 'electrodes' disagrees with the number of pads (" + std::to_string(a.size()) +
              ")");
  return a;
}

ElectrodeArray array_from_json(const Json& j) {
  if (!j.is_object()) bad_input("array: expected an object");
  if (j.contains("grid") || j.contains("pads")) return array_2d_from_json(j);
  reject_unknown(j, {"electrodes", "pitch_mm", "positions_mm", "width_mm", "length_mm"}, "array");
  ElectrodeArray a;
  const double width = j.contains("width_mm") ? json_finite(j["width_mm"], "array.width_mm") : 0.5;
  const double length =
      j.contains("length_mm") ? json_finite(j["length_mm"], "array.length_mm") : 10.0;
  if (j.contains("positions_mm")) {
    a.positions_mm = finite_list(j["positions_mm"], "array.positions_mm");
    a.width_mm = width;
    a.length_mm = length;
    if (j.contains("electrodes") &&
        json_int(j["electrodes"], "array.electrodes") != static_cast<int>(a.positions_mm.size()))
      bad_input("array: 'electrodes' disagrees with the length of 'positions_mm'");
    if (j.contains("pitch_mm")) a.pitch_mm = json_finite(j["pitch_mm"], "array.pitch_mm");
  } else {
    if (!j.contains("electrodes") || !j.contains("pitch_mm"))
      bad_input(
          "array: give 'positions_mm', or 'electrodes' and 'pitch_mm' (or a 2-D 'grid' or "
          "'pads')");
    a = ElectrodeArray::uniform(json_int(j["electrodes"], "array.electrodes"),
                                json_finite(j["pitch_mm"], "array.pitch_mm"), width, length);
  }
  a.validate();
  return a;
}

}  // namespace

bool model_uses(const std::string& model, const std::string& key) {
  if (key == "resistivity_ohm_m") return model != "layered";  // layered: the skin's layers
  if (key == "plane_z_mm") return model == "point3d" || model == "rect3d" || model == "layered";
  if (key == "source_depth_mm") return model == "point3d";
  if (key == "skin") return model == "layered";
  return true;
}

void check_setting_applies(const std::string& model, const std::string& key,
                           const std::string& name, const std::string& how) {
  if (model_uses(model, key)) return;
  std::string which;
  if (key == "resistivity_ohm_m")
    which =
        "the uniform models (line2d, strip2d, point3d, rect3d); the layered model takes its "
        "resistivities from its skin's layers";
  else if (key == "plane_z_mm")
    which = "the 3-D models (point3d, rect3d, layered) only";
  else if (key == "source_depth_mm")
    which = "the point3d model only";
  else
    which = "the layered model only";
  bad_input(name + ": applies to " + which + "; this model is " + model + how);
}

Document document_from_json(const Json& j) {
  if (!j.is_object()) bad_input("document: expected a JSON object");
  Document d;
  if (j.contains("format")) {
    if (!j["format"].is_string() || j["format"].get<std::string>() != kDocumentFormat)
      bad_input(std::string("document: 'format' must be \"") + kDocumentFormat + "\"");
  }
  if (!j.contains("array")) bad_input("document: missing 'array'");
  d.setup.array = array_from_json(j["array"]);
  // A 2-D array needs a 3-D model: rect3d unless the document names one.
  if (d.setup.array.two_d()) d.setup.conductor.model = "rect3d";
  if (j.contains("model")) {
    const Json& m = j["model"];
    if (!m.is_object()) bad_input("model: expected an object");
    reject_unknown(m,
                   {"conductor", "resistivity_ohm_m", "lateral_margin_mm", "plane_z_mm",
                    "source_depth_mm", "skin"},
                   "model");
    if (m.contains("conductor")) {
      if (!m["conductor"].is_string()) bad_input("model.conductor: expected a string");
      d.setup.conductor.model = m["conductor"].get<std::string>();
    }
    if (m.contains("resistivity_ohm_m")) {
      d.setup.conductor.resistivity_ohm_m =
          json_finite(m["resistivity_ohm_m"], "model.resistivity_ohm_m");
      ranges::check(d.setup.conductor.resistivity_ohm_m, ranges::resistivity_ohm_m,
                    "model.resistivity_ohm_m");
    }
    if (m.contains("lateral_margin_mm")) {
      d.setup.lateral_margin_mm = json_finite(m["lateral_margin_mm"], "model.lateral_margin_mm");
      ranges::check(d.setup.lateral_margin_mm, ranges::lateral_margin_mm,
                    "model.lateral_margin_mm");
    }
    if (m.contains("plane_z_mm")) {
      d.setup.conductor.plane_z_mm = json_finite(m["plane_z_mm"], "model.plane_z_mm");
      ranges::check(d.setup.conductor.plane_z_mm, ranges::plane_z_mm, "model.plane_z_mm");
    }
    if (m.contains("source_depth_mm")) {
      d.setup.conductor.source_depth_mm =
          json_finite(m["source_depth_mm"], "model.source_depth_mm");
      ranges::check(d.setup.conductor.source_depth_mm, ranges::source_depth_mm,
                    "model.source_depth_mm");
    }
    if (m.contains("skin")) {
      // A built-in name or a skin file's path (layered model), or the skin itself inline.
      if (m["skin"].is_string())
        d.setup.conductor.skin = load_skin(m["skin"].get<std::string>(), "model.skin");
      else
        d.setup.conductor.skin = skin_from_json(m["skin"], "model.skin");
    }
    for (const char* key : {"resistivity_ohm_m", "plane_z_mm", "source_depth_mm", "skin"})
      if (m.contains(key)) d.model_settings.emplace_back(key);
    // Documents written before settings were checked carried the default resistivity under
    // every model, the layered one included: that value, and only that, reads as not given.
    if (d.setup.conductor.model == "layered" && m.contains("resistivity_ohm_m") &&
        d.setup.conductor.resistivity_ohm_m == constants::tissue_resistivity_ohm_m) {
      d.model_settings.erase(std::find(d.model_settings.begin(), d.model_settings.end(),
                                       std::string("resistivity_ohm_m")));
      d.setup.conductor.resistivity_ohm_m = 0.0;
    }
  }
  if (j.contains("receptors")) d.setup.receptors = receptors_from_json(j["receptors"]);
  validate_setup(d.setup);  // the model name, and the model against the receptors
  // A setting the model does not use would be silently ignored: refuse it.
  for (const std::string& key : d.model_settings)
    check_setting_applies(d.setup.conductor.model, key, "model." + key);
  if (j.contains("weights")) {
    d.weights = finite_list(j["weights"], "weights");
    for (std::size_t i = 0; i < d.weights->size(); ++i)
      ranges::check((*d.weights)[i], ranges::weight, "weights[" + std::to_string(i) + "]");
    if (d.weights->size() != d.setup.array.size())
      bad_input("weights: expected " + std::to_string(d.setup.array.size()) + " values, got " +
                std::to_string(d.weights->size()));
  }
  if (j.contains("max_current_mA")) {
    d.max_current_mA = json_finite(j["max_current_mA"], "max_current_mA");
    ranges::check(d.max_current_mA, ranges::max_current_mA, "max_current_mA");
  }
  static const std::set<std::string> own = {"format",    "array",   "model",
                                            "receptors", "weights", "max_current_mA"};
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!own.count(it.key())) d.extra[it.key()] = it.value();
  return d;
}

ElectrodeArray array_from_flags(const std::string& electrodes, const std::string& pitch,
                                int min_electrodes) {
  const long n = electrodes.empty() ? 8 : parse_integer(electrodes, "--electrodes");
  if (n < min_electrodes)
    bad_input("--electrodes: need at least " + std::to_string(min_electrodes) + ", got " +
              electrodes);
  if (n > ranges::max_line_electrodes)
    bad_input("--electrodes: at most " + std::to_string(ranges::max_line_electrodes) + ", got " +
              electrodes);
  const double p = pitch.empty() ? 1.0 : parse_finite(pitch, "--pitch");
  ranges::check(p, ranges::pitch_mm, "--pitch");
  return ElectrodeArray::uniform(static_cast<int>(n), p);
}

Json array_to_json(const ElectrodeArray& a) {
  Json j;
  j["electrodes"] = a.size();
  if (a.grid()) {
    Json g;
    g["columns"] = a.columns;
    g["rows"] = a.rows;
    g["pitch_mm"] = *a.pitch_mm;
    g["row_pitch_mm"] = a.row_pitch_mm;
    j["grid"] = g;
  } else if (a.two_d()) {
    Json list = Json::array();
    for (std::size_t i = 0; i < a.size(); ++i)
      list.push_back(Json{{"x_mm", a.positions_mm[i]}, {"z_mm", a.z_mm[i]}});
    j["pads"] = list;
  } else {
    if (a.pitch_mm) j["pitch_mm"] = *a.pitch_mm;
    j["positions_mm"] = a.positions_mm;
  }
  j["width_mm"] = a.width_mm;
  j["length_mm"] = a.length_mm;
  return j;
}

Json model_to_json(const Setup& s) {
  Json j;
  j["conductor"] = s.conductor.model;
  // Only the settings the model uses (a document read back must not hold one it ignores).
  const std::string& m = s.conductor.model;
  if (model_uses(m, "resistivity_ohm_m"))
    j["resistivity_ohm_m"] = s.conductor.resistivity_ohm_m > 0
                                 ? s.conductor.resistivity_ohm_m
                                 : constants::tissue_resistivity_ohm_m;
  j["lateral_margin_mm"] = s.lateral_margin_mm;
  if (s.conductor.plane_z_mm != 0.0 && model_uses(m, "plane_z_mm"))
    j["plane_z_mm"] = s.conductor.plane_z_mm;
  if (s.conductor.source_depth_mm != 0.0 && model_uses(m, "source_depth_mm"))
    j["source_depth_mm"] = s.conductor.source_depth_mm;
  if (model_uses(m, "skin")) j["skin"] = skin_to_json(effective_skin(s.conductor));
  return j;
}

Json document_to_json(const Document& d) {
  Json j;
  j["format"] = kDocumentFormat;
  j["array"] = array_to_json(d.setup.array);
  j["model"] = model_to_json(d.setup);
  j["receptors"] = receptors_to_json(d.setup.receptors);
  if (d.weights) j["weights"] = *d.weights;
  j["max_current_mA"] = d.max_current_mA;
  for (auto it = d.extra.begin(); it != d.extra.end(); ++it) j[it.key()] = it.value();
  return j;
}

std::optional<std::array<double, 2>> fibre_point(const Document& doc,
                                                 const std::optional<std::vector<double>>& at,
                                                 const std::string& at_text) {
  if (at) {
    if (!doc.setup.array.two_d())
      bad_input("--at: applies to 2-D arrays only (a 1-D array's fibres span it)");
    if (at->size() != 2) bad_input("--at: expected X,Z (mm), got " + quoted_text(at_text));
    return std::array<double, 2>{(*at)[0], (*at)[1]};
  }
  if (!doc.setup.array.two_d() || !doc.extra.contains("focus")) return std::nullopt;
  const Json& f = doc.extra["focus"];
  if (!f.is_object() || !f.contains("x_mm") || !f.contains("z_mm") || !f["x_mm"].is_number() ||
      !f["z_mm"].is_number())
    bad_input("focus: expected an object with numbers x_mm and z_mm");
  return std::array<double, 2>{f["x_mm"].get<double>(), f["z_mm"].get<double>()};
}

}  // namespace tp
