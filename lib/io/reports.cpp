#include "io/reports.hpp"

#include <cmath>

#include "core/error.hpp"
#include "io/csv.hpp"
#include "model/constants.hpp"
#include "core/ranges.hpp"

namespace tp {

namespace {

// An axis along the skin (MIN and MAX within the positions' range), and the grid's size.
void check_lateral(const Axis& a, const std::string& flag) {
  ranges::check(a.min, ranges::position_mm, flag + " MIN");
  ranges::check(a.max, ranges::position_mm, flag + " MAX");
}
void check_points(const Axis& a, const Axis& b) {
  const double points = static_cast<double>(a.count()) * static_cast<double>(b.count());
  if (points > ranges::max_grid_points)
    bad_input("grid: " + number_text(points) + " points, more than " +
              number_text(ranges::max_grid_points));
}

}  // namespace

void validate_grid(const Axis& x, const Axis& y) {
  if (!(y.min > 0.0)) bad_input("--y: depths must be > 0 mm (the skin surface is y = 0)");
  ranges::check(y.min, ranges::depth_mm, "--y MIN");
  ranges::check(y.max, ranges::depth_mm, "--y MAX");
  check_lateral(x, "--x");
  check_points(x, y);
}

namespace {

// Rows (a, b, af_h, af_v) over the grid a (inner) by b (outer): values(a, b, af_h, af_v).
template <class F>
void write_map(const ByteSink& out, const char* b_name, const Axis& a, const Axis& b, F&& values) {
  CsvWriter csv(out, 1 << 20);
  csv.header({"x_mm", b_name, "af_h", "af_v"});
  const std::size_t na = a.count(), nb = b.count();
  double row[4];
  for (std::size_t j = 0; j < nb; ++j) {
    row[1] = b.at(j);
    for (std::size_t i = 0; i < na; ++i) {
      row[0] = a.at(i);
      values(row[0], row[1], row[2], row[3]);
      csv.row(row, 4);
    }
  }
  csv.flush();
}

}  // namespace

void write_af_grid(const ByteSink& out, const Field& field, const Axis& x, const Axis& y) {
  validate_grid(x, y);
  const double k = fibre_factor_mm2_per_ms(
      Fibre{Orientation::horizontal, constants::reference_diameter_um, true});
  write_map(out, "y_mm", x, y, [&](double xv, double yv, double& h, double& v) {
    double xx = 0.0, yy = 0.0;
    field.second_derivatives(xv, yv, xx, yy);
    h = k * xx;
    v = k * yy;
  });
}

void validate_plane(const Axis& x, const Axis& z, double y_mm) {
  ranges::check(y_mm, ranges::depth_mm, "--plane-depth");
  check_lateral(x, "--x");
  check_lateral(z, "--z-grid");
  check_points(x, z);
}

void write_af_plane(const ByteSink& out, const Field& field, const Axis& x, const Axis& z,
                    double y_mm) {
  validate_plane(x, z, y_mm);
  const Fibre fibre{Orientation::horizontal, constants::reference_diameter_um, true};
  const FibreAxis along_x{}, vertical{true, 0.0, 0.0};
  write_map(out, "z_mm", x, z, [&](double xv, double zv, double& h, double& v) {
    h = field.af_3d(fibre, along_x, xv, y_mm, zv);
    v = field.af_3d(fibre, vertical, xv, y_mm, zv);
  });
}

void check_grid_work(double points, std::size_t pads) {
  constexpr double kMaxWork = 6.4e9;
  const double work = points * static_cast<double>(pads);
  if (!(work <= kMaxWork))
    bad_input("grid: " + number_text(points) + " points x " + std::to_string(pads) +
              " pads = " + number_text(work) + " pad evaluations, more than " +
              number_text(kMaxWork) + " (a coarser or smaller grid)");
}

Axis default_z_axis(const ElectrodeArray& a) {
  return Axis{std::max(ranges::position_mm.lo, std::floor(a.z_min_mm() - 5.0)),
              std::min(ranges::position_mm.hi, std::ceil(a.z_max_mm() + 5.0)), 0.1};
}

Axis default_x_axis(const ElectrodeArray& a) {
  return Axis{std::max(ranges::position_mm.lo, std::floor(a.x_min_mm() - 5.0)),
              std::min(ranges::position_mm.hi, std::ceil(a.x_max_mm() + 5.0)), 0.1};
}
Axis default_y_axis() {
  return Axis{0.2, 3.0, 0.05};
}

Json summary_to_json(const Setup& setup, const std::vector<double>& currents_mA, const Summary& s) {
  Json j;
  j["format"] = "tactile-primaries/af-summary/1";
  j["af_unit"] = "V/ms";
  j["conductor"] = setup.conductor.model;
  if (setup.conductor.model == "layered") j["skin"] = effective_skin(setup.conductor).name;
  j["currents_mA"] = currents_mA;
  Json rec = Json::object();
  for (std::size_t i = 0; i < s.peaks.size(); ++i) {
    const Receptor& r = setup.receptors[i];
    const Peak& p = s.peaks[i].second;
    Json e;
    e["max_af"] = p.af;
    e["x_mm"] = p.x_mm;
    e["y_mm"] = p.y_mm;
    if (setup.array.two_d()) e["z_mm"] = p.z_mm;
    e["orientation"] = to_string(r.fibre.orientation);
    e["diameter_um"] = r.fibre.diameter_um;
    e["fibre_factor_mm2_per_ms"] = fibre_factor_mm2_per_ms(r.fibre);
    rec[s.peaks[i].first] = e;
  }
  j["receptors"] = rec;
  Json ratios = Json::object();
  for (const auto& [name, ratio] : s.ratios) ratios[name] = ratio ? Json(*ratio) : Json(nullptr);
  j["ratios"] = ratios;
  return j;
}

}  // namespace tp
