#pragma once
// Where a receptor's fibre runs (docs/fibres.md, "Afferent geometry").
//
//  - straight: the paper's fibres.  A horizontal fibre along x; a vertical one from a
//    sealed node at the receptor's top straight down through its range and beyond.
//  - afferent: a vertical (RA) receptor's fibre as the anatomy has it.  An unmyelinated
//    ending in the corpuscle at the receptor's top, the heminode where the myelin ends
//    below it, an ascending myelinated axon whose last internodes are short, a bend at
//    the bottom of the receptor's range into a horizontal stem in the dermal nerve plexus,
//    which runs along x to either side.  Horizontal receptors keep straight fibres.

#include <cstddef>
#include <string>

#include "fibre/axon.hpp"
#include "fibre/models.hpp"

namespace tp::fibre {

enum class Geometry { straight, afferent };
const char* to_string(Geometry g);
Geometry geometry_from_string(const std::string& name);  // bad input names --geometry

// The afferent's shape.  Sources and assumptions: docs/fibres.md, "Afferent geometry".
struct AfferentShape {
  double ending_um = 80.0;          // the ending's length: a Meissner corpuscle's long axis
  double ending_diameter_um = 1.5;  // assumption: thin unmyelinated branches
  std::size_t ending_compartments = 4;
  std::size_t short_internodes = 4;  // the last four internodes before the ending
  double short_internode_um = 80.0;  // their length (Nolano et al. 2003: 79.1 +- 13.8 um)
  double bend_radius_mm = 0.1;       // assumption
};

// The afferent of a fibre of diameter d: the ending's tip at the path's origin, the bend's
// end (the stem's depth) drop_mm below it, the stem running `direction` (+1: toward +x,
// -1: toward -x) at least stem_mm beyond the bend.  Nodes: the heminode is Axon::nodes[0],
// the stem's far end the last.  Bad input when the drop cannot hold the ending, the short
// internodes and the bend, or for a model without afferents (SENN).
Axon afferent_axon(const FibreModel& model, double diameter_um, double drop_mm, int direction,
                   double stem_mm, const AfferentShape& shape = {});

}  // namespace tp::fibre
