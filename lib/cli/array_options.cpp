#include "cli/array_options.hpp"

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

}  // namespace tp::cli
