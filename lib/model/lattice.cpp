#include "model/lattice.hpp"

#include <cmath>
#include <list>
#include <mutex>
#include <string>

#include "model/field.hpp"

namespace tp {

std::optional<GridLattice> grid_lattice(const ElectrodeArray& arr, double x0_mm, double x1_mm,
                                        double z0_mm, double z1_mm, double step_mm) {
  if (!arr.grid() || !(step_mm > 0.0)) return std::nullopt;
  const double pitch = *arr.pitch_mm, row_pitch = arr.row_pitch_mm;
  const double m = std::ceil(pitch / step_mm - 1e-9), mz = std::ceil(row_pitch / step_mm - 1e-9);
  GridLattice g;
  g.hx = pitch / m;
  g.hz = row_pitch / mz;
  g.x00 = arr.positions_mm.front();
  g.z00 = arr.z_mm.front();
  const double a0 = std::ceil((x0_mm - g.x00) / g.hx - 1e-9);
  const double a1 = std::floor((x1_mm - g.x00) / g.hx + 1e-9);
  const double b0 = std::ceil((z0_mm - g.z00) / g.hz - 1e-9);
  const double b1 = std::floor((z1_mm - g.z00) / g.hz + 1e-9);
  const double oa = a0 - (arr.columns - 1) * m, ob = b0 - (arr.rows - 1) * mz;
  // Counted in floating point: a count beyond int's range is never converted.
  const double points = (a1 - a0 + 1) * (b1 - b0 + 1);
  const double entries = (a1 - oa + 1) * (b1 - ob + 1);
  if (!(a1 >= a0 && b1 >= b0 && points <= kMaxSamples &&
        entries <= points * static_cast<double>(arr.size()) && entries <= kMaxSamples))
    return std::nullopt;
  g.m = static_cast<int>(m);
  g.mz = static_cast<int>(mz);
  g.a0 = static_cast<int>(a0);
  g.a1 = static_cast<int>(a1);
  g.b0 = static_cast<int>(b0);
  g.b1 = static_cast<int>(b1);
  g.x0_off = x0_mm < g.x(g.a0) - 1e-9 * g.hx;
  g.x1_off = x1_mm > g.x(g.a1) + 1e-9 * g.hx;
  g.z0_off = z0_mm < g.z(g.b0) - 1e-9 * g.hz;
  g.z1_off = z1_mm > g.z(g.b1) + 1e-9 * g.hz;
  return g;
}

namespace {

// AmplitudeLattice lines origin + i step for i in [i0, i1], with the ends lo, hi when off them.
std::vector<double> axis(double lo, double hi, bool lo_off, bool hi_off, double origin, double step,
                         int i0, int i1) {
  std::vector<double> v;
  if (lo_off) v.push_back(lo);
  for (int i = i0; i <= i1; ++i) v.push_back(origin + i * step);
  if (hi_off) v.push_back(hi);
  return v;
}

}  // namespace

std::vector<double> GridLattice::x_axis(double x0_mm, double x1_mm) const {
  return axis(x0_mm, x1_mm, x0_off, x1_off, x00, hx, a0, a1);
}

std::vector<double> GridLattice::z_axis(double z0_mm, double z1_mm) const {
  return axis(z0_mm, z1_mm, z0_off, z1_off, z00, hz, b0, b1);
}

namespace {

PadTable build_table(const ConductorParams& params, const ElectrodeArray& arr, const GridLattice& g,
                     double y_mm, const FibreAxis& axis) {
  PadTable t;
  t.oa = g.a0 - (arr.columns - 1) * g.m;
  t.ob = g.b0 - (arr.rows - 1) * g.mz;
  t.na = g.a1 - t.oa + 1;
  t.nb = g.b1 - t.ob + 1;
  const ElectrodeArray lone = ElectrodeArray::pads({0.0}, {0.0}, arr.width_mm, arr.length_mm);
  const auto c = make_conductor(params, lone);
  t.k.resize(static_cast<std::size_t>(t.na) * static_cast<std::size_t>(t.nb));
  for (int b = 0; b < t.nb; ++b)
    for (int a = 0; a < t.na; ++a)
      c->unit_d2_along((t.oa + a) * g.hx, y_mm, (t.ob + b) * g.hz, axis,
                       &t.k[static_cast<std::size_t>(b) * static_cast<std::size_t>(t.na) +
                            static_cast<std::size_t>(a)]);
  return t;
}

}  // namespace

namespace {

// Everything a lone pad's response depends on besides the points: the model's settings and
// the pad.
std::vector<double> conductor_key(const ConductorParams& params, const ElectrodeArray& arr) {
  std::vector<double> key = {params.resistivity_ohm_m, params.source_depth_mm, arr.width_mm,
                             arr.length_mm};
  key.push_back(static_cast<double>(params.skin.layers.size()));  // then what follows
  for (const Layer& l : params.skin.layers) {
    key.push_back(l.thickness_mm);
    key.push_back(l.resistivity_ohm_m);
  }
  return key;
}

// The tables of one kind, kept for the process (most recent first, up to 2e7 entries of
// the kind), shared between threads.  A table depends only on its key, so keeping it
// changes no value (two threads may build the same one at once: both are the same).
template <class Table, class Build>
std::shared_ptr<const Table> kept(const std::string& model, std::vector<double> key,
                                  Build&& build) {
  struct Entry {
    std::string model;
    std::vector<double> key;
    std::shared_ptr<const Table> table;
  };
  static std::mutex mutex;
  static std::list<Entry> cache;
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (auto it = cache.begin(); it != cache.end(); ++it)
      if (it->model == model && it->key == key) {
        cache.splice(cache.begin(), cache, it);
        return cache.front().table;
      }
  }
  auto table = std::make_shared<const Table>(build());
  std::lock_guard<std::mutex> lock(mutex);
  cache.push_front({model, std::move(key), table});
  constexpr std::size_t kBudget = 20000000;  // entries kept in all
  std::size_t total = 0;
  for (auto it = cache.begin(); it != cache.end();) {
    total += it->table->k.size();
    if (total > kBudget && it != cache.begin())
      it = cache.erase(it);
    else
      ++it;
  }
  return table;
}

}  // namespace

