// The `layered` conductor: each electrode a width_mm x length_mm rectangle of uniform
// current density on the insulated surface of a horizontally layered half-space
// (model/layered.hpp).  Coordinates as in rect3d: x across the electrodes, y depth, z along
// their length; the fibres lie in the plane z = plane_z_mm.
//
// In layer k the point response is C_k / R (closed form) plus a smooth remainder (layered.hpp),
// so a rectangle's field is rect3d's with rho = C_k plus the rectangle's remainder, a
// function of u = x - x_i and y only (every electrode is the same rectangle):
//   F_xx(u, y) = 1/(wL) Int_{b1}^{b2} [g(a2, b) - g(a1, b)] db,   g(a, b) = R'(r, y) a / r
//   F_zz(u, y) = 1/(wL) Int_{a1}^{a2} [g(b2, a) - g(b1, a)] da,   (a and b swapped)
//   F_yy = -(F_xx + F_zz)               (the remainder is harmonic inside the layer)
// with a1,2 = u -+ w/2, b1,2 = plane_z -+ L/2, r = sqrt(a^2 + b^2) and the remainder's radial
// derivative  R'(r, y) = -(1/2pi) Int rem(lambda, y) lambda J1(lambda r) dlambda.
//
// The remainder is analytic within a(y) = remainder_distance(y) of each point, so it is
// tabulated once per design as piecewise Chebyshev interpolants on fixed lattices:
//   - R'(r, y) on r-tiles [0, s], [s, 2s], [2s, 4s], ... (s = the smallest a of the stack),
//     16 nodes each, for each depth node; the Hankel integral is a fixed Gauss-Legendre rule
//     per r-tile (panels of at most half a period of J1 at the tile's largest r), so the
//     Bessel values are computed once per tile and every depth costs two exponentials per
//     node (remainder_coefficients);
//   - F_xx, F_zz on (u, y) tiles: y-tiles of half the layer's smallest a (geometric in the
//     semi-infinite bottom layer), u-tiles of that a near the rectangle, then doubling with
//     the distance from its edge; 16 x 10 nodes each, the edge integrals by 8-point
//     Gauss-Legendre on panels graded the same way.
// 2-D arrays (pads off z = 0, and any 3-D point): the rectangle's remainder at offset
// (u, v) = (x - x_i, z - z_i) from its centre, through its corners, with (a, b) = the
// point's offset from a corner along x and z:
//   F_xx = 1/(wL) C[Q(a, b)],  F_zz = 1/(wL) C[Q(b, a)],  F_xz = 1/(wL) C[R(r)],
//   Q(a, b) = Int_0^b g(a, beta) dbeta         (odd in a and in b),
// C[f] = f(a2, b2) - f(a1, b2) - f(a2, b1) + f(a1, b1) as in rect3d, R the point remainder.
// Q and R(r) are tabulated on (|a|, |b|) tiles at each depth node of a y-tile, a and b on
// the lattice 0, s, 2s, 4s, ... (s as the u-tiles'), 16 x 16 nodes each; Q by the graded
// rule up to the tile's first b, then 8-point Gauss-Legendre between consecutive nodes.
// From them, F_xx, F_zz (even in u and v) and F_xz (odd in each) are tabulated on
// (|u|, |v|, y) tiles (u and v graded from the pad's edges, as the u-tiles; 16 x 16 x 10
// nodes), so that a pad costs one 2-D interpolant per derivative.  Along a fibre at
// azimuth (c, s): c^2 F_xx + 2 c s F_xz + s^2 F_zz; vertical: F_yy = -(F_xx + F_zz).
//
// Each tile is built when first needed and kept (shared by every conductor of the same
// design in the process), and depends only on its own nodes: results do not depend on the
// order of evaluation.  A conductor object caches the current depth's row (not for use by
// two threads at once; separate objects are).

#include <algorithm>
#include <array>
#include <cmath>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number.hpp"
#include "model/conductor.hpp"
#include "model/layered.hpp"
#include "model/quadrature.hpp"

