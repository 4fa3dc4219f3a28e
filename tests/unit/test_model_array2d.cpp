// 2-D pad arrays (issue 21): the document's grid and pads, and the 3-D evaluation of the
// half-space models checked against the 1-D path, superposition of single pads, the
// array's mirror symmetries, Laplace and finite differences of the potential.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/document.hpp"
#include "model/field.hpp"
#include "core/ranges.hpp"

using namespace tp;

namespace {

ConductorParams params(const std::string& model, double plane_z = 0.0, double depth = 0.0) {
  ConductorParams p;
  p.model = model;
  p.resistivity_ohm_m = 3.0;
  p.plane_z_mm = plane_z;
  p.source_depth_mm = depth;
  return p;
}

std::vector<double> along(const Conductor& c, double x, double y, double z, const FibreAxis& e) {
  std::vector<double> out(c.size());
  c.unit_d2_along(x, y, z, e, out.data());
  return out;
}

const FibreAxis kX{}, kY{true, 0.0, 0.0}, kZ{false, 0.0, 1.0};

// Points below and beside a 4 x 3 grid at 2 x 1.5 mm, at receptor depths and beyond.
const std::vector<std::array<double, 3>> kPoints = {
    {0.0, 0.9, 0.0},  {0.3, 0.7, -0.4}, {-1.2, 2.0, 1.1}, {2.5, 1.3, 2.9},
    {-3.1, 0.4, 0.2}, {4.0, 3.0, -2.0}, {0.7, 0.25, 0.75}};

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

}  // namespace

TEST_CASE("a grid is centred on (0, 0) and indexed row-major", "[array2d]") {
  const ElectrodeArray a = ElectrodeArray::grid_of(4, 3, 2.0, 1.5, 1.0, 1.0);
  REQUIRE(a.size() == 12);
  REQUIRE(a.two_d());
  // index = row x columns + column; columns along x, rows along z.
  CHECK(a.positions_mm[0] == -3.0);
  CHECK(a.z_mm[0] == -1.5);
  CHECK(a.positions_mm[5] == -1.0);  // row 1, column 1
  CHECK(a.z_mm[5] == 0.0);
  CHECK(a.positions_mm[11] == 3.0);
  CHECK(a.z_mm[11] == 1.5);
  CHECK(a.centre_index() == 5);
}

TEST_CASE("a grid of one row is the 1-D array of the same pads (rect3d, point3d)",
          "[array2d][rect3d][point3d]") {
  const ElectrodeArray line = ElectrodeArray::uniform(5, 2.0, 1.0, 1.5);
  const ElectrodeArray grid = ElectrodeArray::grid_of(5, 1, 2.0, 2.0, 1.0, 1.5);
  for (const char* model : {"rect3d", "point3d"})
    for (const auto& p : kPoints) {
      // The 1-D array's fibres lie in the plane z = plane_z_mm; the grid's anywhere.
      const auto c1 = make_conductor(params(model, p[2]), line);
      const auto c2 = make_conductor(params(model), grid);
      std::vector<double> xx(5), yy(5), psi1(5), psi2(5);
      c1->unit_second_derivatives(p[0], p[1], xx.data(), yy.data());
      const auto gx = along(*c2, p[0], p[1], p[2], kX), gy = along(*c2, p[0], p[1], p[2], kY);
      c1->unit_potentials(p[0], p[1], psi1.data());
      c2->unit_potentials_3d(p[0], p[1], p[2], psi2.data());
      const double scale = std::max(max_abs(xx), max_abs(yy));
      for (std::size_t i = 0; i < 5; ++i) {
        CHECK(std::fabs(gx[i] - xx[i]) <= 1e-12 * scale);
        CHECK(std::fabs(gy[i] - yy[i]) <= 1e-12 * scale);
        CHECK(psi2[i] == Approx(psi1[i]).epsilon(1e-13));
      }
    }
}

