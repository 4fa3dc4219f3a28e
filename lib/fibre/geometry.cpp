// The afferent's path and compartments (geometry.hpp).

#include "fibre/geometry.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/number.hpp"

namespace tp::fibre {

const char* to_string(Geometry g) {
  return g == Geometry::afferent ? "afferent" : "straight";
}

Geometry geometry_from_string(const std::string& name) {
  if (name == "straight") return Geometry::straight;
  if (name == "afferent") return Geometry::afferent;
  bad_input("--geometry: unknown fibre geometry " + quoted_text(name) + " (straight or afferent)");
}

Axon afferent_axon(const FibreModel& model, double d, double drop_mm, int direction, double stem_mm,
                   const AfferentShape& shape) {
  constexpr double kPi = 3.14159265358979323846;
  const double R = shape.bend_radius_mm;
  const double ending_mm = shape.ending_um * 1e-3;
  const double short_mm =
      static_cast<double>(shape.short_internodes) * shape.short_internode_um * 1e-3;
  // The vertical run (ending included) ends where the bend begins, R above the stem.
  const double vertical_mm = drop_mm - R;
  if (!(vertical_mm >= ending_mm + short_mm))
    bad_input("afferent: a drop of " + number_text(drop_mm) +
              " mm from the receptor's top to its stem cannot hold the ending (" +
              number_text(ending_mm) + " mm), its short internodes (" + number_text(short_mm) +
              " mm) and the bend (" + number_text(R) + " mm): a deeper receptor range");
  if (!(stem_mm > 0) || (direction != 1 && direction != -1))
    bad_input("afferent: a stem of " + number_text(stem_mm) + " mm toward " +
              std::to_string(direction));
  // Myelinated length from the heminode: the rest of the vertical run, the bend, the stem.
  const double L_mm = model.internode_um(d) * 1e-3;
  const double myelinated_mm = vertical_mm - ending_mm + 0.5 * kPi * R + stem_mm;
  std::vector<double> internodes(shape.short_internodes, shape.short_internode_um);
  const auto regular =
      static_cast<std::size_t>(std::ceil((myelinated_mm - short_mm) / L_mm - 1e-9));
  internodes.insert(internodes.end(), regular, model.internode_um(d));
  const Axon myelinated = model.axon_with_internodes(d, internodes);

  Axon a;
  a.model = myelinated.model;
  a.diameter_um = d;
  a.double_cable = myelinated.double_cable;
  a.internode_um = myelinated.internode_um;
  // The path's name keys cached potentials: everything that places its compartments.
  a.path = std::string(direction > 0 ? "afferent+x" : "afferent-x") + " drop " +
           number_text(drop_mm) + " stem " + number_text(stem_mm) + " ending " +
           number_text(shape.ending_um) + "/" + number_text(shape.ending_diameter_um) + "/" +
           std::to_string(shape.ending_compartments) + " short " +
           std::to_string(shape.short_internodes) + "x" + number_text(shape.short_internode_um) +
           " bend " + number_text(R);
  const double piece_um = shape.ending_um / static_cast<double>(shape.ending_compartments);
  double s_um = 0.0;  // arc length from the tip
  for (std::size_t k = 0; k < shape.ending_compartments; ++k) {
    a.compartments.push_back(model.ending(piece_um, shape.ending_diameter_um));
    a.centre_um.push_back(s_um + 0.5 * piece_um);
    s_um += piece_um;
  }
  // The heminode's 1 um begins where the ending ends; the myelinated axon's centres are
  // from its centre.
  const double heminode_centre_um = s_um + 0.5 * myelinated.compartments.front().length_um;
  for (std::size_t k = 0; k < myelinated.compartments.size(); ++k) {
    a.compartments.push_back(myelinated.compartments[k]);
    a.centre_um.push_back(heminode_centre_um + myelinated.centre_um[k]);
  }
  for (std::size_t n : myelinated.nodes) a.nodes.push_back(n + shape.ending_compartments);
  // The path: straight down from the tip to vertical_mm, a quarter circle of radius R, then
  // along x at drop_mm.
  const double arc_mm = 0.5 * kPi * R;
  for (double c_um : a.centre_um) {
    const double s = c_um * 1e-3;
    double x, y;
    if (s <= vertical_mm) {
      x = 0.0;
      y = s;
    } else if (s <= vertical_mm + arc_mm) {
      const double t = (s - vertical_mm) / R;
      x = R * (1.0 - std::cos(t));
      y = vertical_mm + R * std::sin(t);
    } else {
      x = R + (s - vertical_mm - arc_mm);
      y = drop_mm;
    }
    a.path_x_mm.push_back(direction * x);
    a.path_y_mm.push_back(y);
  }
  return a;
}

}  // namespace tp::fibre
