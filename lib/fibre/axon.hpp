#pragma once
// A myelinated axon discretised into compartments: the electrical network the simulator
// integrates.  Built by a fibre model (fibre/models.hpp) for a diameter and a number of
// nodes, along a straight line; or laid along a path (fibre/geometry.hpp: an afferent that
// ends in the skin and bends into a stem).
//
// Each compartment has an intracellular node joined to its neighbours through the axoplasm.
// In a double cable (MRG) it also has a periaxonal node, joined to its neighbours through
// the periaxonal space and to the extracellular potential through the myelin sheath (a
// conductance and a capacitance); the membrane (capacitance, passive or active current)
// sits between the two.  In a single cable (SENN) the membrane faces the extracellular
// potential directly.  Units: kOhm, mS, uF, mV, ms, uA.

#include <cstddef>
#include <string>
#include <vector>

namespace tp::fibre {

// ending: an unmyelinated, passive terminal (an afferent's ending, geometry.hpp), whose
// membrane faces the extracellular potential as a node's does.
enum class CompartmentKind { node, mysa, flut, stin, ending };

struct Compartment {
  CompartmentKind kind = CompartmentKind::node;
  double length_um = 0.0;
  double area_cm2 = 0.0;      // membrane area
  double c_uF = 0.0;          // membrane capacitance
  double ri_half_kohm = 0.0;  // axoplasm, centre to either end
  double rp_half_kohm = 0.0;  // periaxonal space, centre to either end (double cable)
  double g_sheath_mS = 0.0;   // periaxonal node to outside (double cable)
  double c_sheath_uF = 0.0;
  double g_pas_mS = 0.0;  // passive membrane (compartments other than nodes)
  double e_pas_mV = 0.0;
};

struct Axon {
  std::string model;  // "mrg", "senn"
  double diameter_um = 0.0;
  bool double_cable = false;
  double internode_um = 0.0;  // node-to-node distance
  std::vector<Compartment> compartments;
  // Each compartment's centre along the axon: from the first node's centre (a straight
  // fibre), or from the tip of the ending (a path's).
  std::vector<double> centre_um;
  std::vector<std::size_t> nodes;  // compartment index of each node of Ranvier, in order
  double length_um() const { return centre_um.empty() ? 0.0 : centre_um.back(); }
  // A fibre laid along a path: its name ("afferent+x ..." with every dimension that places
  // its compartments: what potentials are cached under) and each compartment centre's place
  // in mm from the path's origin (x along the skin, y down into it).  Empty for a straight
  // fibre.
  std::string path;
  std::vector<double> path_x_mm, path_y_mm;
};

}  // namespace tp::fibre