TEST_CASE("a 2-D array's field is the sum of its pads' fields, each pad alone",
          "[array2d][rect3d][point3d]") {
  const ElectrodeArray grid = ElectrodeArray::grid_of(4, 3, 2.0, 1.5, 1.0, 1.0);
  for (const char* model : {"rect3d", "point3d"}) {
    const auto c = make_conductor(params(model), grid);
    for (const auto& p : kPoints)
      for (const FibreAxis& e : {kX, kY, kZ, FibreAxis{false, 0.6, -0.8}}) {
        const auto all = along(*c, p[0], p[1], p[2], e);
        for (std::size_t i = 0; i < grid.size(); ++i) {
          const ElectrodeArray one =
              ElectrodeArray::pads({grid.positions_mm[i]}, {grid.z_mm[i]}, 1.0, 1.0);
          const auto alone = along(*make_conductor(params(model), one), p[0], p[1], p[2], e);
          CHECK(all[i] == Approx(alone[0]).epsilon(1e-14).margin(1e-300));
        }
      }
  }
}

TEST_CASE("a 2-D array's field keeps the grid's mirror symmetries", "[array2d][rect3d]") {
  // A 4 x 3 grid is symmetric under x -> -x (column c <-> 3 - c) and z -> -z (row r <->
  // 2 - r): the field of the mirrored weights at the mirrored point is the same, with the
  // azimuth mirrored too.
  const ElectrodeArray grid = ElectrodeArray::grid_of(4, 3, 2.0, 1.5, 1.0, 1.0);
  const auto c = make_conductor(params("rect3d"), grid);
  const std::vector<double> w = {0.3, -1, 0.2, 0.5, 0.1, 1, -0.7, 0.4, -0.2, 0.6, -0.9, 0.8};
  auto mirrored = [&](bool mx, bool mz) {
    std::vector<double> m(12);
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col)
        m[static_cast<std::size_t>(r * 4 + col)] =
            w[static_cast<std::size_t>((mz ? 2 - r : r) * 4 + (mx ? 3 - col : col))];
    return m;
  };
  auto af = [&](const std::vector<double>& weights, double x, double y, double z, FibreAxis e) {
    const auto g = along(*c, x, y, z, e);
    double s = 0.0;
    for (std::size_t i = 0; i < 12; ++i) s += weights[i] * g[i];
    return s;
  };
  const FibreAxis slant{false, 0.6, 0.8};
  for (const auto& p : kPoints)
    for (const FibreAxis& e : {kX, kY, kZ, slant}) {
      const double v = af(w, p[0], p[1], p[2], e);
      const double tol = 1e-12 * (1.0 + std::fabs(v));
      // x -> -x turns the azimuth's x component, z -> -z its z component.
      const FibreAxis ex{e.vertical, -e.cos_az, e.sin_az}, ez{e.vertical, e.cos_az, -e.sin_az};
      CHECK(std::fabs(af(mirrored(true, false), -p[0], p[1], p[2], ex) - v) <= tol);
      CHECK(std::fabs(af(mirrored(false, true), p[0], p[1], -p[2], ez) - v) <= tol);
      CHECK(std::fabs(af(mirrored(true, true), -p[0], p[1], -p[2], e) - v) <= tol);
    }
}

TEST_CASE("3-D second derivatives of 2-D arrays: Laplace, and finite differences of Psi",
          "[array2d][rect3d][point3d]") {
  const ElectrodeArray grid = ElectrodeArray::grid_of(3, 2, 2.0, 1.5, 1.0, 1.0);
  for (const char* model : {"rect3d", "point3d"}) {
    const auto c = make_conductor(params(model), grid);
    for (const auto& p : kPoints) {
      const auto xx = along(*c, p[0], p[1], p[2], kX), yy = along(*c, p[0], p[1], p[2], kY),
                 zz = along(*c, p[0], p[1], p[2], kZ);
      const double scale = std::max({max_abs(xx), max_abs(yy), max_abs(zz)});
      for (std::size_t i = 0; i < grid.size(); ++i)
        CHECK(std::fabs(xx[i] + yy[i] + zz[i]) <= 1e-11 * scale);
      // Along a slanted axis e: Psi(p + h e) - 2 Psi(p) + Psi(p - h e), over h^2 (the
      // fourth-order Richardson of two steps).
      for (const FibreAxis& e : {kX, kZ, FibreAxis{false, 0.6, 0.8}, FibreAxis{false, 0.8, -0.6}}) {
        const auto exact = along(*c, p[0], p[1], p[2], e);
        auto second = [&](double h) {
          std::vector<double> a(grid.size()), b(grid.size()), m(grid.size()), out(grid.size());
          c->unit_potentials_3d(p[0] + h * e.cos_az, p[1], p[2] + h * e.sin_az, a.data());
          c->unit_potentials_3d(p[0] - h * e.cos_az, p[1], p[2] - h * e.sin_az, b.data());
          c->unit_potentials_3d(p[0], p[1], p[2], m.data());
          for (std::size_t i = 0; i < grid.size(); ++i) out[i] = (a[i] - 2 * m[i] + b[i]) / (h * h);
          return out;
        };
        const double h = 0.02 * p[1];
        const auto f1 = second(h), f2 = second(h / 2);
        for (std::size_t i = 0; i < grid.size(); ++i) {
          const double richardson = (4 * f2[i] - f1[i]) / 3;
          CHECK(std::fabs(richardson - exact[i]) <= 2e-6 * scale);
        }
      }
    }
  }
}

