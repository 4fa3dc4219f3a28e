#include "cli/array_options.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "io/number.hpp"
#include "model/conductor.hpp"
#include "model/ranges.hpp"

namespace tp::cli {

CLI::Option* add_array_options(CLI::App& app, ArrayOptions& o, const std::string& config_help) {
  auto* config = app.add_option("--config", o.config, config_help)->type_name("FILE");
  auto* n = app.add_option("--electrodes", o.electrodes,
                           "Number of electrodes of a uniform array, 1 to 64 [8]")
                ->type_name("N");
  auto* pitch =
      app.add_option("--pitch", o.pitch, "Electrode pitch, mm, 0.01 to 100 [1]")->type_name("MM");
  config->excludes(n)->excludes(pitch);
  return config;
}

Document load_document(const ArrayOptions& o, int min_electrodes) {
  if (!o.config.empty()) return document_from_json(read_json(o.config, "--config"));
  Document doc;
  doc.setup.array = array_from_flags(o.electrodes, o.pitch, min_electrodes);
  return doc;
}

void add_model_options(CLI::App& app, ModelOptions& o) {
  app.add_option(o.flag, o.model,
                 "Conductor model: line2d (the paper's), strip2d, point3d or rect3d (3-D, "
                 "half-space), layered (3-D, layered skin) [the document's, or line2d]")
      ->type_name("NAME");
  app.add_option("--z", o.plane_z,
                 "3-D models: the fibres' plane along the electrodes' length, mm, within +-500 "
                 "(0: their middle) [the document's, or 0]")
      ->type_name("MM");
  app.add_option("--skin", o.skin,
                 "layered model: the skin's layers, fingertip (hydrated, electrode gel), "
                 "fingertip-dry, or a skin file (JSON; - for stdin) [the document's, or fingertip]")
      ->type_name("NAME|FILE");
}

void apply_model_options(Document& doc, const ModelOptions& o) {
  if (!o.model.empty()) doc.setup.conductor.model = o.model;
  const std::string& model = doc.setup.conductor.model;
  // Nothing given may be silently ignored: neither a flag nor a setting of the document
  // that the (possibly new) model does not use.
  const std::string how = o.model.empty() ? "" : " (from " + o.flag + ")";
  const auto& known = conductor_models();
  if (std::find(known.begin(), known.end(), model) == known.end())
    bad_input(o.flag + ": unknown conductor model '" + model + "' (expected " +
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

}  // namespace tp::cli
