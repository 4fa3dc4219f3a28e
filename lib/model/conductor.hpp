#pragma once
// Volume-conductor models: the extracellular potential Psi set up by the electrode currents.
//
// A conductor gives, for a unit (1 mA, cathodic) current on each electrode, the second
// derivatives of Psi at a point.  Psi is linear in the currents, so the field of any current
// pattern is the weighted sum (Eq. 25); the optimiser uses the per-electrode responses
// directly.  Models: line2d and strip2d (2-D, the paper's), point3d and rect3d (3-D
// half-space), layered (rectangles on a layered skin); each is registered in make_conductor()
// (model/conductor.cpp).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "model/array.hpp"
#include "model/skin.hpp"

namespace tp {

// The direction of a fibre, for the 3-D evaluation: vertical (along y, into the skin) or
// horizontal at an azimuth in the skin plane, (cos, 0, sin) of the angle from x toward z.
struct FibreAxis {
  bool vertical = false;
  double cos_az = 1.0, sin_az = 0.0;
};

struct ConductorParams {
  std::string model = "line2d";    // one of conductor_models()
  double resistivity_ohm_m = 0.0;  // 0: constants::tissue_resistivity_ohm_m
  double plane_z_mm = 0.0;         // 3-D models: the fibres' plane, along the electrodes' length
  double source_depth_mm = 0.0;    // point3d: depth of the point sources (0: on the surface)
  Skin skin;                       // layered: the layers (empty: the built-in "fingertip")
};

class Conductor {
 public:
  virtual ~Conductor() = default;
  virtual const char* name() const = 0;
  virtual std::size_t size() const = 0;  // number of electrodes

  // For 1 mA cathodic on electrode i alone: d2Psi/dx2 into xx[i] and d2Psi/dy2 into yy[i],
  // in V/mm^2, at (x_mm, y_mm) with y_mm > 0.  Either pointer may be null.
  virtual void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const = 0;

  // Psi (V) at (x_mm, y_mm) for 1 mA cathodic on each electrode alone, up to a constant
  // (the 2-D models have no zero at infinity).  Used to check the derivatives.
  virtual void unit_potentials(double x_mm, double y_mm, double* psi) const = 0;

  // Bad input when the potentials or second derivatives at a depth in [y_min_mm, y_max_mm]
  // and lateral offsets up to max_offset_mm from the electrodes could not be evaluated (the
  // layered model's Hankel rule is bounded); `what` names those points in the message
  // ("receptor SAI's fibres").  Called before any work or output, so that none fails
  // half-way: af-field's grid (check_grid), each receptor's fibre region
  // (check_fibre_reach), each simulated fibre (fibre::fibre_nodes).  Every other point of
  // the model's range can be evaluated.
  virtual void check_reach(double /*max_offset_mm*/, double /*y_min_mm*/, double /*y_max_mm*/,
                           const std::string& /*what*/) const {}

  // The 3-D models: for 1 mA cathodic on pad i alone, the second derivative of Psi along a
  // fibre's axis, in V/mm^2, at (x_mm, y_mm, z_mm) with y_mm > 0, into out[i].  Pads lie at
  // (positions_mm[i], 0, z_of(i)): a 1-D array's at z = 0 (plane_z_mm is not used here).
  // Only the models with three_d() give it (make_conductor refuses a 2-D array for others).
  virtual bool three_d() const { return false; }
  virtual void unit_d2_along(double /*x_mm*/, double /*y_mm*/, double /*z_mm*/,
                             const FibreAxis& /*axis*/, double* /*out*/) const;
  // Psi (V) at (x_mm, y_mm, z_mm) for 1 mA cathodic on each pad alone (the checks).
  virtual void unit_potentials_3d(double /*x_mm*/, double /*y_mm*/, double /*z_mm*/,
                                  double* /*psi*/) const;

  // The depth (mm) of the point sources that stand for the pads, one under each pad's
  // centre (positions_mm[i], depth, z_of(i)), where Psi is singular inside the conductor;
  // 0 when no source lies below the surface (every model but point3d with a
  // source_depth_mm).  What the checks need to keep fibres, grids and planes clear of the
  // singularities (fibre::fibre_nodes, validate_setup, check_grid, check_plane).
  virtual double buried_source_depth_mm() const { return 0.0; }

  // Pad i's spreading (access) resistance in kOhm, the series resistance of the
  // electrode-skin interface (device/skin_circuit.hpp): the mean potential over the pad for
  // 1 mA through it alone, where the model can give it.  rect3d gives the closed form of a
  // uniformly loaded rectangle on a half-space (docs/skin.md); none elsewhere (the 2-D
  // models have no zero at infinity, a point source's own potential is infinite, and the
  // layered model's is not done).
  virtual std::optional<double> spreading_resistance_kohm(std::size_t /*pad*/) const {
    return std::nullopt;
  }

  // Depths (mm) where the conductor's resistivity changes (the layered model's interfaces):
  // Psi is harmonic in space between them.
  virtual std::vector<double> interfaces_mm() const { return {}; }

  // True when Psi is harmonic in the (x, y) plane, so that the AF of either orientation
  // is harmonic too (Eq. 28-30) and obeys the maximum principle.
  virtual bool planar_harmonic() const = 0;
};

std::unique_ptr<Conductor> make_conductor(const ConductorParams& params,
                                          const ElectrodeArray& array);

// The model names make_conductor() knows, and "a, b or c" of them for messages.
const std::vector<std::string>& conductor_models();
std::string conductor_model_list();

// The models themselves (model/line2d.cpp, model/halfspace3d.cpp).
std::unique_ptr<Conductor> make_line2d(const ElectrodeArray& array, double rho_ohm_m);
std::unique_ptr<Conductor> make_strip2d(const ElectrodeArray& array, double rho_ohm_m);
std::unique_ptr<Conductor> make_point3d(const ElectrodeArray& array, double rho_ohm_m,
                                        double plane_z_mm, double source_depth_mm);
std::unique_ptr<Conductor> make_rect3d(const ElectrodeArray& array, double rho_ohm_m,
                                       double plane_z_mm);
// rect3d's d2Psi/dz2 for electrode i (the tests' Laplace check); c must be a rect3d.
double rect3d_unit_zz(const Conductor& c, std::size_t i, double x_mm, double y_mm);
// The same at a 3-D point (pads of a 2-D array at their own z).
double rect3d_unit_zz_3d(const Conductor& c, std::size_t i, double x_mm, double y_mm, double z_mm);
// The layered model (model/layered_rect.cpp): rectangles on a layered half-space.
std::unique_ptr<Conductor> make_layered(const ElectrodeArray& array,
                                        const std::vector<Layer>& layers, double plane_z_mm);
double layered_unit_zz(const Conductor& c, std::size_t i, double x_mm, double y_mm);

}  // namespace tp
