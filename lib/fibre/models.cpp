// The fibre models: MRG (double cable) and SENN (single cable of nodes).  Geometry and
// electrical constants with their sources: docs/fibres.md.

#include "fibre/models.hpp"

#include <array>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/number.hpp"

namespace tp::fibre {
namespace {

constexpr double kPi = 3.14159265358979323846;

// um -> cm, um^2 -> cm^2.
constexpr double kCmPerUm = 1e-4;
constexpr double kCm2PerUm2 = 1e-8;

// ---- MRG ---------------------------------------------------------------------------------

// MRGaxon.hoc (ModelDB 3810), after McIntyre, Richardson & Grill 2002, Table 1:
// fibre, axon, node, MYSA, FLUT diameters, deltax, FLUT length, lamellae.
constexpr std::array<MrgGeometry, 9> kMrgTable{{
    {5.7, 3.4, 1.9, 1.9, 3.4, 500.0, 35.0, 80.0},
    {7.3, 4.6, 2.4, 2.4, 4.6, 750.0, 38.0, 100.0},
    {8.7, 5.8, 2.8, 2.8, 5.8, 1000.0, 40.0, 110.0},
    {10.0, 6.9, 3.3, 3.3, 6.9, 1150.0, 46.0, 120.0},
    {11.5, 8.1, 3.7, 3.7, 8.1, 1250.0, 50.0, 130.0},
    {12.8, 9.2, 4.2, 4.2, 9.2, 1350.0, 54.0, 135.0},
    {14.0, 10.4, 4.7, 4.7, 10.4, 1400.0, 56.0, 140.0},
    {15.0, 11.5, 5.0, 5.0, 11.5, 1450.0, 58.0, 145.0},
    {16.0, 12.7, 5.5, 5.5, 12.7, 1500.0, 60.0, 150.0},
}};

constexpr double kMrgMinDiameter = 2.0, kMrgMaxDiameter = 16.0;

// MRG's electrical constants (MRGaxon.hoc): axoplasm 0.7e6 ohm um = 70 ohm cm; membrane
// 2 uF/cm^2; myelin 0.1 uF/cm^2 and 0.001 S/cm^2 per lamella membrane; periaxonal space
// widths 0.002 um (node, MYSA) and 0.004 um (FLUT, STIN); passive membrane 0.001 S/cm^2
// (MYSA) and 0.0001 S/cm^2 (FLUT, STIN) at -80 mV.
constexpr double kRhoAxOhmCm = 70.0;
constexpr double kRhoAxOhmUm = 0.7e6;
constexpr double kCmUfPerCm2 = 2.0;
constexpr double kMyelinCUfPerCm2 = 0.1, kMyelinGSPerCm2 = 0.001;
constexpr double kSpaceNodeUm = 0.002, kSpaceFlutUm = 0.004, kSpaceStinUm = 0.004;
constexpr double kGMysa = 0.001, kGFlutStin = 0.0001, kEPas = -80.0;
constexpr double kNodeSheathG = 1e10;  // S/cm^2: the node's periaxonal node is the outside

// Periaxonal resistance per length of an annulus `space` wide around diameter d, kOhm/um.
double periaxonal_kohm_per_um(double d_um, double space_um) {
  const double annulus_um2 =
      kPi * ((d_um / 2 + space_um) * (d_um / 2 + space_um) - d_um * d_um / 4);
  return kRhoAxOhmUm / annulus_um2 * 1e-3;  // ohm/um -> kOhm/um
}

class Mrg final : public FibreModel {
 public:
  Mrg() : node_(make_mrg_node(37.0)) {}
  const char* name() const override { return "mrg"; }
  double min_diameter_um() const override { return kMrgMinDiameter; }
  double max_diameter_um() const override { return kMrgMaxDiameter; }
  double internode_um(double d) const override { return mrg_geometry(d).internode_um; }
  const NodeKinetics& kinetics() const override { return *node_; }
  double initial_mV() const override { return -80.0; }

