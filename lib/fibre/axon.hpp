#pragma once
// A myelinated axon discretised into compartments along a straight line: the electrical
// network the simulator integrates.  Built by a fibre model (fibre/models.hpp) for a
// diameter and a number of nodes.
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

enum class CompartmentKind { node, mysa, flut, stin };

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
  std::vector<double> centre_um;   // each compartment's centre, from the first node's centre
  std::vector<std::size_t> nodes;  // compartment index of each node of Ranvier, in order
  double length_um() const { return centre_um.empty() ? 0.0 : centre_um.back(); }
};

}  // namespace tp::fibre