namespace tp {
namespace {

constexpr int kNu = 16;             // Chebyshev nodes along u per tile
constexpr int kNy = 10;             // along y
constexpr int kNq = 16;             // along a and b, per corner tile (2-D arrays)
constexpr int kNr = 16;             // along r, per r-tile
constexpr int kGl = 8;              // Gauss-Legendre points per panel
constexpr double kDecay = 40.0;     // Hankel integrals stop at e^-40 of the remainder's decay
constexpr double kMaxPanels = 2e5;  // panels of one r-tile's Hankel rule (~1 KB each, ~2 KB
                                    // with the potentials' J0: 2-D arrays)

const Chebyshev<kNu>& cheb_u() {
  static const Chebyshev<kNu> c;
  return c;
}
const Chebyshev<kNq>& cheb_q() {
  static const Chebyshev<kNq> c;
  return c;
}
// A 2-D Chebyshev series c[k * kNq + i] (degree k along the second variable, i along the
// first) at (ta, tb) in [-1, 1]^2.
// Clenshaw's recurrence along the second variable runs on whole rows at once (kNq
// independent lanes, which the compiler vectorises), then once along the first.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
double
cheb2(const double* c, double ta, double tb) {
  std::array<double, kNq> b1{}, b2{};
  const double tb2 = 2.0 * tb;
  for (std::size_t k = kNq - 1; k > 0; --k) {
    const double* row = c + k * kNq;
    for (std::size_t i = 0; i < kNq; ++i) {
      const double b0 = row[i] + tb2 * b1[i] - b2[i];
      b2[i] = b1[i];
      b1[i] = b0;
    }
  }
  std::array<double, kNq> along_a{};
  for (std::size_t i = 0; i < kNq; ++i) along_a[i] = c[i] + tb * b1[i] - b2[i];
  return Chebyshev<kNq>::eval(along_a.data(), ta);
}
// The 2-D coefficients of kNy planes of values f[(j * kNq + k) * kNq + i] at the nodes:
// along the first variable, then the second, into c (same layout).
void fit_planes(const double* f, double* c) {
  constexpr std::size_t kAB = kNq * kNq;
  std::array<double, kNy * kAB> t{};
  for (std::size_t jk = 0; jk < kNy * kNq; ++jk) cheb_q().fit(&f[jk * kNq], &t[jk * kNq]);
  for (std::size_t j = 0; j < kNy; ++j)
    for (std::size_t i = 0; i < kNq; ++i) cheb_q().fit(&t[j * kAB + i], &c[j * kAB + i], kNq);
}
const Chebyshev<kNy>& cheb_y() {
  static const Chebyshev<kNy> c;
  return c;
}
const Chebyshev<kNr>& cheb_r() {
  static const Chebyshev<kNr> c;
  return c;
}
const GaussLegendre<kGl>& gl8() {
  static const GaussLegendre<kGl> g;
  return g;
}

// Breakpoints 0, s, 2s, ... up to `shift + s`, then doubling the distance from `shift`:
// tiles of width s near the source and of width equal to their distance from it beyond.
struct AmplitudeLattice {
  double s = 1.0, shift = 0.0;
  long m0 = 1;      // first geometric index
  double b0 = 1.0;  // B(m0)
  AmplitudeLattice() = default;
  AmplitudeLattice(double s_, double shift_) : s(s_), shift(shift_) {
    m0 = std::max(1L, static_cast<long>(std::ceil((shift + s) / s)));
    b0 = static_cast<double>(m0) * s;
  }
  double at(long m) const {
    if (m <= m0) return static_cast<double>(m) * s;
    return shift + (b0 - shift) * std::ldexp(1.0, static_cast<int>(m - m0));
  }
  long index(double v) const {  // the tile [B(m), B(m+1)) holding v >= 0
    long m = v < b0 ? static_cast<long>(std::floor(v / s))
                    : m0 + static_cast<long>(std::floor(std::log2((v - shift) / (b0 - shift))));
    m = std::max(0L, m);
    while (m > 0 && at(m) > v) --m;
    while (at(m + 1) <= v) ++m;
    return m;
  }
};

// Gauss-Legendre points of an integral over [lo, hi], on panels cut at +-B(m) of a lattice
// with shift 0 centred on 0 (graded toward 0, where the integrands vary fastest).
template <class F>
double graded_integral(double lo, double hi, double s, F&& f) {
  if (!(hi > lo)) return 0.0;
  const AmplitudeLattice lat(s, 0.0);
  std::vector<double> cuts = {lo, hi};
  for (int sign : {-1, 1}) {
    for (long m = 0;; ++m) {
      const double b = sign * lat.at(m);
      if (b > lo && b < hi) cuts.push_back(b);
      if (lat.at(m) >= std::max(std::fabs(lo), std::fabs(hi))) break;
    }
  }
  std::sort(cuts.begin(), cuts.end());
  const auto& g = gl8();
  double sum = 0.0;
  for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
    const double a = cuts[p], b = cuts[p + 1];
    if (!(b > a)) continue;
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (std::size_t q = 0; q < kGl; ++q) sum += half * g.w[q] * f(mid + half * g.x[q]);
  }
  return sum;
}

// The shared, lazily built tables of one design: stack, rectangle and fibre plane.
class Tables {
 public:
  Tables(std::vector<Layer> layers, double width_mm, double length_mm, double plane_z_mm)
      : stack_(std::move(layers)), w_(width_mm), l_(length_mm), z_(plane_z_mm) {
    const auto& ls = stack_.layers();
    const std::size_t n = ls.size();
    a_glob_ = INFINITY;
    for (std::size_t k = 0; k < n; ++k) {
      a_glob_ = std::min(a_glob_, layer_a_min(k, stack_.top_of(k),
                                              k + 1 < n ? stack_.top_of(k + 1) : stack_.top_of(k)));
    }
    stack_depth_ = std::max(stack_.top_of(n - 1), a_glob_);
    r_lattice_ = AmplitudeLattice(a_glob_, 0.0);
    lambda_max_ = kDecay / a_glob_;
  }

  const LayeredHalfSpace& stack() const { return stack_; }

  struct Tile {
    double u0, u1;
    std::array<double, kNy * kNu> cxx{}, czz{};  // [j * kNu + i]: y-degree j, u-degree i
  };
  // Q(a, b) and R(sqrt(a^2 + b^2)) on one (a, b) tile of a y-tile, at each of its depth
  // nodes (what the F tiles are built from).
  struct QTile {
    double a0 = 0.0, a1 = 0.0, b0 = 0.0, b1 = 0.0;
    // [(j * kNq + k) * kNq + i]: depth node j, b-degree k, a-degree i
    std::array<double, kNy * kNq * kNq> cq{}, cp{};
  };
  // A pad's remainder F_xx, F_zz (even in u and in v) and F_xz (odd in each) on one
  // (|u|, |v|) tile of a y-tile (u, v: the point's offset from the pad's centre).
  struct FTile {
    double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0;
    // [(j * kNq + k) * kNq + i]: y-degree j, v-degree k, u-degree i
    std::array<double, kNy * kNq * kNq> cxx{}, czz{}, cxz{};
  };
  struct YTile {
    std::size_t layer = 0;
    double y0 = 0.0, y1 = 0.0, s = 0.0;
    AmplitudeLattice u, q;
    std::vector<std::unique_ptr<Tile>> tiles;  // by u-tile index
    AmplitudeLattice fu, fv;                            // u and v, graded from the pad's edges
    std::map<std::pair<long, long>, std::unique_ptr<QTile>> qtiles;  // by (a, b) tile index
    std::map<std::pair<long, long>, std::unique_ptr<FTile>> ftiles;  // by (u, v) tile index
  };

  // The y-tile holding depth y (> 0), built on first use.
  const YTile& ytile(double y) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::size_t k = stack_.layer_of(y);
    const std::size_t n = stack_.layers().size();
    double y0 = 0.0, y1 = 0.0;
    long j = 0;
    if (k + 1 < n) {
      const double t0 = stack_.top_of(k), t1 = stack_.top_of(k + 1);
      const double a = layer_a_min(k, t0, t1);
      const long count = static_cast<long>(std::ceil((t1 - t0) / (0.5 * a)));
      j = std::clamp(
          static_cast<long>(std::floor((y - t0) / (t1 - t0) * static_cast<double>(count))), 0L,
          count - 1);
      y0 = t0 + (t1 - t0) * static_cast<double>(j) / static_cast<double>(count);
      y1 = j + 1 == count
               ? t1
               : t0 + (t1 - t0) * static_cast<double>(j + 1) / static_cast<double>(count);
    } else {
      // y + g grows by 3/2 per tile: tile height half the remainder distance a = y + g.
      const double t = stack_.top_of(k), g = stack_.remainder_distance(t) - t;
      auto at = [&](long i) { return (t + g) * std::pow(1.5, static_cast<double>(i)) - g; };
      j = std::max(0L, static_cast<long>(std::floor(std::log((y + g) / (t + g)) / std::log(1.5))));
      while (j > 0 && at(j) > y) --j;
      while (at(j + 1) <= y) ++j;
      y0 = j == 0 ? t : at(j);
      y1 = at(j + 1);
    }
    auto& slot = ytiles_[{k, j}];
    if (!slot) {
      slot = std::make_unique<YTile>();
      slot->layer = k;
      slot->y0 = y0;
      slot->y1 = y1;
      slot->s = layer_a_min(k, y0, y1);
      slot->u = AmplitudeLattice(slot->s, 0.5 * w_);
      slot->q = AmplitudeLattice(slot->s, 0.0);
      slot->fu = AmplitudeLattice(slot->s, 0.5 * w_);
      slot->fv = AmplitudeLattice(slot->s, 0.5 * l_);
    }
    return *slot;
  }