  Axon axon_with_internodes(double d, const std::vector<double>& internodes_um) const override {
    const MrgGeometry g = mrg_geometry(d);
    for (double L : internodes_um)
      if (!(L >= kMinInternodeUm && L <= g.internode_um))
        bad_input("mrg: an internode of " + number_beside(L, kMinInternodeUm, g.internode_um) +
                  " um at " + number_text(d) + " um (from " + number_text(kMinInternodeUm) +
                  " um to the model's " + number_text(g.internode_um) + " um)");
    const std::size_t nodes = internodes_um.size() + 1;
    Axon a;
    a.model = "mrg";
    a.diameter_um = d;
    a.double_cable = true;
    a.internode_um = g.internode_um;
    // Node (1 um) and two MYSA (3 um) keep their lengths; the rest (two FLUT, six STIN)
    // scales to the internode's length: 1 at the model's own.
    const double fixed_um = 1.0 + 2 * 3.0;
    const double stin_um = (g.internode_um - fixed_um - 2 * g.flut_length_um) / 6.0;
    const double sheath_g = kMyelinGSPerCm2 / (2 * g.lamellae);
    const double sheath_c = kMyelinCUfPerCm2 / (2 * g.lamellae);

    auto add = [&](CompartmentKind kind, double length, double inner, double space) {
      Compartment c;
      c.kind = kind;
      c.length_um = length;
      // NEURON's section: diameter fibre_um (node: node_um), with Ra and cm scaled so that
      // the axoplasm and the membrane are the inner diameter's (MRGaxon.hoc).
      const double outer = kind == CompartmentKind::node ? g.node_um : g.fibre_um;
      c.area_cm2 = kPi * outer * length * kCm2PerUm2;
      const double ratio = inner / outer;
      const double ra_ohm_cm = kRhoAxOhmCm / (ratio * ratio);
      c.ri_half_kohm =
          ra_ohm_cm * (0.5 * length * kCmPerUm) / (kPi * outer * outer / 4 * kCm2PerUm2) * 1e-3;
      c.c_uF = kCmUfPerCm2 * ratio * c.area_cm2;
      c.rp_half_kohm = periaxonal_kohm_per_um(inner, space) * 0.5 * length;
      if (kind == CompartmentKind::node) {
        c.g_sheath_mS = kNodeSheathG * c.area_cm2 * 1e3;
        c.c_sheath_uF = 0.0;
      } else {
        c.g_sheath_mS = sheath_g * c.area_cm2 * 1e3;
        c.c_sheath_uF = sheath_c * c.area_cm2;
        c.g_pas_mS =
            (kind == CompartmentKind::mysa ? kGMysa : kGFlutStin) * ratio * c.area_cm2 * 1e3;
        c.e_pas_mV = kEPas;
      }
      a.compartments.push_back(c);
    };
    for (std::size_t i = 0; i < nodes; ++i) {
      a.nodes.push_back(a.compartments.size());
      add(CompartmentKind::node, 1.0, g.node_um, kSpaceNodeUm);
      if (i + 1 == nodes) break;
      const double L = internodes_um[i];
      const double scale = L == g.internode_um ? 1.0 : (L - fixed_um) / (g.internode_um - fixed_um);
      add(CompartmentKind::mysa, 3.0, g.mysa_um, kSpaceNodeUm);
      add(CompartmentKind::flut, g.flut_length_um * scale, g.flut_um, kSpaceFlutUm);
      for (int k = 0; k < 6; ++k)
        add(CompartmentKind::stin, stin_um * scale, g.axon_um, kSpaceStinUm);
      add(CompartmentKind::flut, g.flut_length_um * scale, g.flut_um, kSpaceFlutUm);
      add(CompartmentKind::mysa, 3.0, g.mysa_um, kSpaceNodeUm);
    }
    double s = -0.5;  // the first node (1 um long) is centred on 0
    for (const Compartment& c : a.compartments) {
      a.centre_um.push_back(s + 0.5 * c.length_um);
      s += c.length_um;
    }
    return a;
  }

  // An unmyelinated ending: MRG's axoplasm and membrane capacitance, the leak of its FLUT and
  // STIN at rest, the periaxonal node shorted to the outside as at a node.
  Compartment ending(double length_um, double d) const override {
    Compartment c;
    c.kind = CompartmentKind::ending;
    c.length_um = length_um;
    c.area_cm2 = kPi * d * length_um * kCm2PerUm2;
    c.c_uF = kCmUfPerCm2 * c.area_cm2;
    c.ri_half_kohm =
        kRhoAxOhmCm * (0.5 * length_um * kCmPerUm) / (kPi * d * d / 4 * kCm2PerUm2) * 1e-3;
    c.rp_half_kohm = periaxonal_kohm_per_um(d, kSpaceNodeUm) * 0.5 * length_um;
    c.g_sheath_mS = kNodeSheathG * c.area_cm2 * 1e3;
    c.g_pas_mS = kGFlutStin * c.area_cm2 * 1e3;
    c.e_pas_mV = kEPas;
    return c;
  }

