#include "requests/document_options.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/number.hpp"
#include "model/conductor.hpp"
#include "core/ranges.hpp"

namespace tp {

namespace {

// "AxB" into two strings; bad input naming the flag otherwise.
std::pair<std::string, std::string> split_x(const std::string& text, const std::string& flag,
                                            const std::string& form) {
  const std::size_t at = text.find('x');
  if (at == std::string::npos || at == 0 || at + 1 == text.size() ||
      text.find('x', at + 1) != std::string::npos)
    bad_input(flag + ": expected " + form + ", got " + quoted_text(text));
  return {text.substr(0, at), text.substr(at + 1)};
}

}  // namespace

Document load_document(const ArrayOptions& o, int min_electrodes) {
  if (!o.config.empty()) return document_from_json(read_json(o.config, "--config"));
  Document doc;
  if (o.grid.empty()) {
    if (!o.row_pitch.empty()) bad_input("--row-pitch: applies to --grid only");
    if (!o.pad.empty()) bad_input("--pad: applies to --grid only");
    doc.setup.array = array_from_flags(o.electrodes, o.pitch, min_electrodes);
    return doc;
  }
  const auto [cols, rows] = split_x(o.grid, "--grid", "COLUMNSxROWS, e.g. 8x8");
  const long c = parse_integer(cols, "--grid columns"), r = parse_integer(rows, "--grid rows");
  for (const long v : {c, r})
    if (v < 1 || v > ranges::max_grid_side)
      bad_input("--grid: " + std::to_string(v) + " outside [1, " +
                std::to_string(ranges::max_grid_side) + "]");
  if (c * r > ranges::max_electrodes)
    bad_input("--grid: " + std::to_string(c * r) + " pads, at most " +
              std::to_string(ranges::max_electrodes));
  if (c * r < min_electrodes)
    bad_input("--grid: need at least " + std::to_string(min_electrodes) + " pads");
  const double p = o.pitch.empty() ? 1.0 : parse_finite(o.pitch, "--pitch");
  ranges::check(p, ranges::pitch_mm, "--pitch");
  const double rp = o.row_pitch.empty() ? p : parse_finite(o.row_pitch, "--row-pitch");
  ranges::check(rp, ranges::pitch_mm, "--row-pitch");
  double w = 0.5 * p, l = 0.5 * rp;
  if (!o.pad.empty()) {
    const auto [ws, ls] = split_x(o.pad, "--pad", "WIDTHxLENGTH in mm, e.g. 1x1");
    w = parse_finite(ws, "--pad width");
    l = parse_finite(ls, "--pad length");
    if (!(w > 0.0)) bad_input("--pad: the width must be > 0 mm");
    ranges::check(w, ranges::width_mm, "--pad width");
    ranges::check(l, ranges::length_mm, "--pad length");
  }
  if (o.pad.empty()) {  // the default pads must be in range too, named as such
    ranges::check(w, ranges::width_mm, "--pad width (default half the --pitch)");
    ranges::check(l, ranges::length_mm, "--pad length (default half the --row-pitch)");
  }
  doc.setup.array = ElectrodeArray::grid_of(static_cast<int>(c), static_cast<int>(r), p, rp, w, l);
  doc.setup.conductor.model = "rect3d";
  return doc;
}

void apply_model_options(Document& doc, const ModelOptions& o) {
  if (!o.model.empty()) doc.setup.conductor.model = o.model;
  const std::string& model = doc.setup.conductor.model;
  // Nothing given may be silently ignored: neither a flag nor a setting of the document
  // that the (possibly new) model does not use.
  const std::string how = o.model.empty() ? "" : " (from " + o.flag + ")";
  const auto& known = conductor_models();
  if (std::find(known.begin(), known.end(), model) == known.end())
    bad_input(o.flag + ": unknown conductor model " + quoted_text(model) + " (expected " +
              conductor_model_list() + ")");
  for (const std::string& key : doc.model_settings)
    check_setting_applies(model, key, "model." + key, how);
  if (!o.plane_z.empty()) {
    check_setting_applies(model, "plane_z_mm", "--z", how);
    doc.setup.conductor.plane_z_mm = parse_finite(o.plane_z, "--z");
    ranges::check(doc.setup.conductor.plane_z_mm, ranges::plane_z_mm, "--z");
  }
  if (!o.skin.empty()) {
    check_setting_applies(model, "skin", "--skin",
                          how.empty() ? "; add " + o.flag + " layered" : how);
    doc.setup.conductor.skin = load_skin(o.skin, "--skin");
  }
  validate_setup(doc.setup);
}

void refuse_plane_z(const Document& doc, const ModelOptions& o, const std::string& why) {
  refuse_plane_z(doc, !o.plane_z.empty(), why);
}

void refuse_plane_z(const Document& doc, bool z_given, const std::string& why) {
  if (z_given) bad_input("--z: does not apply " + why);
  if (std::find(doc.model_settings.begin(), doc.model_settings.end(), "plane_z_mm") !=
      doc.model_settings.end())
    bad_input("model.plane_z_mm: does not apply " + why);
}

}  // namespace tp