  // Tile m of a y-tile, built on first use.
  const Tile& tile(const YTile& yt_const, long m) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& yt = const_cast<YTile&>(yt_const);  // owned by ytiles_; only this object mutates it
    const auto mi = static_cast<std::size_t>(m);
    if (yt.tiles.size() <= mi) yt.tiles.resize(mi + 1);
    if (!yt.tiles[mi]) yt.tiles[mi] = build_tile(yt, m);
    return *yt.tiles[mi];
  }

  // F tile (iu, iv) of a y-tile, built on first use.
  const FTile& ftile(const YTile& yt_const, long iu, long iv) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& yt = const_cast<YTile&>(yt_const);  // owned by ytiles_; only this object mutates it
    auto& slot = yt.ftiles[{iu, iv}];
    if (!slot) slot = build_ftile(yt, iu, iv);
    return *slot;
  }

  // Bad input when a point at a depth in [y_min_mm, y_max_mm] and lateral offset up to
  // u_max_mm from an electrode would need more than kMaxPanels panels.  Conservative: for
  // every y-tile the range meets, the r-tile of the farthest edge of the u-tile of u_max_mm,
  // at every depth node of the y-tile (what its second derivatives are built from) and at
  // the range's ends within it (where potentials are evaluated).  Checked before any work or
  // output, so that no evaluation fails half-way through.
  // corners: the point may be off the plane z = plane_z (a 2-D array's pads, a 3-D point),
  // u_max_mm its largest distance from a pad's centre: the corner tiles' reach is checked.
  void reach(double u_max_mm, double y_min_mm, double y_max_mm, const std::string& what,
             bool corners) {
    double worst = 0.0, at_y_mm = y_min_mm;
    // A tile lies in one layer, where the remainder distance is concave in y: its least over
    // any interval is at an end.
    auto consider = [&](const RGrid& g, std::size_t layer, double y_mm) {
      const double p = panels_to(g, kDecay / stack_.remainder_distance_in(layer, y_mm));
      if (p > worst) {
        worst = p;
        at_y_mm = y_mm;
      }
    };
    double y_mm = y_min_mm, last_y1_mm = -1.0;
    for (;;) {
      const YTile& yt = ytile(y_mm);
      if (!(yt.y1 > last_y1_mm)) {  // y on a tile's bottom, rounded into it: step past
        y_mm = std::nextafter(y_mm, INFINITY);
        continue;
      }
      last_y1_mm = yt.y1;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        const double u1 = yt.u.at(yt.u.index(std::fabs(u_max_mm)) + 1);
        double r_max = std::hypot(u1 + 0.5 * w_, std::fabs(z_) + 0.5 * l_);
        if (corners) {  // the F tiles' far ends, and the corner tiles those need
          const double off = std::fabs(u_max_mm);
          const double a = yt.fu.at(yt.fu.index(off) + 1) + 0.5 * w_,
                       b = yt.fv.at(yt.fv.index(off) + 1) + 0.5 * l_;
          r_max =
              std::max(r_max, std::hypot(yt.q.at(yt.q.index(a) + 1), yt.q.at(yt.q.index(b) + 1)));
        }
        const RGrid& g = rgrid(r_lattice_.index(r_max));
        const double ymid = 0.5 * (yt.y0 + yt.y1), yhalf = 0.5 * (yt.y1 - yt.y0);
        for (std::size_t j = 0; j < kNy; ++j) consider(g, yt.layer, ymid + yhalf * cheb_y().t[j]);
        consider(g, yt.layer, std::max(y_min_mm, yt.y0));
        consider(g, yt.layer, std::min(y_max_mm, yt.y1));
      }
      if (yt.y1 >= y_max_mm) break;
      y_mm = yt.y1;
    }
    if (!(worst <= kMaxPanels))
      bad_input("layered: " + what + " at depth " +
                (y_max_mm > y_min_mm ? number_text(y_min_mm) + " to " + number_text(y_max_mm)
                                     : number_text(y_min_mm)) +
                " mm, up to " + number_text(std::fabs(u_max_mm)) +
                " mm from an electrode, would need a Hankel rule of " + number_text(worst) +
                " panels (at most " + number_text(kMaxPanels) + ", near depth " +
                number_text(at_y_mm) +
                " mm): the skin's thinnest layer is too thin for points this "
                "shallow this far away (deeper points, or a narrower grid, array or margin)");
  }

  // The remainder's potential (V, 1 mA injected) of one rectangle at (u, y): a 2-D integral
  // of the tabulated point remainder (for unit_potentials, which only the checks use).
  // v: the point's offset from the rectangle's centre along z.
  // Memoised: the arguments are rounded to 1 pm (1e-9 mm) and the potential computed at the
  // rounded point, cached or not, so the value does not depend on what was asked before.
  // Fibre placements on a lattice (vertical fibres and afferents every quarter pitch) meet
  // the same offsets from different pads, and each is integrated once.
  double remainder_potential(double u, double v, double y) {
    const std::array<long long, 3> key{std::llround(u * 1e9), std::llround(v * 1e9),
                                       std::llround(y * 1e9)};
    u = static_cast<double>(key[0]) * 1e-9;
    v = static_cast<double>(key[1]) * 1e-9;
    y = static_cast<double>(key[2]) * 1e-9;
    // Under the lock: the memo, and the r-tiles the integral reaches, built if need be and
    // copied out; the integral itself runs outside it, so that threads integrate at once.
    const double a1 = u - 0.5 * w_, a2 = u + 0.5 * w_, b1 = v - 0.5 * l_, b2 = v + 0.5 * l_;
    auto nearest = [](double lo, double hi) { return lo > 0.0 ? lo : hi < 0.0 ? -hi : 0.0; };
    const double r_lo = std::hypot(nearest(a1, a2), nearest(b1, b2));
    const double r_hi =
        std::hypot(std::max(std::fabs(a1), std::fabs(a2)), std::max(std::fabs(b1), std::fabs(b2)));
    RTable* rt = nullptr;
    long m0 = 0;
    std::vector<std::array<double, kNr>> local;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (const auto it = potential_memo_.find(key); it != potential_memo_.end()) return it->second;
      rt = &rtable(y);
      m0 = r_lattice_.index(r_lo);
      const long m1 = r_lattice_.index(r_hi);
      for (long m = m0; m <= m1; ++m) {
        const auto mi = static_cast<std::size_t>(m);
        if (rt->have_pot.size() <= mi || !rt->have_pot[mi]) fill(*rt, m, true);
        local.push_back(rt->pot[mi]);
      }
    }
    // The same tiles and the same arithmetic as RTable::eval: the same value.  A point the
    // rounding puts past the range is evaluated under the lock.
    auto eval = [&](double r) {
      const long m = r_lattice_.index(r);
      if (m < m0 || m - m0 >= static_cast<long>(local.size())) {
        std::lock_guard<std::mutex> lock(mutex_);
        return rt->eval(*this, r, true);
      }
      const double r0 = r_lattice_.at(m), r1 = r_lattice_.at(m + 1);
      return Chebyshev<kNr>::eval(local[static_cast<std::size_t>(m - m0)].data(),
                                  (2.0 * r - r0 - r1) / (r1 - r0));
    };
    const double s = stack_.remainder_distance(y);
    const double total = graded_integral(a1, a2, s, [&](double a) {
      return graded_integral(b1, b2, s, [&](double b) { return eval(std::hypot(a, b)); });
    });
    const double value = total / (w_ * l_);
    std::lock_guard<std::mutex> lock(mutex_);
    if (potential_memo_.size() >= kPotentialMemo) potential_memo_.clear();  // bounded
    potential_memo_.emplace(key, value);
    return value;
  }

 private:
  double layer_a_min(std::size_t k, double t0, double t1) const {
    return std::min(stack_.remainder_distance_in(k, t0), stack_.remainder_distance_in(k, t1));
  }

  // The Hankel rule of one r-tile: nodes, weights and lambda W J1(lambda r_i) (and, when
  // potentials are asked for, W J0(lambda r_i)) at its 16 r nodes.
  struct RGrid {
    double r0 = 0.0, r1 = 0.0;
    std::vector<double> fixed_cuts;  // the panels up to coarse_start
    double coarse_start = 0.0, coarse_width = 1.0, coarse_count = 0.0;
    // The nodes, extended as depths need them:
    std::vector<double> lambda, weight;
    std::vector<std::size_t> panel_end;  // nodes up to each panel's end
    // Filled on demand up to the largest lambda a depth has needed (each entry depends on
    // its node alone, so how far they are filled changes no value):
    std::vector<double> j1, j0;                    // [q * kNr + i]
    std::vector<std::vector<double>> alpha, beta;  // per layer
  };
  RGrid& rgrid(long m) {
    const auto mi = static_cast<std::size_t>(m);
    if (rgrids_.size() <= mi) rgrids_.resize(mi + 1);
    if (rgrids_[mi]) return *rgrids_[mi];
    auto g = std::make_unique<RGrid>();
    g->r0 = r_lattice_.at(m);
    g->r1 = r_lattice_.at(m + 1);
    // Panels: graded toward lambda = 0 (the kernel's poles near the origin for high
    // contrasts), then at most 1/(4 H) up to 20 / H (the kernel's slow scale, where its
    // poles lie within ~pi / h of the axis; H the stack's depth, at least its thickest
    // layer), then the coarse width: half a period of J1 at r1, and fine enough for the
    // remainder's decay.  The nodes and Bessel values are built only as far as a depth needs
    // (to kDecay over its remainder distance), and that is bounded: at most kMaxPanels
    // (~200 MB, or ~400 MB with J0 for 2-D arrays), checked per depth (fill(), reach()), so that a
    // deep point far from the electrodes is not refused for what a shallow one would need.
    const double coarse = std::min(kQuadPi / g->r1, 0.5 / a_glob_);
    const double fine = std::min(coarse, 0.25 / stack_depth_);
    const double lambda_fine = std::min(20.0 / stack_depth_, lambda_max_);
    std::vector<double> cuts = {0.0};
    auto cut_to = [&](double end, double width) {  // equal panels of at most `width`
      const double start = cuts.back();
      const double n = std::ceil((end - start) / width);
      for (double i = 1; i <= n; ++i) cuts.push_back(i == n ? end : start + (end - start) * i / n);
    };
    for (double e = 1e-3 / stack_depth_; e < 1.0 / stack_depth_ && e < lambda_fine; e *= 2.0)
      cut_to(e, fine);
    cut_to(lambda_fine, fine);
    g->fixed_cuts = std::move(cuts);
    // Beyond lambda_fine, equal panels to lambda_max, added as depths need them.
    g->coarse_count = std::max(1.0, std::ceil((lambda_max_ - lambda_fine) / coarse));
    g->coarse_start = lambda_fine;
    g->coarse_width = (lambda_max_ - lambda_fine) / g->coarse_count;
    g->alpha.resize(stack_.layers().size());
    g->beta.resize(stack_.layers().size());
    rgrids_[mi] = std::move(g);
    return *rgrids_[mi];
  }
  // The panel start of panel p, and the nodes of every panel that starts at or below
  // lam_stop (built on demand; returns how many panels that is).
  static double panel_start(const RGrid& g, std::size_t p) {
    const std::size_t nf = g.fixed_cuts.size() - 1;
    return p < nf ? g.fixed_cuts[p] : g.coarse_start + static_cast<double>(p - nf) * g.coarse_width;
  }
  static double panel_stop(const RGrid& g, std::size_t p) {
    const std::size_t nf = g.fixed_cuts.size() - 1;
    return p + 1 < nf + 1 ? g.fixed_cuts[p + 1]
                          : g.coarse_start + static_cast<double>(p + 1 - nf) * g.coarse_width;
  }
  // The number of panels that start at or below lam_stop (what extend_panels() builds).
  static double panels_to(const RGrid& g, double lam_stop) {
    const std::size_t nf = g.fixed_cuts.size() - 1;
    const double fixed = static_cast<double>(
        std::upper_bound(g.fixed_cuts.begin(), g.fixed_cuts.end() - 1, lam_stop) -
        g.fixed_cuts.begin());
    if (fixed < static_cast<double>(nf) || lam_stop < g.coarse_start) return fixed;
    return fixed +
           std::min(g.coarse_count, std::floor((lam_stop - g.coarse_start) / g.coarse_width) + 1.0);
  }
  // lam_stop of a depth: the remainder is negligible beyond it.
  double lambda_stop(double y) const { return kDecay / stack_.remainder_distance(y); }
  static void check_panels(const RGrid& g, double lam_stop, double y) {
    const double panels = panels_to(g, lam_stop);
    if (!(panels <= kMaxPanels))
      failure("layered: the Hankel rule needs " + number_text(panels) + " panels at depth " +
              number_text(y) + " mm, " + number_text(g.r1) + " mm from an electrode (at most " +
              number_text(kMaxPanels) + ")");
  }
  static std::size_t extend_panels(RGrid& g, double lam_stop) {
    const std::size_t total = g.fixed_cuts.size() - 1 + static_cast<std::size_t>(g.coarse_count);
    std::size_t p = 0;
    while (p < total && panel_start(g, p) <= lam_stop) {
      if (p == g.panel_end.size()) {
        const double a = panel_start(g, p), b = panel_stop(g, p);
        const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
        const auto& gl = gl8();
        for (std::size_t q = 0; q < kGl; ++q) {
          g.lambda.push_back(mid + half * gl.x[q]);
          g.weight.push_back(half * gl.w[q]);
        }
        g.panel_end.push_back(g.lambda.size());
      }
      ++p;
    }
    return p;
  }

  // The Bessel values (J1, or J0 for potentials) and layer k's coefficients at the nodes
  // below `nq`.
  void need(RGrid& g, std::size_t nq, bool potential, std::size_t k) {
    auto& mat = potential ? g.j0 : g.j1;
    const double mid = 0.5 * (g.r0 + g.r1), half = 0.5 * (g.r1 - g.r0);
    for (std::size_t q = mat.size() / kNr; q < nq; ++q)
      for (std::size_t i = 0; i < kNr; ++i) {
        const double x = g.lambda[q] * (mid + half * cheb_r().t[i]);
        mat.push_back(potential ? g.weight[q] * ::j0(x) : g.weight[q] * g.lambda[q] * ::j1(x));
      }
    for (std::size_t q = g.alpha[k].size(); q < nq; ++q) {
      double a = 0.0, b = 0.0;
      stack_.remainder_coefficients(g.lambda[q], k, a, b);
      g.alpha[k].push_back(a);
      g.beta[k].push_back(b);
    }
  }

  // R'(r, y) (and the remainder itself, for potentials) at one depth, on the r-tiles.
  struct RTable {
    double y = 0.0;
    std::size_t layer = 0;
    std::vector<std::array<double, kNr>> dr, pot;  // per r-tile; pot only on demand
    std::vector<char> have_dr, have_pot;
    double eval(Tables& t, double r, bool potential) {
      const long m = t.r_lattice_.index(r);
      const auto mi = static_cast<std::size_t>(m);
      auto& have = potential ? have_pot : have_dr;
      if (have.size() <= mi || !have[mi]) t.fill(*this, m, potential);
      const double r0 = t.r_lattice_.at(m), r1 = t.r_lattice_.at(m + 1);
      const auto& c = potential ? pot[mi] : dr[mi];
      return Chebyshev<kNr>::eval(c.data(), (2.0 * r - r0 - r1) / (r1 - r0));
    }
  };
  RTable& rtable(double y) {
    auto& slot = rtables_[y];
    if (!slot) {
      slot = std::make_unique<RTable>();
      slot->y = y;
      slot->layer = stack_.layer_of(y);
    }
    return *slot;
  }
  void fill(RTable& rt, long m, bool potential) {
    const auto mi = static_cast<std::size_t>(m);
    RGrid& g = rgrid(m);
    const std::size_t k = rt.layer;
    const double y = rt.y;
    const double s = y - stack_.top_of(k);
    const double h2 = k + 1 < stack_.layers().size() ? 2.0 * stack_.layers()[k].thickness_mm : 0.0;
    const double lam_stop = lambda_stop(y);
    // The panels this depth needs: up to the first that starts beyond lam_stop.
    check_panels(g, lam_stop, y);
    const std::size_t panels = extend_panels(g, lam_stop);
    const std::size_t nq = panels == 0 ? 0 : g.panel_end[panels - 1];
    need(g, nq, potential, k);
    std::array<double, kNr> v{};
    const auto& mat = potential ? g.j0 : g.j1;
    {
      for (std::size_t q = 0; q < nq; ++q) {
        const double lam = g.lambda[q];
        double rem = g.alpha[k][q] * std::exp(-lam * s);
        if (g.beta[k][q] != 0.0) rem += g.beta[k][q] * std::exp(-lam * (h2 - s));
        const double* row = &mat[q * kNr];
        for (std::size_t i = 0; i < kNr; ++i) v[i] += rem * row[i];
      }
    }
    // R' = -(1/2pi) Int rem lambda J1;  R = (1/2pi) Int rem J0.
    const double scale = (potential ? 1.0 : -1.0) / (2.0 * kQuadPi);
    for (double& x : v) x *= scale;
    auto& store = potential ? rt.pot : rt.dr;
    auto& have = potential ? rt.have_pot : rt.have_dr;
    if (store.size() <= mi) {
      store.resize(mi + 1);
      have.resize(mi + 1, 0);
    }
    cheb_r().fit(v.data(), store[mi].data());
    have[mi] = 1;
  }

  std::unique_ptr<Tile> build_tile(const YTile& yt, long m) {
    auto tile = std::make_unique<Tile>();
    tile->u0 = yt.u.at(m);
    tile->u1 = yt.u.at(m + 1);
    const double b1 = z_ - 0.5 * l_, b2 = z_ + 0.5 * l_;
    const double hw = 0.5 * w_;
    std::array<double, kNy * kNu> fxx{}, fzz{};
    const double umid = 0.5 * (tile->u0 + tile->u1), uhalf = 0.5 * (tile->u1 - tile->u0);
    const double ymid = 0.5 * (yt.y0 + yt.y1), yhalf = 0.5 * (yt.y1 - yt.y0);
    for (std::size_t j = 0; j < kNy; ++j) {
      const double y = ymid + yhalf * cheb_y().t[j];
      RTable& rt = rtable(y);
      auto g = [&](double a, double b) {
        const double r = std::hypot(a, b);
        return r > 0.0 ? rt.eval(*this, r, false) * a / r : 0.0;
      };
      for (std::size_t i = 0; i < kNu; ++i) {
        const double u = umid + uhalf * cheb_u().t[i];
        const double a1 = u - hw, a2 = u + hw;
        fxx[j * kNu + i] =
            graded_integral(b1, b2, yt.s, [&](double b) { return g(a2, b) - g(a1, b); }) /
            (w_ * l_);
        fzz[j * kNu + i] =
            graded_integral(a1, a2, yt.s, [&](double a) { return g(b2, a) - g(b1, a); }) /
            (w_ * l_);
      }
    }
    // 2-D coefficients: along u for each y node, then along y for each u degree.
    std::array<double, kNy * kNu> tmp{};
    for (auto [f, c] : {std::pair{&fxx, &tile->cxx}, std::pair{&fzz, &tile->czz}}) {
      for (std::size_t j = 0; j < kNy; ++j) cheb_u().fit(&(*f)[j * kNu], &tmp[j * kNu]);
      for (std::size_t i = 0; i < kNu; ++i) cheb_y().fit(&tmp[i], &(*c)[i], kNu);
    }
    return tile;
  }

  std::unique_ptr<QTile> build_qtile(const YTile& yt, long ia, long ib) {
    auto tile = std::make_unique<QTile>();
    tile->a0 = yt.q.at(ia);
    tile->a1 = yt.q.at(ia + 1);
    tile->b0 = yt.q.at(ib);
    tile->b1 = yt.q.at(ib + 1);
    constexpr std::size_t kAB = kNq * kNq;
    std::array<double, kNy * kAB> q{}, p{};
    const double amid = 0.5 * (tile->a0 + tile->a1), ahalf = 0.5 * (tile->a1 - tile->a0);
    const double bmid = 0.5 * (tile->b0 + tile->b1), bhalf = 0.5 * (tile->b1 - tile->b0);
    const double ymid = 0.5 * (yt.y0 + yt.y1), yhalf = 0.5 * (yt.y1 - yt.y0);
    const auto& gl = gl8();
    for (std::size_t j = 0; j < kNy; ++j) {
      RTable& rt = rtable(ymid + yhalf * cheb_y().t[j]);
      for (std::size_t i = 0; i < kNq; ++i) {
        const double a = amid + ahalf * cheb_q().t[i];  // > 0: nodes are interior
        auto g = [&](double b) {
          const double r = std::hypot(a, b);
          return rt.eval(*this, r, false) * a / r;
        };
        // Q(a, b0), then on from node to node (the nodes decrease with their index).
        double acc = graded_integral(0.0, tile->b0, yt.s, g), prev = tile->b0;
        for (std::size_t k = kNq; k-- > 0;) {
          const double b = bmid + bhalf * cheb_q().t[k];
          const double half = 0.5 * (b - prev), mid = 0.5 * (b + prev);
          for (std::size_t n = 0; n < kGl; ++n) acc += half * gl.w[n] * g(mid + half * gl.x[n]);
          prev = b;
          q[j * kAB + k * kNq + i] = acc;
          p[j * kAB + k * kNq + i] = rt.eval(*this, std::hypot(a, b), true);
        }
      }
    }
    // Per depth node: 2-D coefficients, along a, then b.
    fit_planes(q.data(), tile->cq.data());
    fit_planes(p.data(), tile->cp.data());
    return tile;
  }

  // Q(a, b) (odd in each) and R at depth node j of a y-tile (mutex_ held).
  void corner_at(YTile& yt, std::size_t j, double a, double b, double& q, double& r) {
    const double aa = std::fabs(a), bb = std::fabs(b);
    const long ia = yt.q.index(aa), ib = yt.q.index(bb);
    auto& slot = yt.qtiles[{ia, ib}];
    if (!slot) slot = build_qtile(yt, ia, ib);
    const QTile& t = *slot;
    const double ta = (2.0 * aa - t.a0 - t.a1) / (t.a1 - t.a0);
    const double tb = (2.0 * bb - t.b0 - t.b1) / (t.b1 - t.b0);
    constexpr std::size_t kAB = kNq * kNq;
    auto eval2 = [&](const double* c) { return cheb2(c, ta, tb); };
    q = ((a < 0.0) != (b < 0.0) ? -1.0 : 1.0) * eval2(&t.cq[j * kAB]);
    r = eval2(&t.cp[j * kAB]);
  }

  std::unique_ptr<FTile> build_ftile(YTile& yt, long iu, long iv) {
    auto tile = std::make_unique<FTile>();
    tile->u0 = yt.fu.at(iu);
    tile->u1 = yt.fu.at(iu + 1);
    tile->v0 = yt.fv.at(iv);
    tile->v1 = yt.fv.at(iv + 1);
    constexpr std::size_t kAB = kNq * kNq;
    std::array<double, kNy * kAB> fxx{}, fzz{}, fxz{}, t2{};
    const double umid = 0.5 * (tile->u0 + tile->u1), uhalf = 0.5 * (tile->u1 - tile->u0);
    const double vmid = 0.5 * (tile->v0 + tile->v1), vhalf = 0.5 * (tile->v1 - tile->v0);
    const double hw = 0.5 * w_, hl = 0.5 * l_, inv_area = 1.0 / (w_ * l_);
    for (std::size_t j = 0; j < kNy; ++j)
      for (std::size_t k = 0; k < kNq; ++k)
        for (std::size_t i = 0; i < kNq; ++i) {
          const double u = umid + uhalf * cheb_q().t[i], v = vmid + vhalf * cheb_q().t[k];
          const double a[2] = {u - hw, u + hw}, b[2] = {v - hl, v + hl};
          double sxx = 0.0, szz = 0.0, sxz = 0.0;
          for (int pa = 0; pa < 2; ++pa)
            for (int qb = 0; qb < 2; ++qb) {
              const double sign = pa == qb ? 1.0 : -1.0;  // + at (a2, b2) and (a1, b1)
              double q = 0.0, r = 0.0;
              corner_at(yt, j, a[pa], b[qb], q, r);
              sxx += sign * q;
              sxz += sign * r;
              corner_at(yt, j, b[qb], a[pa], q, r);
              szz += sign * q;
            }
          const std::size_t at = j * kAB + k * kNq + i;
          fxx[at] = sxx * inv_area;
          fzz[at] = szz * inv_area;
          fxz[at] = sxz * inv_area;
        }
    // 3-D coefficients: along u, then v, then y.
    for (auto [f, c] :
         {std::pair{&fxx, &tile->cxx}, std::pair{&fzz, &tile->czz}, std::pair{&fxz, &tile->cxz}}) {
      fit_planes(f->data(), t2.data());
      for (std::size_t ki = 0; ki < kAB; ++ki) cheb_y().fit(&t2[ki], &(*c)[ki], kAB);
    }
    return tile;
  }

  LayeredHalfSpace stack_;
  double w_, l_, z_;
  double a_glob_ = 1.0, stack_depth_ = 1.0, lambda_max_ = 1.0;
  AmplitudeLattice r_lattice_;
  std::mutex mutex_;
  static constexpr std::size_t kPotentialMemo = 500'000;  // about 40 MB at most
  std::map<std::array<long long, 3>, double> potential_memo_;
  std::map<std::pair<std::size_t, long>, std::unique_ptr<YTile>> ytiles_;
  std::vector<std::unique_ptr<RGrid>> rgrids_;
  std::map<double, std::unique_ptr<RTable>> rtables_;
};

