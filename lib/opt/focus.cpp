#include "opt/focus.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "io/number.hpp"
#include "model/lattice.hpp"
#include "opt/ldp.hpp"
#include "opt/lp.hpp"
#include "opt/problem.hpp"

namespace tp {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
// A continuous maximum may exceed its sampled bound by this much (relative) before it
// joins the samples: the spill, a bound, by 1e-3; an off-target maximum, which only
// makes the objective's estimate optimistic, by 1 % (a lobe the samples missed).
constexpr double kCheckSpill = 1e-3;
constexpr double kCheckOff = 1e-2;
constexpr int kMaxRounds = 8;

struct Sample {
  double x, y, z;
  std::size_t receptor;
  int table = -1;  // a lattice plane's (Lattice): the sample is its point (a, b)
  int a = 0, b = 0;
};

// A grid's face plane, sampled on a lattice (model/lattice.hpp).
struct Lattice {
  GridLattice g;
  std::shared_ptr<const PadTable> t;
};

// Sampling step of a face at depth y: the AF varies on the scale of the depth.
double step_at(double y) {
  return std::min(0.25, y / 4.0);
}

// n + 1 points from a to b, both ends exact.
template <class F>
void line(double a, double b, double step, F&& f) {
  const double n = std::max(1.0, std::ceil((b - a) / step));
  if (!(n < kMaxSamples)) refuse_sample_count("a fibre region's samples", n);
  const auto k = static_cast<std::size_t>(n);
  if (!(b > a)) {
    f(a);
    return;
  }
  for (std::size_t i = 0; i <= k; ++i)
    f(i == k ? b : a + (b - a) * static_cast<double>(i) / static_cast<double>(k));
}

// Every receptor's fibres, sampled: a 1-D array's region row by row (its depths, and
// along x); a 2-D array's box on its faces (the maximum principle, model/field.cpp), a
// grid's face planes on a Lattice (its table into `tables`).
void sample_receptor(const Setup& s, std::size_t r, std::vector<Sample>& out,
                     std::vector<Lattice>& tables) {
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
    line(g.y0_mm, g.y1_mm, step_at(g.y0_mm), [&](double y) {
      line(g.x0_mm, g.x1_mm, step_at(y), [&](double x) { out.push_back({x, y, g.z0_mm, r}); });
    });
    return;
  }
  const ElectrodeArray& arr = s.array;
  auto plane = [&](double y) {
    const double h = step_at(y);
    guard((std::ceil((g.x1_mm - g.x0_mm) / h) + 3) * (std::ceil((g.z1_mm - g.z0_mm) / h) + 3));
    auto plain = [&] {
      line(g.z0_mm, g.z1_mm, h, [&](double z) {
        line(g.x0_mm, g.x1_mm, h, [&](double x) { out.push_back({x, y, z, r}); });
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
  line(g.y0_mm, g.y1_mm, h, [&](double y) {
    line(g.x0_mm, g.x1_mm, h, [&](double x) {
      out.push_back({x, y, g.z0_mm, r});
      if (g.z1_mm > g.z0_mm) out.push_back({x, y, g.z1_mm, r});
    });
    line(g.z0_mm, g.z1_mm, h, [&](double z) {
      out.push_back({g.x0_mm, y, z, r});
      if (g.x1_mm > g.x0_mm) out.push_back({g.x1_mm, y, z, r});
    });
  });
}

// The rows (AF per unit z, zero-sum basis) of the samples from `first` on, in blocks (the
// pads' responses, then one product with the basis).
Eigen::MatrixXd rows_of(const Setup& s, const Conductor& c, const std::vector<Lattice>& tables,
                        const std::vector<Sample>& pts, const Eigen::MatrixXd& basis,
                        std::size_t first = 0) {
  const auto n = static_cast<Eigen::Index>(s.array.size());
  const std::size_t count = pts.size() - std::min(first, pts.size());
  Eigen::MatrixXd out(static_cast<Eigen::Index>(count), basis.cols());
  constexpr std::size_t kBlock = 2048;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> g;
  for (std::size_t start = 0; start < count; start += kBlock) {
    const std::size_t len = std::min(kBlock, count - start);
    g.resize(static_cast<Eigen::Index>(len), n);
    for (std::size_t i = 0; i < len; ++i) {
      const Sample& p = pts[first + start + i];
      const Receptor& r = s.receptors[p.receptor];
      double* row = g.row(static_cast<Eigen::Index>(i)).data();
      if (p.table >= 0) {
        const Lattice& l = tables[static_cast<std::size_t>(p.table)];
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

// The samples' rows (row-major), grown by the rounds with room to spare (reserve_spare).
struct Rows {
  using Map =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  std::vector<double> v;
  Eigen::Index n = 0, cols = 0;
  explicit Rows(Eigen::Index columns) : cols(columns) {}
  Map all() const { return from(0); }
  Map from(Eigen::Index i) const { return Map(v.data() + i * cols, n - i, cols); }
  void append(const Eigen::MatrixXd& m) {
    reserve_spare(v, v.size() + static_cast<std::size_t>(m.size()));
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j) v.push_back(m(i, j));
    n += m.rows();
  }
};

// Rows for the samples added since the rows were last extended.
void extend_rows(Rows& m, const Setup& s, const Conductor& c, const std::vector<Lattice>& tables,
                 const std::vector<Sample>& pts, const Eigen::MatrixXd& basis) {
  const auto done = static_cast<std::size_t>(m.n);
  if (done == pts.size()) return;
  m.append(rows_of(s, c, tables, pts, basis, done));
}

// A reflection through the focus: x -> 2 x_f - x, z -> 2 z_f - z, or both.
struct Mirror {
  bool x, z;
};

double lateral(const FocusOptions& o, bool two_d, double x, double z) {
  return two_d ? std::sqrt((x - o.x_mm) * (x - o.x_mm) + (z - o.z_mm) * (z - o.z_mm))
               : std::fabs(x - o.x_mm);
}

// The target's largest AF farther than `radius` from the focus: the faces of its box with
// the disc masked out, and the cylinder around the focus where the mask ends.
Peak max_beyond(const Setup& s, const Field& f, const Receptor& r, const FocusOptions& o,
                double radius) {
  const Region g = fibre_region(s, r);
  const bool two_d = s.array.two_d();
  auto af = [&](double x, double y, double z) {
    if (!(lateral(o, two_d, x, z) > radius)) return -kInf;
    return two_d ? f.af_3d(r.fibre, fibre_axis(r), x, y, z) : f.af(r.fibre, x, y);
  };
  Peak best{-kInf, 0, 0, 0};
  auto consider = [&](double v, double x, double y, double z) {
    if (v > best.af) best = {v, x, y, z};
  };
  if (!two_d) {
    line(g.y0_mm, g.y1_mm, step_at(g.y0_mm) / 2, [&](double y) {
      const auto [x, v] =
          maximize_1d([&](double xv) { return af(xv, y, 0.0); }, g.x0_mm, g.x1_mm, step_at(y) / 4);
      consider(v, x, y, g.z0_mm);
    });
    for (const double x : {o.x_mm - radius * (1 + 1e-12), o.x_mm + radius * (1 + 1e-12)})
      if (x >= g.x0_mm && x <= g.x1_mm && g.y1_mm > g.y0_mm) {
        const auto [y, v] = maximize_1d([&](double yv) { return af(x, yv, 0.0); }, g.y0_mm, g.y1_mm,
                                        step_at(g.y0_mm) / 4);
        consider(v, x, y, g.z0_mm);
      }
    return best;
  }
  auto plane = [&](double y) {
    GridValues v = f.plane_af(r, y, step_at(y) / 2);
    for (std::size_t j = 0; j < v.t.size(); ++j)
      for (std::size_t i = 0; i < v.s.size(); ++i)
        if (!(lateral(o, two_d, v.s[i], v.t[j]) > radius)) v.v[j * v.s.size() + i] = -kInf;
    const Max2d m = maximize_2d_grid([&](double x, double z) { return af(x, y, z); }, v);
    consider(m.value, m.s, y, m.t);
  };
  plane(g.y0_mm);
  if (!(g.y1_mm > g.y0_mm)) return best;
  plane(g.y1_mm);
  const double h = step_at(g.y0_mm) / 2;
  // The walls, the disc's points masked.
  auto wall = [&](bool along_x, double fixed) {
    GridValues v = f.wall_af(r, along_x, fixed, h);
    for (std::size_t i = 0; i < v.s.size(); ++i) {
      const double x = along_x ? v.s[i] : fixed, z = along_x ? fixed : v.s[i];
      if (lateral(o, two_d, x, z) > radius) continue;
      for (std::size_t j = 0; j < v.t.size(); ++j) v.v[j * v.s.size() + i] = -kInf;
    }
    return maximize_2d_grid(
        [&](double sv, double y) { return along_x ? af(sv, y, fixed) : af(fixed, y, sv); }, v);
  };
  for (const double z : {g.z0_mm, g.z1_mm}) {
    const Max2d m = wall(true, z);
    consider(m.value, m.s, m.t, z);
  }
  for (const double x : {g.x0_mm, g.x1_mm}) {
    const Max2d m = wall(false, x);
    consider(m.value, x, m.t, m.s);
  }
  // The cylinder of the radius, where the masked region's boundary lies inside the box.
  const double rr = radius * (1 + 1e-12);
  const Max2d m = maximize_2d(
      [&](double th, double y) {
        const double x = o.x_mm + rr * std::cos(th), z = o.z_mm + rr * std::sin(th);
        if (x < g.x0_mm || x > g.x1_mm || z < g.z0_mm || z > g.z1_mm) return -kInf;
        return af(x, y, z);
      },
      -kPi, kPi, g.y0_mm, g.y1_mm, std::min(h, h / std::max(rr, 1e-3)));
  consider(m.value, o.x_mm + rr * std::cos(m.s), m.t, o.z_mm + rr * std::sin(m.s));
  return best;
}

// Every receptor's largest AF (a Summary) and the target's largest beyond the radius, on
// opt.threads threads, each task with its own Field.
std::pair<Summary, Peak> check_pattern(const Setup& s, const std::vector<double>& currents,
                                       const Receptor& target, const FocusOptions& o,
                                       double radius) {
  const std::size_t n = s.receptors.size();
  std::vector<Peak> peaks(n);
  Peak far;
  parallel_for(n + 1, std::max(1u, o.threads), [&](std::size_t i) {
    const Field f(s, currents);
    if (i < n)
      peaks[i] = f.peak(s.receptors[i]);
    else
      far = max_beyond(s, f, target, o, radius);
  });
  return {summary_of(s, peaks), far};
}

// Calls f(s, t) at every grid point above `over` and at least as high as its neighbours.
template <class F>
void peaks_above(const GridValues& g, double over, F&& f) {
  const std::size_t ns = g.s.size(), nt = g.t.size();
  for (std::size_t j = 0; j < nt; ++j)
    for (std::size_t i = 0; i < ns; ++i) {
      const double c = g.v[j * ns + i];
      if (!(c > over)) continue;
      bool top = true;
      for (std::size_t jj = j ? j - 1 : 0; jj <= std::min(nt - 1, j + 1) && top; ++jj)
        for (std::size_t ii = i ? i - 1 : 0; ii <= std::min(ns - 1, i + 1); ++ii)
          if (g.v[jj * ns + ii] > c) {
            top = false;
            break;
          }
      if (top) f(g.s[i], g.t[j]);
    }
}

}  // namespace

double nominal_pitch_mm(const ElectrodeArray& a) {
  if (a.pitch_mm) return a.grid() ? std::min(*a.pitch_mm, a.row_pitch_mm) : *a.pitch_mm;
  double best = kInf;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j)
      best =
          std::min(best, std::hypot(a.positions_mm[i] - a.positions_mm[j], a.z_of(i) - a.z_of(j)));
  return std::isfinite(best) ? best : std::max(0.01, a.width_mm);
}

void check_focus(const Setup& s, const FocusOptions& o) {
  const ElectrodeArray& a = s.array;
  const double p = nominal_pitch_mm(a);
  if (!std::isfinite(o.x_mm) || !std::isfinite(o.z_mm)) bad_input("--at: not finite");
  if (o.x_mm < a.x_min_mm() - p || o.x_mm > a.x_max_mm() + p ||
      (a.two_d() && (o.z_mm < a.z_min_mm() - p || o.z_mm > a.z_max_mm() + p)))
    bad_input("--at: (" + number_text(o.x_mm) + (a.two_d() ? ", " + number_text(o.z_mm) : "") +
              ") mm lies outside the array's extent plus one pitch (x " +
              number_text(a.x_min_mm() - p) + " to " + number_text(a.x_max_mm() + p) +
              (a.two_d()
                   ? ", z " + number_text(a.z_min_mm() - p) + " to " + number_text(a.z_max_mm() + p)
                   : "") +
              " mm)");
  if (!(o.spill > 0.0 && o.spill <= 1.0))
    bad_input("--spill: " + number_beside(o.spill, 0.0, 1.0) + " outside (0, 1]");
  if (!(o.radius_mm >= 0.0 && o.radius_mm <= 1000.0))
    bad_input("--radius: " + number_beside(o.radius_mm, 0.0, 1000.0) + " mm outside (0, 1000] mm");
  if (o.radius_mm > 0.0 && !(o.radius_mm > p / 4))
    bad_input("--radius: " + number_beside(o.radius_mm, p / 4) +
              " mm is not beyond a quarter pitch (" + number_text(p / 4) +
              " mm), where the target's peak may lie");
}

std::string focus_failure_text(const Setup& setup, const std::string& mode, const FocusOptions& opt,
                               const FocusFailure& why) {
  const bool two_d = setup.array.two_d();
  const double radius = opt.radius_mm > 0.0 ? opt.radius_mm : nominal_pitch_mm(setup.array);
  const std::string place =
      "(" + number_text(opt.x_mm) + (two_d ? ", " + number_text(opt.z_mm) : "") + ") mm";
  const std::string no_weights = "no weights put receptor " + mode + "'s largest AF at the focus " +
                                 place + " with a spill of at most " + number_text(opt.spill) +
                                 " beyond " + number_text(radius) + " mm";
  switch (why.kind) {
    case FocusFailure::Kind::nowhere:
      return no_weights + ": no weights put its peak there at all";
    case FocusFailure::Kind::impossible:
      return no_weights + ": no spill up to 1 is possible (the least on the samples is " +
             number_text(why.value) + ": the peak itself cannot sit there)";
    case FocusFailure::Kind::least_spill:
      return no_weights + ": the least spill reachable is " + number_text(why.value) +
             " (on the samples: a lower bound)";
    case FocusFailure::Kind::caps:
      return no_weights + " on the continuous fibres: the least reached is " +
             number_text(why.value);
    case FocusFailure::Kind::rounds:
      break;
  }
  return "receptor " + mode + "'s pixel at " + place + ": after " + std::to_string(why.rounds) +
         " rounds its peak lies at (" + number_text(why.peak_x_mm) +
         (two_d ? ", " + number_text(why.peak_z_mm) : "") + ") mm and its spill is " +
         number_text(why.value) + " (at most " + number_text(opt.spill) +
         " asked); a larger --spill or --radius";
}

FocusResult optimize_focus(const Setup& setup, const std::string& mode, const FocusOptions& opt) {
  FocusFailure why;
  auto r = try_optimize_focus(setup, mode, opt, why);
  if (!r) failure(focus_failure_text(setup, mode, opt, why));
  return std::move(*r);
}

std::optional<FocusResult> try_optimize_focus(const Setup& setup, const std::string& mode,
                                              const FocusOptions& opt, FocusFailure& why) {
  const auto t0 = std::chrono::steady_clock::now();
  check_focus(setup, opt);
  if (setup.array.size() < 2) bad_input("optimisation needs at least 2 electrodes");
  if (setup.receptors.size() < 2) bad_input("optimisation needs at least 2 receptors");
  const std::size_t target = receptor_index(setup, mode);
  const Receptor& tr = setup.receptors[target];
  const bool two_d = setup.array.two_d();
  FocusResult res;
  res.mode = mode;
  res.pitch_mm = nominal_pitch_mm(setup.array);
  res.radius_mm = opt.radius_mm > 0.0 ? opt.radius_mm : res.pitch_mm;
  const double quarter = res.pitch_mm / 4.0;
  const auto conductor = make_conductor(setup.conductor, setup.array);
  check_fibre_reach(setup, *conductor);
  const Eigen::MatrixXd basis = zero_sum_basis(setup.array.size());

  // The samples: every other receptor's (<= t), the target's own away from the focus
  // (capped at 1 or at the spill).
  // The samples beyond the radius are capped at spill_cap: the spill, lowered by the
  // excess the check finds between them (below), so that the bound holds on the
  // continuous fibres and not only at the samples.
  std::vector<Sample> off, capped, inner;  // inner: the target's within a quarter pitch
  std::vector<Lattice> tables;
  std::vector<double> caps;
  std::vector<char> beyond;  // per capped sample: beyond the radius
  double spill_cap = opt.spill;
  auto add_target_sample = [&](const Sample& p) {
    const double d = lateral(opt, two_d, p.x, p.z);
    if (d > res.radius_mm) {
      capped.push_back(p);
      caps.push_back(spill_cap);
      beyond.push_back(1);
    } else if (d > quarter) {
      capped.push_back(p);
      caps.push_back(1.0);
      beyond.push_back(0);
    } else {
      inner.push_back(p);
    }
  };
  for (std::size_t r = 0; r < setup.receptors.size(); ++r) {
    if (r != target) {
      sample_receptor(setup, r, off, tables);
      continue;
    }
    std::vector<Sample> own;
    sample_receptor(setup, r, own, tables);
    // The bounds change at the radius and at a quarter pitch: sample those circles (a 1-D
    // array: those points) just outside, where the constrained AF is largest.
    const Region g = fibre_region(setup, tr);
    for (const double rad : {quarter, res.radius_mm}) {
      const double rr = rad * (1 + 1e-9);
      auto ring = [&](double y) {
        if (!two_d) {
          for (const double x : {opt.x_mm - rr, opt.x_mm + rr})
            if (x >= g.x0_mm && x <= g.x1_mm) own.push_back({x, y, g.z0_mm, r});
          return;
        }
        // A multiple of 4, so that the ring is closed under the mirrors x and z.
        const double n = 4 * std::ceil(2 * kPi * rr / step_at(y) / 4);
        if (!(n < kMaxSamples)) refuse_sample_count("a focus circle", n);
        for (double k = 0; k < n; ++k) {
          // The quarter turns exactly (cos and sin of pi are not 0 in floating point: the
          // ring's points on the focus's axes would fall a rounding off them, and out of a
          // region one sample thick, as a grid of one row with no margin).
          const double th = 2 * kPi * k / n;
          const double quarter_turns = 4 * k / n;
          const bool axis = quarter_turns == std::floor(quarter_turns);
          const double c = axis ? std::round(std::cos(th)) : std::cos(th);
          const double sn = axis ? std::round(std::sin(th)) : std::sin(th);
          const double x = opt.x_mm + rr * c, z = opt.z_mm + rr * sn;
          if (x >= g.x0_mm && x <= g.x1_mm && z >= g.z0_mm && z <= g.z1_mm)
            own.push_back({x, y, z, r});
        }
      };
      line(g.y0_mm, g.y1_mm, step_at(g.y0_mm), ring);
    }
    for (const Sample& p : own) add_target_sample(p);
  }
  const double entries =
      static_cast<double>(off.size() + capped.size()) * static_cast<double>(setup.array.size());
  if (entries > kMaxProblemEntries)
    bad_input("focus problem of " + std::to_string(off.size() + capped.size()) + " samples x " +
              std::to_string(setup.array.size()) + " electrodes = " + number_text(entries) +
              ", more than the cap of " + number_text(kMaxProblemEntries) +
              " (fewer pads, or a smaller margin)");

  // The focus point's candidate depths: the target's depth, or five down its range.
  std::vector<double> depths;
  if (tr.depth_max_mm > tr.depth_min_mm)
    for (int k = 0; k <= 4; ++k)
      depths.push_back(tr.depth_min_mm + (tr.depth_max_mm - tr.depth_min_mm) * k / 4.0);
  else
    depths.push_back(tr.depth_min_mm);
  auto focus_row = [&](double y) {
    const std::vector<Sample> p = {
        {opt.x_mm, y, two_d ? opt.z_mm : setup.conductor.plane_z_mm, target}};
    return Eigen::VectorXd(rows_of(setup, *conductor, tables, p, basis).row(0).transpose());
  };

  Eigen::VectorXd w_best;
  std::optional<double> best_depth;
  const std::vector<double> all_depths = depths;
  bool all_depths_again = false;  // the chosen depth failed: every candidate from then on
  std::vector<double> last_caps;  // the caps of the last round's LP
  // The samples' rows, extended by the samples each round adds.
  Rows a_off(basis.cols()), a_cap(basis.cols());
  // One LP for every round: each adds its samples and lowers caps, and the rows the last
  // solves needed stay in (with their basis), so a round starts near its answer.
  std::unique_ptr<TargetLp> lp;
  for (res.rounds = 1;; ++res.rounds) {
    // The rounds add samples: the cap holds for them too.
    const double now =
        static_cast<double>(off.size() + capped.size()) * static_cast<double>(setup.array.size());
    if (now > kMaxProblemEntries)
      failure("focus problem: the samples the rounds added make " + number_text(now) +
              " entries, more than the cap of " + number_text(kMaxProblemEntries));
    const Eigen::Index off_had = a_off.n, cap_had = a_cap.n;
    extend_rows(a_off, setup, *conductor, tables, off, basis);
    extend_rows(a_cap, setup, *conductor, tables, capped, basis);
    const Eigen::VectorXd b_cap =
        Eigen::Map<const Eigen::VectorXd>(caps.data(), static_cast<Eigen::Index>(caps.size()));
    if (!lp) {
      lp = std::make_unique<TargetLp>(a_off.all(), basis, 0.0, a_cap.all(), b_cap);
    } else {
      lp->append(a_off.from(off_had), a_cap.from(cap_had), b_cap.tail(a_cap.n - cap_had));
      lp->set_caps(b_cap);
    }
    std::optional<LpSolution> best;
    Eigen::VectorXd best_row;
    // The depth is chosen in the first round; later rounds add samples at the same one.
    if (res.rounds == 2 && best_depth && !all_depths_again) depths = {*best_depth};
    last_caps = caps;
    for (const double y : depths) {
      const Eigen::VectorXd row = focus_row(y);
      ++res.lp_solves;
      const auto sol = lp->solve(row);
      if (sol && (!best || sol->value < best->value - 1e-12 * std::fabs(best->value))) {
        best = sol;
        best_row = row;
        res.target_depth_mm = y;
        best_depth = y;
      }
    }
    if (!best && depths.size() < all_depths.size()) {
      // The depth chosen in the first round no longer works: every candidate again.
      depths = all_depths;
      all_depths_again = true;
      --res.rounds;
      continue;
    }
    if (!best && res.rounds > 1) {
      // The caps were lowered by the check, and no weights meet them: the spill reached
      // on the continuous fibres is the last round's.
      why = {FocusFailure::Kind::caps, res.spill};
      return std::nullopt;
    }
    if (!best) {
      // The least spill any weights reach with the peak at the focus: the same problem
      // with the target's samples beyond the radius as the off-target rows.
      std::vector<Sample> far, near;
      std::vector<double> near_caps;
      for (std::size_t i = 0; i < capped.size(); ++i) {
        if (beyond[i]) {
          far.push_back(capped[i]);
        } else {
          near.push_back(capped[i]);
          near_caps.push_back(1.0);
        }
      }
      double least = kInf;
      if (!far.empty()) {
        TargetLp aux(rows_of(setup, *conductor, tables, far, basis), basis, 0.0,
                     rows_of(setup, *conductor, tables, near, basis),
                     Eigen::Map<const Eigen::VectorXd>(
                         near_caps.data(), static_cast<Eigen::Index>(near_caps.size())));
        for (const double y : depths)
          if (const auto s = aux.solve(focus_row(y))) least = std::min(least, s->value);
      }
      why = {!std::isfinite(least) ? FocusFailure::Kind::nowhere
             : least > 1.0         ? FocusFailure::Kind::impossible
                                   : FocusFailure::Kind::least_spill,
             least};
      return std::nullopt;
    }
    res.sampled_optimum = best->value;

    // One answer: the least |z| (= |w|, the basis being orthonormal) with the focus row's
    // AF 1 and every sample within its bound, t relaxed to t* (1 + tolerance).  The
    // equality is eliminated, z = z0 + Q v with z0 = e / |e|^2 and Q an orthonormal basis
    // of e's complement, so |z|^2 = |z0|^2 + |v|^2; each row a z <= b becomes
    // -(a Q) v >= a z0 - b: a least-distance programme in v.
    const Eigen::Index nz = basis.cols();
    const Eigen::VectorXd& e = best_row;
    const Eigen::VectorXd z0 = e / e.squaredNorm();
    Eigen::MatrixXd q;
    {
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(e);
      const Eigen::MatrixXd full = qr.householderQ();
      q = full.rightCols(nz - 1);
    }
    const double t_bound = best->value + opt.tolerance * std::fabs(best->value);
    const Eigen::Index n_off = a_off.n, n_all = a_off.n + a_cap.n;
    Eigen::VectorXd bound(n_all);
    bound.head(n_off).setConstant(t_bound);
    bound.tail(a_cap.n) = b_cap;
    auto row_at = [&](Eigen::Index i) {
      return i < n_off ? Eigen::RowVectorXd(a_off.all().row(i))
                       : Eigen::RowVectorXd(a_cap.all().row(i - n_off));
    };
    // Excess of every row over its bound at z.
    auto excess = [&](const Eigen::VectorXd& z) {
      Eigen::VectorXd v(n_all);
      v.head(n_off) = a_off.all() * z;
      v.tail(a_cap.n) = a_cap.all() * z;
      return Eigen::VectorXd(v - bound);
    };
    // Working set: the rows the LP optimum holds (nearly) tight, then the violated ones.
    std::vector<Eigen::Index> work;
    std::vector<bool> in_work(static_cast<std::size_t>(n_all), false);
    {
      const Eigen::VectorXd ex = excess(best->z);
      const double scale = std::max(1.0, std::fabs(best->value));
      for (Eigen::Index i = 0; i < n_all; ++i)
        if (ex(i) > -1e-3 * scale) {
          work.push_back(i);
          in_work[static_cast<std::size_t>(i)] = true;
        }
    }

    Eigen::VectorXd z = best->z;
    // The least-distance programme is solved in units of |z0| with unit rows, so that its
    // tests do not depend on the AF's scale (resistivity, diameters).
    const double zs = z0.norm();
    res.least_norm = false;
    for (int pass = 0;; ++pass) {
      Eigen::MatrixXd g(static_cast<Eigen::Index>(work.size()), nz - 1);
      Eigen::VectorXd h(static_cast<Eigen::Index>(work.size()));
      for (std::size_t k = 0; k < work.size(); ++k) {
        const Eigen::RowVectorXd a = row_at(work[k]);
        const Eigen::RowVectorXd aq = -(a * q);
        const double norm = std::max(aq.norm(), 1e-300);
        g.row(static_cast<Eigen::Index>(k)) = aq / norm;
        h(static_cast<Eigen::Index>(k)) = (a.dot(z0) - bound(work[k])) / (norm * zs);
      }
      auto v = least_distance(g, h);
      if (!v) break;  // rounding made the relaxed set look empty: keep the LP's answer
      *v *= zs;
      const Eigen::VectorXd zc = z0 + q * *v;
      const Eigen::VectorXd ex = excess(zc);
      const double tol = 1e-9 * std::max(1.0, std::fabs(best->value));
      std::vector<std::pair<double, Eigen::Index>> violated;
      for (Eigen::Index i = 0; i < n_all; ++i)
        if (ex(i) > tol && !in_work[static_cast<std::size_t>(i)]) violated.emplace_back(ex(i), i);
      if (violated.empty() || pass > 50) {
        if (violated.empty()) {
          z = zc;
          res.least_norm = true;
        }
        break;
      }
      const std::size_t k = std::min<std::size_t>(64, violated.size());
      std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(k),
                        violated.end(), [](const auto& l, const auto& r) {
                          return l.first > r.first || (l.first == r.first && l.second < r.second);
                        });
      for (std::size_t i = 0; i < k; ++i) {
        work.push_back(violated[i].second);
        in_work[static_cast<std::size_t>(violated[i].second)] = true;
      }
    }
    res.samples = off.size() + capped.size();
    w_best = basis * z;
    w_best.array() -= w_best.mean();
    w_best /= w_best.cwiseAbs().maxCoeff();

    // The check on the continuous fibres.
    std::vector<double> currents;
    for (Eigen::Index i = 0; i < w_best.size(); ++i)
      currents.push_back(w_best(i) * opt.max_current_mA);
    const auto [sum, far] = check_pattern(setup, currents, tr, opt, res.radius_mm);
    const Field field(setup, currents);
    const double target_af = sum.peaks[target].second.af;
    // The bounds as the issue states them, on the true maxima: the target's largest AF
    // within a quarter pitch of the focus, its AF beyond the radius at most the spill of
    // that peak, every off-target AF at most t (1 + tolerance) of it.
    const Peak& tp_ = sum.peaks[target].second;
    std::vector<Sample> add_off, add_target;
    for (std::size_t r = 0; r < setup.receptors.size(); ++r) {
      if (r == target) continue;
      const Peak& p = sum.peaks[r].second;
      const double over = t_bound * target_af * (1 + kCheckOff);
      if (!(p.af > over)) continue;
      add_off.push_back({p.x_mm, p.y_mm, two_d ? p.z_mm : setup.conductor.plane_z_mm, r});
      // The other lobes above the bound on the faces at its depths, found between the
      // samples at once rather than one per round.
      if (two_d) {
        const Region g = fibre_region(setup, setup.receptors[r]);
        for (const double y : {g.y0_mm, g.y1_mm}) {
          if (y == g.y1_mm && !(g.y1_mm > g.y0_mm)) break;
          peaks_above(field.plane_af(setup.receptors[r], y, step_at(y) / 2), over,
                      [&](double px, double pz) {
                        add_off.push_back({px, y, pz, r});
                      });
        }
      }
    }
    if (lateral(opt, two_d, tp_.x_mm, tp_.z_mm) > quarter)
      add_target.push_back(
          {tp_.x_mm, tp_.y_mm, two_d ? tp_.z_mm : setup.conductor.plane_z_mm, target});
    if (far.af > opt.spill * target_af) {
      // Many lobes may sit at the cap, each exceeding it between samples by about as much:
      // lower the cap by any excess found, and add the point when it is more than the
      // check's tolerance.
      if (far.af > opt.spill * target_af * (1 + kCheckSpill))
        add_target.push_back(
            {far.x_mm, far.y_mm, two_d ? far.z_mm : setup.conductor.plane_z_mm, target});
      spill_cap *= opt.spill * target_af / far.af;
      for (std::size_t i = 0; i < caps.size(); ++i)
        if (beyond[i]) caps[i] = spill_cap;
    }
    const bool spill_over = far.af > opt.spill * target_af;
    res.summary = sum;
    res.target_max_af = target_af;
    res.spill = std::max(0.0, far.af) / target_af;
    const auto ratio = mode_ratio(sum.peaks, mode);
    res.ratio = ratio ? *ratio : kInf;
    const bool peak_away = lateral(opt, two_d, tp_.x_mm, tp_.z_mm) > quarter;
    if ((add_off.empty() && add_target.empty() && !spill_over) || res.rounds >= kMaxRounds) {
      // Never a silent violation: the bounds hold on the continuous fibres (the spill to
      // the check's tolerance) or the program says they cannot be met.
      if (peak_away || res.spill > opt.spill * (1 + kCheckSpill)) {
        why = {FocusFailure::Kind::rounds, res.spill, res.rounds, tp_.x_mm, tp_.z_mm};
        return std::nullopt;
      }
      break;
    }
    // Add the offending points with their mirror images through the focus, those within
    // the fibres' region: the array's symmetries that fix the focus (the answer's too), and
    // near the focus, where the pattern is nearly symmetric whatever the array, its next
    // lobes (else found one per round).
    auto with_mirrors = [&](const Sample& p, auto&& add) {
      add(p);
      const Region g = fibre_region(setup, setup.receptors[p.receptor]);
      for (const Mirror m : {Mirror{true, false}, Mirror{false, true}, Mirror{true, true}}) {
        if (m.z && !two_d) continue;
        const double mx = m.x ? 2 * opt.x_mm - p.x : p.x, mz = m.z ? 2 * opt.z_mm - p.z : p.z;
        if (mx >= g.x0_mm && mx <= g.x1_mm && (!two_d || (mz >= g.z0_mm && mz <= g.z1_mm)))
          add(Sample{mx, p.y, mz, p.receptor});
      }
    };
    for (const Sample& p : add_off) with_mirrors(p, [&](const Sample& s) { off.push_back(s); });
    for (const Sample& p : add_target) with_mirrors(p, add_target_sample);
  }

  if (opt.certify) {
    // The best over every place the peak may take: the LP with the last round's rows and
    // caps, its target at each sample within a quarter pitch of the focus and at p*'s
    // candidates.  p* is one of them, so the certified optimum is at most t*.  (The
    // rounds' LP holds those rows: the last round added none.)
    lp->set_caps(Eigen::Map<const Eigen::VectorXd>(last_caps.data(),
                                                   static_cast<Eigen::Index>(last_caps.size())));
    std::vector<Sample> cands = inner;
    for (const double y : all_depths)
      cands.push_back({opt.x_mm, y, two_d ? opt.z_mm : setup.conductor.plane_z_mm, target});
    const Eigen::MatrixXd rows = rows_of(setup, *conductor, tables, cands, basis);
    for (Eigen::Index i = 0; i < rows.rows(); ++i) {
      ++res.lp_solves;
      const auto sol = lp->solve(rows.row(i).transpose());
      if (sol && (!res.certified_optimum || sol->value < *res.certified_optimum)) {
        res.certified_optimum = sol->value;
        const Sample& c = cands[static_cast<std::size_t>(i)];
        res.certified_at = {sol->value, c.x, c.y, c.z};
      }
    }
    res.certified_points = cands.size();
  }

  res.weights.assign(w_best.data(), w_best.data() + w_best.size());
  for (double& v : res.weights)
    if (v == 0.0) v = 0.0;  // no -0 in the output
  for (double v : res.weights) res.currents_mA.push_back(v * opt.max_current_mA);
  res.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

FocusResult evaluate_focus(const Setup& setup, const std::string& mode, const FocusOptions& opt,
                           const std::vector<double>& weights) {
  const auto t0 = std::chrono::steady_clock::now();
  check_focus(setup, opt);
  const std::size_t target = receptor_index(setup, mode);
  const bool two_d = setup.array.two_d();
  FocusResult res;
  res.mode = mode;
  res.pitch_mm = nominal_pitch_mm(setup.array);
  res.radius_mm = opt.radius_mm > 0.0 ? opt.radius_mm : res.pitch_mm;
  res.weights = weights;
  for (double v : weights) res.currents_mA.push_back(v * opt.max_current_mA);
  {
    const auto c = make_conductor(setup.conductor, setup.array);
    check_fibre_reach(setup, *c);  // before any work
  }
  const auto [sum, far] =
      check_pattern(setup, res.currents_mA, setup.receptors[target], opt, res.radius_mm);
  res.summary = sum;
  const Peak& tp_ = res.summary.peaks[target].second;
  res.target_max_af = tp_.af;
  res.target_depth_mm = tp_.y_mm;
  res.spill = res.target_max_af > 0.0 ? std::max(0.0, far.af) / res.target_max_af : kInf;
  const auto ratio = mode_ratio(res.summary.peaks, mode);
  res.ratio = ratio ? *ratio : kInf;
  res.bounds_hold = lateral(opt, two_d, tp_.x_mm, tp_.z_mm) <= res.pitch_mm / 4.0 &&
                    res.spill <= opt.spill * (1 + kCheckSpill);
  res.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace tp