std::shared_ptr<const PadTable> pad_table(const ConductorParams& params, const ElectrodeArray& arr,
                                          const GridLattice& g, double y_mm,
                                          const FibreAxis& axis) {
  std::vector<double> key = conductor_key(params, arr);
  key.insert(key.end(), {g.hx, g.hz, static_cast<double>(g.a0 - (arr.columns - 1) * g.m),
                         static_cast<double>(g.b0 - (arr.rows - 1) * g.mz),
                         static_cast<double>(g.a1), static_cast<double>(g.b1), y_mm,
                         axis.vertical ? 1.0 : 0.0, axis.cos_az, axis.sin_az});
  return kept<PadTable>(params.model, std::move(key),
                        [&] { return build_table(params, arr, g, y_mm, axis); });
}

std::shared_ptr<const WallTable> wall_table(const ConductorParams& params,
                                            const ElectrodeArray& arr, const GridLattice& g,
                                            bool along_x, double fixed_mm,
                                            const std::vector<double>& ys, const FibreAxis& axis) {
  WallTable t;
  t.along_x = along_x;
  t.o = along_x ? g.a0 - (arr.columns - 1) * g.m : g.b0 - (arr.rows - 1) * g.mz;
  t.n = (along_x ? g.a1 : g.b1) - t.o + 1;
  t.lines = along_x ? arr.rows : arr.columns;
  const double entries = static_cast<double>(ys.size()) * t.lines * t.n;
  if (!(entries <= kMaxSamples)) return nullptr;
  std::vector<double> key = conductor_key(params, arr);
  key.insert(key.end(),
             {along_x ? 1.0 : 0.0, fixed_mm, g.hx, g.hz, g.x00, g.z00, static_cast<double>(g.m),
              static_cast<double>(g.mz), static_cast<double>(t.o), static_cast<double>(t.n),
              static_cast<double>(t.lines), axis.vertical ? 1.0 : 0.0, axis.cos_az, axis.sin_az});
  key.push_back(static_cast<double>(ys.size()));
  key.insert(key.end(), ys.begin(), ys.end());
  return kept<WallTable>(params.model, std::move(key), [&] {
    WallTable w = t;  // (no entries yet: a cheap copy, returned without one)
    const ElectrodeArray lone = ElectrodeArray::pads({0.0}, {0.0}, arr.width_mm, arr.length_mm);
    const auto c = make_conductor(params, lone);
    w.k.resize(static_cast<std::size_t>(entries));
    std::size_t e = 0;
    for (const double y : ys)
      for (int line = 0; line < w.lines; ++line) {
        // The wall's distance from the line of pads, across it.
        const double across = along_x ? fixed_mm - g.z(line * g.mz) : fixed_mm - g.x(line * g.m);
        for (int i = 0; i < w.n; ++i) {
          const double along = (w.o + i) * (along_x ? g.hx : g.hz);
          if (along_x)
            c->unit_d2_along(along, y, across, axis, &w.k[e++]);
          else
            c->unit_d2_along(across, y, along, axis, &w.k[e++]);
        }
      }
    return w;
  });
}

}  // namespace tp
