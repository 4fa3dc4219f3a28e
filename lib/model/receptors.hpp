#pragma once
// Mechanoreceptor afferents: where their fibres run and how excitable they are.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "model/conductor.hpp"
#include "model/fibre_factor.hpp"

namespace tp {

struct Receptor {
  std::string name;         // "RA", "SAI", "PC": also the name of the mode that targets it
  Fibre fibre;              // orientation, diameter, myelination
  double depth_min_mm = 0;  // horizontal: fibres at every depth in [min, max];
  double depth_max_mm = 0;  // vertical: the segment from the top (min) down to max
  // Horizontal fibres under a 2-D array: the angle in the skin plane from x (the finger's
  // long axis) toward z, degrees in [-180, 180] (0: along x).
  double azimuth_deg = 0;
};

// The axis a receptor's fibres run along (conductor.hpp).
FibreAxis fibre_axis(const Receptor& r);

// Parses {"receptors": [...]} or a bare array (format in docs/document-format.md).
std::vector<Receptor> receptors_from_json(const nlohmann::ordered_json& j);
nlohmann::ordered_json receptors_to_json(const std::vector<Receptor>& receptors);

// The defaults, from data/receptors.json (compiled in).
const std::vector<Receptor>& default_receptors();

const char* to_string(Orientation o);

}  // namespace tp
