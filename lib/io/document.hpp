#pragma once
// The project's JSON document: array geometry, model, receptors and weights.  Every
// program reads and writes this one format (docs/document-format.md); a program's own
// results are added as further keys, which other programs carry along untouched.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "model/field.hpp"

namespace tp {

inline constexpr const char* kDocumentFormat = "tactile-primaries/1";
inline constexpr double kDefaultMaxCurrent_mA = 2.0;  // paper, Sec. 6

struct Document {
  Setup setup;
  std::optional<std::vector<double>> weights;  // positive = cathodic; |w| = 1 -> amplitude
  double max_current_mA = kDefaultMaxCurrent_mA;
  Json extra = Json::object();  // every other key, carried along in order
  // The model settings the document gave (keys of "model" other than conductor and
  // lateral_margin_mm), so that a later change of conductor (--model) can refuse those that
  // the new model would silently ignore.
  std::vector<std::string> model_settings;
};

// Whether conductor model `model` uses the model setting `key` (resistivity_ohm_m,
// plane_z_mm, source_depth_mm, skin; every model uses conductor and lateral_margin_mm).
bool model_uses(const std::string& model, const std::string& key);
// Refuses (bad input) a setting that `model` does not use, naming it as `name` and saying
// which models use it; `how` says where the model came from, e.g. "" or " (from --model)".
void check_setting_applies(const std::string& model, const std::string& key,
                           const std::string& name, const std::string& how = "");

// Parses a document; throws tp::Error (bad input) naming the field at fault.
Document document_from_json(const Json& j);

// A uniform array from the --electrodes and --pitch flags (empty: 8 electrodes, 1 mm);
// bad input names the flag.
ElectrodeArray array_from_flags(const std::string& electrodes, const std::string& pitch,
                                int min_electrodes);

Json array_to_json(const ElectrodeArray& a);
Json model_to_json(const Setup& s);
// The document's own keys (format, array, model, receptors, weights, max_current_mA),
// followed by `extra`.
Json document_to_json(const Document& d);

// Where the fibres under a 2-D array pass (fiber-threshold --at): `at` (X,Z, mm), or the
// document's focus (optimize-weights --at); none for a 1-D array, or a 2-D one with
// neither.  Bad input: `at` for a 1-D array, not two values (`at_text`: as it was given),
// a malformed focus.
std::optional<std::array<double, 2>> fibre_point(const Document& doc,
                                                 const std::optional<std::vector<double>>& at,
                                                 const std::string& at_text);

}  // namespace tp
