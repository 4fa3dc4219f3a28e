#pragma once
// The project's JSON document: array geometry, model, receptors and weights.  Every
// program reads and writes this one format (docs/document-format.md); a program's own
// results are added as further keys, which other programs carry along untouched.

#include <optional>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "model/field.hpp"

namespace tp {

inline constexpr const char* kDocumentFormat = "tactile-primaries/1";
inline constexpr double kDefaultMaxCurrent_mA = 2.0;  // paper, Sec. 6

struct Document {
  Setup setup;
  std::optional<std::vector<double>> weights;  // positive = cathodic; |w| = 1 -> amplitude
  double max_current_mA = kDefaultMaxCurrent_mA;
  Json extra = Json::object();  // every other key, carried along in order
};

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

}  // namespace tp
