// The registry of conductor models.

#include "model/conductor.hpp"

#include "core/error.hpp"
#include "core/text.hpp"
#include "model/constants.hpp"

namespace tp {

const std::vector<std::string>& conductor_models() {
  static const std::vector<std::string> names = {"line2d", "strip2d", "point3d", "rect3d",
                                                 "layered"};
  return names;
}

std::string conductor_model_list() {
  const auto& m = conductor_models();
  std::string s;
  for (std::size_t i = 0; i < m.size(); ++i)
    s += (i == 0 ? "" : i + 1 == m.size() ? " or " : ", ") + m[i];
  return s;
}

const Skin& effective_skin(const ConductorParams& p) {
  return p.skin.layers.empty() ? builtin_skin("fingertip") : p.skin;
}

void Conductor::unit_d2_along(double, double, double, const FibreAxis&, double*) const {
  failure(std::string(name()) + ": no 3-D evaluation");
}
void Conductor::unit_potentials_3d(double, double, double, double*) const {
  failure(std::string(name()) + ": no 3-D evaluation");
}

std::unique_ptr<Conductor> make_conductor(const ConductorParams& params,
                                          const ElectrodeArray& array) {
  if (array.two_d() && (params.model == "line2d" || params.model == "strip2d"))
    bad_input("model.conductor: " + params.model +
              " is a 2-D model (electrodes infinitely long "
              "along z) and takes no 2-D array (" +
              array.describe() + "); use point3d, rect3d or layered");
  const double rho = params.resistivity_ohm_m > 0.0 ? params.resistivity_ohm_m
                                                    : constants::tissue_resistivity_ohm_m;
  if (params.model == "line2d") return make_line2d(array, rho);
  if (params.model == "strip2d") return make_strip2d(array, rho);
  if (params.model == "point3d")
    return make_point3d(array, rho, params.plane_z_mm, params.source_depth_mm);
  if (params.model == "rect3d") return make_rect3d(array, rho, params.plane_z_mm);
  if (params.model == "layered") {
    return make_layered(array, effective_skin(params).layers, params.plane_z_mm);
  }
  bad_input("unknown conductor model " + quoted_text(params.model) + " (expected " +
            conductor_model_list() + ")");
}

}  // namespace tp