// The process's tables, by design: the last few designs are kept, so that the many
// conductors an optimisation makes share one set.
std::shared_ptr<Tables> tables_for(const std::vector<Layer>& layers, double w, double l, double z) {
  static std::mutex mutex;
  static std::list<std::pair<std::vector<double>, std::shared_ptr<Tables>>> cache;
  std::vector<double> key = {w, l, z};
  for (const Layer& ly : layers) {
    key.push_back(ly.thickness_mm);
    key.push_back(ly.resistivity_ohm_m);
  }
  std::lock_guard<std::mutex> lock(mutex);
  for (auto it = cache.begin(); it != cache.end(); ++it)
    if (it->first == key) {
      cache.splice(cache.begin(), cache, it);
      return cache.front().second;
    }
  cache.emplace_front(key, std::make_shared<Tables>(layers, w, l, z));
  if (cache.size() > 4) cache.pop_back();
  return cache.front().second;
}

class Layered : public Conductor {
 public:
  Layered(const ElectrodeArray& array, const std::vector<Layer>& layers, double plane_z_mm)
      : x_(array.positions_mm), pz_(array.z_mm), z_(plane_z_mm), stack_(layers) {
    if (!(array.width_mm > 0.0)) bad_input("layered: array.width_mm must be > 0");
    for (std::size_t k = 0; k < layers.size(); ++k)
      rect_.push_back(make_rect3d(array, stack_.leading_of(k), plane_z_mm));
    if (!stack_.uniform())
      tables_ = tables_for(layers, array.width_mm, array.length_mm, plane_z_mm);
    scratch_.resize(2 * x_.size());
  }
  const char* name() const override { return "layered"; }
  std::size_t size() const override { return x_.size(); }
  bool planar_harmonic() const override { return false; }
  // 3-D points for 2-D arrays (a 1-D array's plane maps would need their z range checked
  // against the Hankel rule: not offered).
  bool three_d() const override { return !pz_.empty(); }
  std::vector<double> interfaces_mm() const override {
    std::vector<double> tops;
    for (std::size_t k = 1; k < stack_.layers().size(); ++k) tops.push_back(stack_.top_of(k));
    return tops;
  }