 private:
  static constexpr double kMinInternodeUm = 20.0;
  std::unique_ptr<NodeKinetics> node_;
};

// ---- SENN --------------------------------------------------------------------------------

constexpr double kSennMinDiameter = 1.0, kSennMaxDiameter = 30.0;

class Senn final : public FibreModel {
 public:
  explicit Senn(const SennParams& p) : p_(p), node_(make_fh_node(p.fh)) {}
  const char* name() const override { return "senn"; }
  double min_diameter_um() const override { return kSennMinDiameter; }
  double max_diameter_um() const override { return kSennMaxDiameter; }
  double internode_um(double d) const override { return p_.internode_ratio * d + p_.gap_um; }
  const NodeKinetics& kinetics() const override { return *node_; }
  double initial_mV() const override { return p_.initial_mV; }

  Compartment ending(double, double) const override {
    bad_input(
        "senn: no afferent geometry (its internodes are uniform): --model mrg, or "
        "--geometry straight");
  }

  Axon axon_with_internodes(double d, const std::vector<double>& internodes_um) const override {
    for (double L : internodes_um)
      if (L != internode_um(d))
        bad_input(
            "senn: no afferent geometry (its internodes are uniform): --model mrg, or "
            "--geometry straight");
    const std::size_t nodes = internodes_um.size() + 1;
    if (!(d >= kSennMinDiameter && d <= kSennMaxDiameter))
      bad_input("senn: fibre diameter " + number_beside(d, kSennMinDiameter, kSennMaxDiameter) +
                " um outside the model's [" + number_text(kSennMinDiameter) + ", " +
                number_text(kSennMaxDiameter) + "] um");
    Axon a;
    a.model = "senn";
    a.diameter_um = d;
    a.double_cable = false;
    a.internode_um = internode_um(d);
    const double dn = p_.node_ratio * d;
    // Node centre to node centre through axoplasm of the node's diameter; half each side.
    const double r_link_kohm =
        p_.rho_i_ohm_cm * a.internode_um * kCmPerUm / (kPi * dn * dn / 4 * kCm2PerUm2) * 1e-3;
    for (std::size_t i = 0; i < nodes; ++i) {
      Compartment c;
      c.kind = CompartmentKind::node;
      c.length_um = p_.gap_um;
      c.area_cm2 = kPi * dn * p_.gap_um * kCm2PerUm2;
      c.c_uF = p_.c_m_uF_cm2 * c.area_cm2;
      c.ri_half_kohm = 0.5 * r_link_kohm;
      a.nodes.push_back(i);
      a.compartments.push_back(c);
      a.centre_um.push_back(a.internode_um * static_cast<double>(i));
    }
    return a;
  }

 private:
  SennParams p_;
  std::unique_ptr<NodeKinetics> node_;
};

}  // namespace

std::unique_ptr<FibreModel> make_senn(const SennParams& params) {
  return std::make_unique<Senn>(params);
}

MrgGeometry mrg_geometry(double d) {
  if (!(d >= kMrgMinDiameter && d <= kMrgMaxDiameter))
    bad_input("mrg: fibre diameter " + number_beside(d, kMrgMinDiameter, kMrgMaxDiameter) +
              " um outside the model's [" + number_text(kMrgMinDiameter) + ", " +
              number_text(kMrgMaxDiameter) + "] um");
  for (const MrgGeometry& g : kMrgTable)
    if (g.fibre_um == d) return g;
  // The interpolation of ASCENT and PyFibers (docs/fibres.md): quadratic fits of the table
  // in D, with a linear internode length below 5.643 um.
  MrgGeometry g{};
  g.fibre_um = d;
  g.node_um = 0.01093 * d * d + 0.1008 * d + 1.099;
  g.mysa_um = g.node_um;
  g.axon_um = 0.02361 * d * d + 0.3673 * d + 0.7122;
  g.flut_um = g.axon_um;
  g.internode_um = d >= 5.643 ? -8.215 * d * d + 272.4 * d - 780.2 : 81.08 * d + 37.84;
  g.flut_length_um = -0.1652 * d * d + 6.354 * d - 0.2862;
  g.lamellae = -0.4749 * d * d + 16.85 * d - 0.7648;
  return g;
}

bool mrg_tabulated(double d) {
  for (const MrgGeometry& g : kMrgTable)
    if (g.fibre_um == d) return true;
  return false;
}

std::unique_ptr<FibreModel> make_fibre_model(const std::string& name) {
  if (name == "mrg") return std::make_unique<Mrg>();
  if (name == "senn") return std::make_unique<Senn>(SennParams{});
  bad_input("--model: unknown fibre model " + quoted_text(name) + " (mrg or senn)");
}

const std::vector<std::string>& fibre_models() {
  static const std::vector<std::string> names{"mrg", "senn"};
  return names;
}

}  // namespace tp::fibre
