#pragma once
// The fibre models behind one interface: a model builds the compartments of an axon of a
// given diameter and node count, and its node kinetics.  Models: "mrg" (McIntyre,
// Richardson & Grill 2002, double cable, 37 C) and "senn" (McNeal 1976 / Reilly 1985,
// Frankenhaeuser-Huxley nodes joined by axoplasm, myelin a perfect insulator).

#include <memory>
#include <string>
#include <vector>

#include "fibre/axon.hpp"
#include "fibre/kinetics.hpp"

namespace tp::fibre {

class FibreModel {
 public:
  virtual ~FibreModel() = default;
  virtual const char* name() const = 0;
  // The diameters (um) the model has a geometry for, inclusive.
  virtual double min_diameter_um() const = 0;
  virtual double max_diameter_um() const = 0;
  // Node-to-node distance of a fibre of this diameter (um).
  virtual double internode_um(double diameter_um) const = 0;
  // The axon: `nodes` nodes of Ranvier, the first at 0, with everything between them.
  // Throws tp::Error (bad input) for a diameter outside the model's range.
  Axon axon(double diameter_um, std::size_t nodes) const {
    return axon_with_internodes(
        diameter_um, std::vector<double>(nodes > 0 ? nodes - 1 : 0, internode_um(diameter_um)));
  }
  // The same with each internode's node-to-node length given (um, one fewer than the nodes):
  // MRG shortens an internode by shortening its paranodes (FLUT) and internodal segments
  // (STIN) in proportion, keeping the node and MYSA; bad input below 20 um or above the
  // model's own length, and for a model that cannot vary them (SENN's are uniform).
  virtual Axon axon_with_internodes(double diameter_um,
                                    const std::vector<double>& internodes_um) const = 0;
  // An unmyelinated, passive ending compartment (CompartmentKind::ending) of this length
  // and diameter, with the model's axoplasm and membrane (docs/fibres.md, "Afferents").
  virtual Compartment ending(double length_um, double diameter_um) const = 0;
  virtual const NodeKinetics& kinetics() const = 0;
  // The membrane potential every compartment starts from (mV).
  virtual double initial_mV() const = 0;
};

std::unique_ptr<FibreModel> make_fibre_model(const std::string& name);

// SENN's constants (defaults: McNeal 1976 Table I as used by Reilly, Freeman & Larkin 1985;
// sources in docs/fibres.md).  A node of width gap_um and diameter node_ratio * D every
// internode_ratio * D + gap_um; between nodes, axoplasm of the node's diameter.
struct SennParams {
  double node_ratio = 0.7;         // axon (and node) diameter / fibre diameter
  double internode_ratio = 100.0;  // internode (myelinated) length / fibre diameter
  double gap_um = 2.5;             // node width
  double rho_i_ohm_cm = 110.0;     // axoplasm
  double c_m_uF_cm2 = 2.0;         // nodal membrane
  double initial_mV = -70.0;       // the resting potential
  FhParams fh = mcneal_fh();
  static FhParams mcneal_fh() {
    FhParams f;
    f.celsius = 295.18 - 273.15;  // GHK at McNeal's 295.18 K; FH's rates unscaled
    f.rate_celsius = 20.0;
    f.e_l_mV = -70.0 + 0.026;  // V_L = 0.026 mV above rest
    f.na_i_mM = 13.7;
    return f;
  }
  // The constants of Reilly 2016's NEURON benchmark (ModelDB 239006, axon10.hoc, fh.mod).
  static SennParams reilly2016() {
    SennParams p;
    p.rho_i_ohm_cm = 100.0;
    p.initial_mV = -69.77;
    p.fh = FhParams{};
    return p;
  }
};
std::unique_ptr<FibreModel> make_senn(const SennParams& params);
const std::vector<std::string>& fibre_models();  // "mrg", "senn"

// MRG's geometry at one diameter (MRGaxon.hoc's table for 5.7-16 um; between 2 and 16 um,
// the interpolation fibre-modelling tools use: docs/fibres.md).
struct MrgGeometry {
  double fibre_um, axon_um, node_um, mysa_um, flut_um;  // diameters
  double internode_um, flut_length_um;                  // deltax, paralength2
  double lamellae;                                      // nl
};
MrgGeometry mrg_geometry(double diameter_um);
// True where the published table has the diameter (else the interpolation is used).
bool mrg_tabulated(double diameter_um);

}  // namespace tp::fibre