  void unit_potentials(double x_mm, double y_mm, double* psi) const override {
    if (!pz_.empty()) return unit_potentials_3d(x_mm, y_mm, z_, psi);
    check_depth(y_mm);
    rect_[stack_.layer_of(y_mm)]->unit_potentials(x_mm, y_mm, psi);
    if (!tables_) return;
    for (std::size_t i = 0; i < x_.size(); ++i)
      psi[i] -= tables_->remainder_potential(x_mm - x_[i], z_, y_mm);  // cathodic
  }

  void unit_potentials_3d(double x_mm, double y_mm, double z_mm, double* psi) const override {
    check_depth(y_mm);
    rect_[stack_.layer_of(y_mm)]->unit_potentials_3d(x_mm, y_mm, z_mm, psi);
    if (!tables_) return;
    for (std::size_t i = 0; i < x_.size(); ++i)
      psi[i] -= tables_->remainder_potential(x_mm - x_[i], z_mm - pz(i), y_mm);  // cathodic
  }

  void unit_d2_along(double x_mm, double y_mm, double z_mm, const FibreAxis& e,
                     double* out) const override {
    check_depth(y_mm);
    rect_[stack_.layer_of(y_mm)]->unit_d2_along(x_mm, y_mm, z_mm, e, out);
    if (!tables_) return;
    select_frow(y_mm);
    const double cc = e.cos_az * e.cos_az, cs2 = 2.0 * e.cos_az * e.sin_az,
                 ss = e.sin_az * e.sin_az;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      // Cathodic: minus the injected current's remainder.
      out[i] -= f_along(x_mm - x_[i], z_mm - pz(i), e.vertical, cc, cs2, ss);
    }
  }

  void unit_second_derivatives(double x_mm, double y_mm, double* xx, double* yy) const override {
    if (!pz_.empty()) {  // a 2-D array: its section at z = plane_z_mm
      if (xx) unit_d2_along(x_mm, y_mm, z_, FibreAxis{}, xx);
      if (yy) unit_d2_along(x_mm, y_mm, z_, FibreAxis{true, 0.0, 0.0}, yy);
      return;
    }
    check_depth(y_mm);
    const std::size_t n = x_.size();
    double* rx = scratch_.data();
    double* ry = rx + n;
    rect_[stack_.layer_of(y_mm)]->unit_second_derivatives(x_mm, y_mm, rx, ry);
    if (tables_) {
      select_row(y_mm);
      for (std::size_t i = 0; i < n; ++i) {
        double fxx = 0.0, fzz = 0.0;
        remainder(std::fabs(x_mm - x_[i]), fxx, fzz);
        rx[i] -= fxx;  // cathodic: minus the injected current's field
        ry[i] += fxx + fzz;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (xx) xx[i] = rx[i];
      if (yy) yy[i] = ry[i];
    }
  }

  void check_reach(double max_offset_mm, double y_min_mm, double y_max_mm,
                   const std::string& what) const override {
    check_depth(y_min_mm);
    check_depth(y_max_mm);
    if (tables_) tables_->reach(max_offset_mm, y_min_mm, y_max_mm, what, !pz_.empty());
  }

  // d2Psi/dz2 of electrode i (the tests' Laplace check).
  double unit_zz(std::size_t i, double x_mm, double y_mm) const {
    if (!pz_.empty()) failure("layered_unit_zz: a 1-D array's (use unit_d2_along along z)");
    check_depth(y_mm);
    double zz = rect3d_unit_zz(*rect_[stack_.layer_of(y_mm)], i, x_mm, y_mm);
    if (tables_) {
      select_row(y_mm);
      double fxx = 0.0, fzz = 0.0;
      remainder(std::fabs(x_mm - x_[i]), fxx, fzz);
      zz -= fzz;
    }
    return zz;
  }

 private:
  static void check_depth(double y_mm) {
    if (!(y_mm > 0.0) || !std::isfinite(y_mm))
      bad_input("layered: depth must be > 0 mm, got " + number_text(y_mm));
  }

  // The current depth's y-tile, and each u-tile's coefficients collapsed along y.
  void select_row(double y) const {
    if (y == row_y_) return;
    row_y_ = y;
    row_ = &tables_->ytile(y);
    row_t_ = (2.0 * y - row_->y0 - row_->y1) / (row_->y1 - row_->y0);
    row_have_.assign(row_have_.size(), 0);
  }
  void remainder(double u, double& fxx, double& fzz) const {
    const long m = row_->u.index(u);
    const auto mi = static_cast<std::size_t>(m);
    if (row_have_.size() <= mi) {
      row_have_.resize(mi + 1, 0);
      row_coef_.resize(mi + 1);
      row_tile_.resize(mi + 1, nullptr);
    }
    if (!row_have_[mi]) {
      const Tables::Tile& t = tables_->tile(*row_, m);
      row_tile_[mi] = &t;
      auto& c = row_coef_[mi];
      for (std::size_t i = 0; i < kNu; ++i) {
        c[i] = Chebyshev<kNy>::eval(&t.cxx[i], row_t_, kNu);
        c[kNu + i] = Chebyshev<kNy>::eval(&t.czz[i], row_t_, kNu);
      }
      row_have_[mi] = 1;
    }
    const Tables::Tile& t = *row_tile_[mi];
    const double tu = (2.0 * u - t.u0 - t.u1) / (t.u1 - t.u0);
    fxx = Chebyshev<kNu>::eval(row_coef_[mi].data(), tu);
    fzz = Chebyshev<kNu>::eval(row_coef_[mi].data() + kNu, tu);
  }

  double pz(std::size_t i) const { return pz_.empty() ? 0.0 : pz_[i]; }

  // The F tables at the current depth: each (u, v) tile's coefficients collapsed along y,
  // kept until the depth changes.
  struct FRow {
    const Tables::FTile* tile = nullptr;
    std::array<double, 3 * kNq * kNq> c{};  // F_xx's, F_zz's, F_xz's: [k * kNq + i]
  };
  void select_frow(double y) const {
    if (y == frow_y_) return;
    frow_y_ = y;
    frow_ = &tables_->ytile(y);
    frow_t_ = (2.0 * y - frow_->y0 - frow_->y1) / (frow_->y1 - frow_->y0);
    fslot_.clear();
    fpool_.clear();
  }
  // A pad's remainder along a fibre axis at offset (u, v), at the current depth.
  double f_along(double u, double v, bool vertical, double cc, double cs2, double ss) const {
    const double au = std::fabs(u), av = std::fabs(v);
    const long iu = frow_->fu.index(au), iv = frow_->fv.index(av);
    const auto su = static_cast<std::size_t>(iu), sv = static_cast<std::size_t>(iv);
    if (fslot_.size() <= su) fslot_.resize(su + 1);
    std::vector<std::size_t>& slots = fslot_[su];
    if (slots.size() <= sv) slots.resize(sv + 1, kNoSlot);
    constexpr std::size_t kAB = kNq * kNq;
    if (slots[sv] == kNoSlot) {
      const Tables::FTile& t = tables_->ftile(*frow_, iu, iv);
      FRow row;
      row.tile = &t;
      for (std::size_t ki = 0; ki < kAB; ++ki) {
        row.c[ki] = Chebyshev<kNy>::eval(&t.cxx[ki], frow_t_, kAB);
        row.c[kAB + ki] = Chebyshev<kNy>::eval(&t.czz[ki], frow_t_, kAB);
        row.c[2 * kAB + ki] = Chebyshev<kNy>::eval(&t.cxz[ki], frow_t_, kAB);
      }
      slots[sv] = fpool_.size();
      fpool_.push_back(row);
    }
    const FRow& row = fpool_[slots[sv]];
    const Tables::FTile& t = *row.tile;
    const double tu = (2.0 * au - t.u0 - t.u1) / (t.u1 - t.u0);
    const double tv = (2.0 * av - t.v0 - t.v1) / (t.v1 - t.v0);
    auto eval2 = [&](const double* c) { return cheb2(c, tu, tv); };
    if (vertical) return -(eval2(row.c.data()) + eval2(row.c.data() + kAB));  // F_yy
    double sum = 0.0;
    if (cc != 0.0) sum += cc * eval2(row.c.data());
    if (ss != 0.0) sum += ss * eval2(row.c.data() + kAB);
    if (cs2 != 0.0)
      sum += cs2 * ((u < 0.0) != (v < 0.0) ? -1.0 : 1.0) * eval2(row.c.data() + 2 * kAB);
    return sum;
  }

  std::vector<double> x_, pz_;  // pad centres (pz_: a 2-D array's, else empty)
  double z_;
  LayeredHalfSpace stack_;
  std::vector<std::unique_ptr<Conductor>> rect_;  // rect3d with rho = C_k, per layer
  std::shared_ptr<Tables> tables_;                // null when the stack is uniform
  mutable std::vector<double> scratch_;
  mutable double row_y_ = NAN;
  mutable const Tables::YTile* row_ = nullptr;
  mutable double row_t_ = 0.0;
  mutable std::vector<char> row_have_;
  mutable std::vector<std::array<double, 2 * kNu>> row_coef_;
  mutable std::vector<const Tables::Tile*> row_tile_;
  mutable double frow_y_ = NAN;
  mutable const Tables::YTile* frow_ = nullptr;
  mutable double frow_t_ = 0.0;
  static constexpr std::size_t kNoSlot = static_cast<std::size_t>(-1);
  mutable std::vector<std::vector<std::size_t>> fslot_;  // [iu][iv] -> fpool_ index, or kNoSlot
  mutable std::vector<FRow> fpool_;
};

}  // namespace

std::unique_ptr<Conductor> make_layered(const ElectrodeArray& array,
                                        const std::vector<Layer>& layers, double plane_z_mm) {
  return std::make_unique<Layered>(array, layers, plane_z_mm);
}

double layered_unit_zz(const Conductor& c, std::size_t i, double x_mm, double y_mm) {
  const auto* l = dynamic_cast<const Layered*>(&c);
  if (!l) failure("layered_unit_zz: not a layered conductor");
  return l->unit_zz(i, x_mm, y_mm);
}

}  // namespace tp
