#include "opt/focus_samples.hpp"

#include <string>

#include "core/error.hpp"
#include "core/number.hpp"
#include "opt/lp.hpp"
#include "opt/problem.hpp"

namespace tp::focus {

// A 1-D array's region row by row (its depths, and along x); a 2-D array's box on its
// faces, a grid's face planes on a lattice (its PlaneTable into `tables`).
void sample_receptor(const Setup& s, std::size_t r, std::vector<Sample>& out,
                     std::vector<PlaneTable>& tables) {
  const Region g = fibre_region(s, s.receptors[r]);
  // The problem's matrices hold samples x pads: refuse before allocating beyond the cap.
  const double cap = kMaxProblemEntries / static_cast<double>(s.array.size());
  auto guard = [&](double more) {
    const double total = static_cast<double>(out.size()) + more;
    if (!(total <= cap))
      bad_input("focus problem: " + number_text(total) + " samples of the fibres x " +
                std::to_string(s.array.size()) + " pads, more than the cap of " +
                number_text(kMaxProblemEntries) + " entries (receptor " + s.receptors[r].name +
                "'s fibres from " + number_text(g.y0_mm) + " mm deep over " +
                number_text(g.x1_mm - g.x0_mm) + " mm" +
                (s.array.two_d() ? " x " + number_text(g.z1_mm - g.z0_mm) + " mm" : "") +
                ": deeper fibres, a smaller margin or fewer pads)");
  };
  if (!s.array.two_d()) {
    const double h0 = step_at(g.y0_mm);
    guard((std::ceil((g.y1_mm - g.y0_mm) / h0) + 1) * (std::ceil((g.x1_mm - g.x0_mm) / h0) + 1));
    sample_line(g.y0_mm, g.y1_mm, step_at(g.y0_mm), [&](double y) {
      sample_line(g.x0_mm, g.x1_mm, step_at(y), [&](double x) {
        out.push_back({x, y, g.z0_mm, r});
      });
    });
    return;
  }
  const ElectrodeArray& arr = s.array;
  auto plane = [&](double y) {
    const double h = step_at(y);
    guard((std::ceil((g.x1_mm - g.x0_mm) / h) + 3) * (std::ceil((g.z1_mm - g.z0_mm) / h) + 3));
    auto plain = [&] {
      sample_line(g.z0_mm, g.z1_mm, h, [&](double z) {
        sample_line(g.x0_mm, g.x1_mm, h, [&](double x) { out.push_back({x, y, z, r}); });
      });
    };
    const auto lat = grid_lattice(arr, g.x0_mm, g.x1_mm, g.z0_mm, g.z1_mm, h);
    if (!lat) return plain();
    const int id = static_cast<int>(tables.size());
    tables.push_back({*lat, pad_table(s.conductor, arr, *lat, y, fibre_axis(s.receptors[r]))});
    // The lattice's points, then the region's edges between its lines.
    for (int b = lat->b0; b <= lat->b1; ++b)
      for (int a = lat->a0; a <= lat->a1; ++a)
        out.push_back({lat->x(a), y, lat->z(b), r, id, a, b});
    for (int b = lat->b0; b <= lat->b1; ++b) {
      if (lat->x0_off) out.push_back({g.x0_mm, y, lat->z(b), r});
      if (lat->x1_off) out.push_back({g.x1_mm, y, lat->z(b), r});
    }
    for (const double x : lat->x_axis(g.x0_mm, g.x1_mm)) {
      if (lat->z0_off) out.push_back({x, y, g.z0_mm, r});
      if (lat->z1_off) out.push_back({x, y, g.z1_mm, r});
    }
  };
  plane(g.y0_mm);
  if (!(g.y1_mm > g.y0_mm)) return;
  plane(g.y1_mm);
  const double h = step_at(g.y0_mm);
  guard((std::ceil((g.y1_mm - g.y0_mm) / h) + 1) * 2 *
        (std::ceil((g.x1_mm - g.x0_mm) / h) + std::ceil((g.z1_mm - g.z0_mm) / h) + 2));
  sample_line(g.y0_mm, g.y1_mm, h, [&](double y) {
    sample_line(g.x0_mm, g.x1_mm, h, [&](double x) {
      out.push_back({x, y, g.z0_mm, r});
      if (g.z1_mm > g.z0_mm) out.push_back({x, y, g.z1_mm, r});
    });
    sample_line(g.z0_mm, g.z1_mm, h, [&](double z) {
      out.push_back({g.x0_mm, y, z, r});
      if (g.x1_mm > g.x0_mm) out.push_back({g.x1_mm, y, z, r});
    });
  });
}

Eigen::MatrixXd rows_of(const Setup& s, const Conductor& c, const std::vector<PlaneTable>& tables,
                        const std::vector<Sample>& pts, const Eigen::MatrixXd& basis,
                        std::size_t first) {
  const auto n = static_cast<Eigen::Index>(s.array.size());
  const std::size_t count = pts.size() - std::min(first, pts.size());
  Eigen::MatrixXd out(static_cast<Eigen::Index>(count), basis.cols());
  constexpr std::size_t kBlock = 2048;
  RowMajorMatrix g;
  for (std::size_t start = 0; start < count; start += kBlock) {
    const std::size_t len = std::min(kBlock, count - start);
    g.resize(static_cast<Eigen::Index>(len), n);
    for (std::size_t i = 0; i < len; ++i) {
      const Sample& p = pts[first + start + i];
      const Receptor& r = s.receptors[p.receptor];
      double* row = g.row(static_cast<Eigen::Index>(i)).data();
      if (p.table >= 0) {
        const PlaneTable& l = tables[static_cast<std::size_t>(p.table)];
        l.t->pads_at(s.array, l.g, p.a, p.b, row);
      } else if (s.array.two_d()) {
        c.unit_d2_along(p.x, p.y, p.z, fibre_axis(r), row);
      } else {
        const bool horizontal = r.fibre.orientation == Orientation::horizontal;
        c.unit_second_derivatives(p.x, p.y, horizontal ? row : nullptr, horizontal ? nullptr : row);
      }
      g.row(static_cast<Eigen::Index>(i)) *= fibre_factor_mm2_per_ms(r.fibre);
    }
    out.middleRows(static_cast<Eigen::Index>(start), static_cast<Eigen::Index>(len)).noalias() =
        g * basis;
  }
  return out;
}

void SampleRows::append(const Eigen::MatrixXd& m) {
  reserve_spare(v, v.size() + static_cast<std::size_t>(m.size()));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) v.push_back(m(i, j));
  n += m.rows();
}

void extend_rows(SampleRows& m, const Setup& s, const Conductor& c,
                 const std::vector<PlaneTable>& tables, const std::vector<Sample>& pts,
                 const Eigen::MatrixXd& basis) {
  const auto done = static_cast<std::size_t>(m.n);
  if (done == pts.size()) return;
  m.append(rows_of(s, c, tables, pts, basis, done));
}

}  // namespace tp::focus