TEST_CASE("a 2-D array's receptor peak: a lone cathode's SAI peak lies under it",
          "[array2d][rect3d]") {
  Setup s;
  s.array = ElectrodeArray::grid_of(4, 4, 2.0, 2.0, 1.0, 1.0);
  s.conductor = params("rect3d");
  std::vector<double> currents(16, 0.0);
  currents[5] = 1.0;  // row 1, column 1: (-1, -1)
  const Summary sum = summarize(s, currents);
  const Peak& sai = sum.peaks[1].second;
  CHECK(sum.peaks[1].first == "SAI");
  // A horizontal fibre along x under a cathode is depolarised most straight beneath it
  // (by symmetry about the pad's centre lines).
  CHECK(sai.x_mm == Approx(-1.0).margin(1e-6));
  CHECK(sai.z_mm == Approx(-1.0).margin(1e-6));
  CHECK(sai.y_mm == 0.9);
  // An independent fine scan of the plane finds nothing higher.
  const Field f(s, currents);
  const Receptor& r = s.receptors[1];
  double best = -INFINITY;
  for (double x = -8; x <= 8; x += 0.05)
    for (double z = -8; z <= 8; z += 0.05)
      best = std::max(best, f.af_3d(r.fibre, fibre_axis(r), x, 0.9, z));
  CHECK(sai.af >= best);
  CHECK(sai.af <= best * (1 + 1e-3));
}

TEST_CASE("a 2-D array's peak over a box of fibres (a depth range) lies on its faces",
          "[array2d][rect3d]") {
  // A horizontal receptor over a depth range and a slanted one: the faces' search against
  // the test's own scan of the whole box.
  Setup s;
  s.array = ElectrodeArray::grid_of(4, 3, 2.0, 1.5, 1.0, 1.0);
  s.conductor = params("rect3d");
  s.lateral_margin_mm = 2.0;
  s.receptors[2].depth_min_mm = 1.2;  // PC over 1.2 to 2.0 mm
  s.receptors[1].azimuth_deg = 35.0;  // SAI slanted
  const std::vector<double> currents = {0.3, -1, 0.2, 0.5, 0.1, 1, -0.7, 0.4, -0.2, 0.6, -0.9, 0.8};
  const Summary sum = summarize(s, currents);
  const Field f(s, currents);
  for (std::size_t k = 0; k < 3; ++k) {
    const Receptor& r = s.receptors[k];
    const Region g = fibre_region(s, r);
    double best = -INFINITY;
    for (double y = g.y0_mm; y <= g.y1_mm + 1e-9; y += 0.1)
      for (double z = g.z0_mm; z <= g.z1_mm + 1e-9; z += 0.05)
        for (double x = g.x0_mm; x <= g.x1_mm + 1e-9; x += 0.05)
          best = std::max(best, f.af_3d(r.fibre, fibre_axis(r), x, y, z));
    INFO(r.name);
    CHECK(sum.peaks[k].second.af >= best);
    CHECK(sum.peaks[k].second.af <= best * (1 + 2e-3));
  }
}
