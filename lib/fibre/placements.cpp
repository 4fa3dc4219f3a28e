// Where a receptor's fibres lie: the plan of placements, the fibres' checks (fibre_nodes),
// the fibres simulated and their potentials (placements.hpp).

#include "fibre/placements.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp::fibre {

double sampling_pitch_mm(const ElectrodeArray& a) {
  if (!a.two_d())
    return a.size() > 1 ? (a.x_max_mm() - a.x_min_mm()) / static_cast<double>(a.size() - 1) : 1.0;
  if (a.grid() && a.pitch_mm) {
    double p = *a.pitch_mm;
    if (a.rows > 1 && a.row_pitch_mm > 0) p = std::min(p, a.row_pitch_mm);
    if (a.columns == 1 && a.rows > 1) p = a.row_pitch_mm;
    return p;
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j)
      best =
          std::min(best, std::hypot(a.positions_mm[i] - a.positions_mm[j], a.z_mm[i] - a.z_mm[j]));
  return std::isfinite(best) ? best : 1.0;
}

bool is_afferent(const Receptor& r, const ThresholdSettings& s) {
  return s.geometry == Geometry::afferent && r.fibre.orientation == Orientation::vertical;
}

std::vector<int> afferent_directions(const ThresholdSettings& s) {
  if (s.fixed_direction) return {*s.fixed_direction};
  return {-1, 1};
}

double default_extension_mm(const Setup& setup, double internode_mm) {
  return setup.lateral_margin_mm + 5.0 * internode_mm;
}

std::array<double, 2> horizontal_span_mm(const Setup& setup, const Receptor& r,
                                         const ThresholdSettings& s, double internode_mm) {
  const Region g = fibre_region(setup, r);
  const double e = default_extension_mm(setup, internode_mm);
  return {g.x0_mm - 5.0 * internode_mm - (s.reach.minus_x - 1.0) * e,
          g.x1_mm + 5.0 * internode_mm + (s.reach.plus_x - 1.0) * e};
}

std::size_t below_internodes(const ThresholdSettings& s) {
  return static_cast<std::size_t>(
      std::llround(static_cast<double>(s.extra_internodes) * s.reach.below));
}

// ---- The plan ----

namespace {
// A vertical_across refinement: 9 placements, a quarter of the step before apart.
constexpr std::size_t kAcrossRefinement = 8;  // intervals
// vertical_around: 5 x 5 in every round.
constexpr int kAroundHalf = 2;
}  // namespace

PlacementPlan::PlacementPlan(const Setup& setup, const Receptor& r, const ThresholdSettings& s,
                             double internode_mm)
    : internode_mm_(internode_mm), top_mm_(r.depth_min_mm), bottom_mm_(r.depth_max_mm) {
  const bool vertical = r.fibre.orientation == Orientation::vertical;
  const bool two_d = setup.array.two_d();
  z_mm_ = two_d ? (*s.through_mm)[1] : 0.0;
  if (is_afferent(r, s)) fibres_ = afferent_directions(s).size();
  if (!vertical) {
    left_mm_ = horizontal_span_mm(setup, r, s, internode_mm)[0];
    if (s.fixed_offset_mm) {
      kind_ = Kind::one_horizontal;
      fixed_ = *s.fixed_offset_mm;
    } else {
      kind_ = Kind::horizontal;
      depths_ = r.depth_max_mm > r.depth_min_mm ? 5 : 1;
      offsets_ = s.offsets;
    }
    return;
  }
  pitch_mm_ = sampling_pitch_mm(setup.array);
  if (s.fixed_x_mm) {
    kind_ = Kind::one_vertical;
    fixed_ = *s.fixed_x_mm;
  } else if (two_d) {
    kind_ = Kind::vertical_around;
    x_mm_ = (*s.through_mm)[0];
  } else {
    kind_ = Kind::vertical_across;
    from_mm_ = setup.array.x_min_mm() - pitch_mm_;
    to_mm_ = setup.array.x_max_mm() + pitch_mm_;
  }
}

std::size_t PlacementPlan::across_intervals() const {
  return static_cast<std::size_t>(std::llround((to_mm_ - from_mm_) / (pitch_mm_ / 4)));
}

std::size_t PlacementPlan::round_size(std::size_t k) const {
  if (k >= rounds()) return 0;
  switch (kind_) {
    case Kind::one_horizontal:
    case Kind::one_vertical:
      return 1;
    case Kind::horizontal:
      return depths_ * offsets_;
    case Kind::vertical_across:
      return (k == 0 ? across_intervals() : kAcrossRefinement) + 1;
    case Kind::vertical_around:
      return (2 * kAroundHalf + 1) * (2 * kAroundHalf + 1);
  }
  return 0;
}

std::size_t PlacementPlan::count() const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < rounds(); ++k) n += round_size(k);
  return n;
}

std::vector<Spot> PlacementPlan::round(std::size_t k, const Spot& best) const {
  std::vector<Spot> out;
  if (k >= rounds()) return out;
  out.reserve(round_size(k));
  const double L = internode_mm_;
  // A horizontal fibre's first node: a node at offset + m L, the first at or before left.
  auto horizontal = [&](double offset, double y) {
    out.push_back({0, offset + L * std::floor((left_mm_ - offset) / L), y, z_mm_, offset});
  };
  auto vertical = [&](double x, double z) { out.push_back({0, x, top_mm_, z, 0.0}); };
  switch (kind_) {
    case Kind::one_horizontal:
      horizontal(fixed_, top_mm_);
      break;
    case Kind::one_vertical:
      vertical(fixed_, z_mm_);
      break;
    case Kind::horizontal:
      for (std::size_t d = 0; d < depths_; ++d) {
        const double y = depths_ == 1 ? top_mm_
                                      : top_mm_ + (bottom_mm_ - top_mm_) * static_cast<double>(d) /
                                                      static_cast<double>(depths_ - 1);
        for (std::size_t q = 0; q < offsets_; ++q)
          horizontal(L * static_cast<double>(q) / static_cast<double>(offsets_), y);
      }
      break;
    case Kind::vertical_across: {
      // Round 0 from the span's start; refinement k from the best less the step before.
      double step = pitch_mm_ / 4, from = from_mm_;
      std::size_t intervals = across_intervals();
      for (std::size_t r = 1; r <= k; ++r) {
        from = best.x0_mm - step;
        step /= 4;
        intervals = kAcrossRefinement;
      }
      for (std::size_t i = 0; i <= intervals; ++i)
        vertical(from + step * static_cast<double>(i), 0.0);
      break;
    }
    case Kind::vertical_around: {
      double step = pitch_mm_ / 4, cx = x_mm_, cz = z_mm_;
      if (k > 0) {
        cx = best.x0_mm;
        cz = best.z0_mm;
        for (std::size_t r = 1; r <= k; ++r) step /= 2;
      }
      for (int jz = -kAroundHalf; jz <= kAroundHalf; ++jz)
        for (int ix = -kAroundHalf; ix <= kAroundHalf; ++ix)
          vertical(cx + step * ix, cz + step * jz);
      break;
    }
  }
  return out;
}

// ---- The fibres and their checks (fibre_nodes) ----

namespace {

constexpr std::size_t kMaxNodes = 2000;  // a 2 um MRG fibre 400 mm long
constexpr double kMaxPotentials = 3e7;   // 240 MB of unit potentials

// The x of every ending an afferent search tries: a population's one; under a 2-D array
// within a pitch of the point; else across the pads, a pitch and a half beyond each side
// (the search's first round reaches one pitch, its refinements a third of one more).
std::array<double, 2> ending_range_mm(const Setup& setup, const ThresholdSettings& s) {
  if (s.fixed_x_mm) return {*s.fixed_x_mm, *s.fixed_x_mm};
  const double p = sampling_pitch_mm(setup.array);
  if (setup.array.two_d()) return {(*s.through_mm)[0] - p, (*s.through_mm)[0] + p};
  return {setup.array.x_min_mm() - 1.5 * p, setup.array.x_max_mm() + 1.5 * p};
}

// An afferent's stem, from the bend: from the farthest ending it serves, past the far side
// of the pads plus the lateral margin (where horizontal fibres end) by five internodes, and
// by (reach - 1) default extensions more.
double afferent_stem_mm(const Setup& setup, const ThresholdSettings& s, double L_mm,
                        int direction) {
  const auto [lo, hi] = ending_range_mm(setup, s);
  const double m = setup.lateral_margin_mm;
  const double span =
      direction < 0 ? hi - (setup.array.x_min_mm() - m) : (setup.array.x_max_mm() + m) - lo;
  const double reach = direction < 0 ? s.reach.minus_x : s.reach.plus_x;
  return std::max(span, 0.0) + 5.0 * L_mm + (reach - 1.0) * default_extension_mm(setup, L_mm);
}

}  // namespace

Axon afferent_for(const FibreModel& model, const Setup& setup, const Receptor& r,
                  const ThresholdSettings& s, int direction) {
  const double d = r.fibre.diameter_um;
  return afferent_axon(model, d, r.depth_max_mm - r.depth_min_mm, direction,
                       afferent_stem_mm(setup, s, model.internode_um(d) * 1e-3, direction),
                       s.shape);
}

namespace {

// Under a 2-D array: the point the fibres pass through is given, within the pads plus the
// lateral margin.
void check_through_point(const Setup& setup, const ThresholdSettings& s) {
  if (!setup.array.two_d()) return;
  if (!s.through_mm)
    bad_input("array: " + setup.array.describe() +
              " is 2-D: give the point the fibres pass through (fiber-threshold --at X,Z; a "
              "pixel's document, optimize-weights --at, carries its focus)");
  const auto [px, pz] = *s.through_mm;
  const double m = setup.lateral_margin_mm;
  if (!(px >= setup.array.x_min_mm() - m && px <= setup.array.x_max_mm() + m &&
        pz >= setup.array.z_min_mm() - m && pz <= setup.array.z_max_mm() + m))
    bad_input("--at: (" + number_text(px) + ", " + number_text(pz) +
              ") mm is outside the pads plus the lateral margin (" + number_text(m) + " mm)");
}

// The fibre model can represent the receptor's fibre.
void check_fibre_kind(const FibreModel& model, const Receptor& r) {
  const double d = r.fibre.diameter_um;
  if (!r.fibre.myelinated)
    bad_input("receptor " + r.name + ": the fibre models are myelinated (myelinated: false)");
  if (d < model.min_diameter_um() || d > model.max_diameter_um())
    bad_input("receptor " + r.name + ": diameter " +
              number_beside(d, model.min_diameter_um(), model.max_diameter_um()) + " um outside " +
              model.name() + "'s range [" + number_text(model.min_diameter_um()) + ", " +
              number_text(model.max_diameter_um()) + "] um");
}

// What fibre_nodes' checks share: the receptor's fibre and where the plan puts it.
struct FibreShape {
  double L_mm;
  bool vertical, afferent, two_d;
  Region region;
  std::vector<Axon> stems;  // an afferent's two, built once: node counts and far ends
  std::size_t nodes;
};

FibreShape fibre_shape(const FibreModel& model, const Setup& setup, const Receptor& r,
                       const ThresholdSettings& s) {
  FibreShape f;
  f.L_mm = model.internode_um(r.fibre.diameter_um) * 1e-3;
  f.vertical = r.fibre.orientation == Orientation::vertical;
  f.two_d = setup.array.two_d();
  f.region = fibre_region(setup, r);
  if (s.fixed_direction && *s.fixed_direction != 1 && *s.fixed_direction != -1)
    bad_input("an afferent's stem direction must be -1 or +1");
  f.afferent = is_afferent(r, s);
  if (f.afferent)
    for (int dir : {-1, 1}) f.stems.push_back(afferent_for(model, setup, r, s, dir));
  if (f.afferent) {
    f.nodes = std::max(f.stems[0].nodes.size(), f.stems[1].nodes.size());
  } else if (f.vertical) {
    f.nodes =
        static_cast<std::size_t>(std::ceil((r.depth_max_mm - r.depth_min_mm) / f.L_mm - 1e-9)) +
        below_internodes(s) + 1;
  } else {  // the region, five internodes each side and the reach's extensions beyond
    const double more =
        (s.reach.minus_x + s.reach.plus_x - 2.0) * default_extension_mm(setup, f.L_mm);
    f.nodes = static_cast<std::size_t>(
                  std::ceil((f.region.x1_mm - f.region.x0_mm + more) / f.L_mm - 1e-9)) +
              12;
  }
  if (f.nodes < 12) f.nodes = 12;
  return f;
}

// A buried point source (Conductor::buried_source_depth_mm) on or near a fibre's path: the
// potential is singular there, and within an internode of the path the compartments do not
// resolve it.  The fibre occupies the depths [top, bottom] (a vertical one down to its deep
// end, the internodes below the receptor included) at every x across the array, in the
// plane z = plane_z_mm (under a 2-D array: at the point's z); the sources lie at depth d
// under each pad.
void check_source_clearance(const Setup& setup, const Conductor& conductor, const Receptor& r,
                            const ThresholdSettings& s, const FibreShape& f) {
  const double src = conductor.buried_source_depth_mm();
  if (!(src > 0.0)) return;
  const double top = r.depth_min_mm;
  const double bottom = f.vertical && !f.afferent
                            ? r.depth_min_mm + static_cast<double>(f.nodes - 1) * f.L_mm
                            : r.depth_max_mm;
  const double gap = src < top ? top - src : src > bottom ? src - bottom : 0.0;
  double dz = setup.conductor.plane_z_mm;
  if (f.two_d) {  // the nearest pad's source, from the fibres' z
    dz = std::numeric_limits<double>::infinity();
    for (std::size_t e = 0; e < setup.array.size(); ++e)
      dz = std::min(dz, std::fabs((*s.through_mm)[1] - setup.array.z_of(e)));
  }
  const double distance = std::hypot(gap, dz);
  if (!(distance >= f.L_mm))
    bad_input("model.source_depth_mm: " + number_text(src) + " mm is " +
              number_beside(distance, f.L_mm) + " mm from receptor " + r.name + "'s " +
              (f.vertical ? "vertical" : "horizontal") + " fibre (depths " + number_text(top) +
              " to " + number_text(bottom) + " mm), less than one internode (" +
              number_text(f.L_mm) + " mm): the source would be on or too near its path");
}

// Bounded work and memory: a fibre of at most kMaxNodes nodes, and the unit potentials of
// all its placements (compartments x electrodes x the plan's placements over its fibres)
// at most kMaxPotentials.
void check_size(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                const Receptor& r, const ThresholdSettings& s, const FibreShape& f) {
  if (f.nodes > kMaxNodes)
    bad_input("receptor " + r.name + ": its fibre would need " + std::to_string(f.nodes) +
              " nodes (at most " + std::to_string(kMaxNodes) + "): the array and margins span " +
              number_text(f.vertical ? r.depth_max_mm - r.depth_min_mm
                                     : f.region.x1_mm - f.region.x0_mm) +
              " mm at " + number_text(f.L_mm) + " mm per internode");
  const double compartments =
      static_cast<double>(f.nodes) *
      static_cast<double>(model.axon(r.fibre.diameter_um, 2).compartments.size() - 1);
  const double per_placement = compartments * static_cast<double>(conductor.size());
  const PlacementPlan plan(setup, r, s, f.L_mm);
  const double placements = static_cast<double>(plan.count() * plan.fibres());
  if (per_placement * placements > kMaxPotentials)
    bad_input("receptor " + r.name + ": " + number_text(per_placement * placements) +
              " unit potentials to keep (at most " + number_text(kMaxPotentials) +
              "): fewer electrodes, a shorter array or fewer --offsets");
}

// Every compartment's potential can be evaluated (the layered model's Hankel rule is
// bounded far from the electrodes, for shallow fibres): the farthest any placement's
// compartment lies from an electrode, over the depths the fibre occupies.  Horizontal: the
// first node within six internodes before the region, the fibre at most `nodes` internodes
// long; vertical: across the array +- one pitch, refined by at most a quarter and a
// sixteenth of a pitch beyond.
void check_simulated_reach(const Setup& setup, const Conductor& conductor, const Receptor& r,
                           const ThresholdSettings& s, const FibreShape& f) {
  const double x_min = setup.array.x_min_mm(), x_max = setup.array.x_max_mm();
  const double pitch_mm = sampling_pitch_mm(setup.array);
  // Under a 2-D array, the farthest in z from the fibres' z widened by `by` each side.
  auto with_z = [&](double reach_mm, double by) {
    const double pz = (*s.through_mm)[1];
    return std::hypot(reach_mm, std::max(std::fabs(pz + by - setup.array.z_min_mm()),
                                         std::fabs(setup.array.z_max_mm() - (pz - by))));
  };
  double reach_mm, bottom_mm;
  if (f.afferent) {  // either stem's far end, as built, from the farthest pad
    const auto [lo, hi] = ending_range_mm(setup, s);
    reach_mm = std::max(x_max - lo, hi - x_min);
    for (const Axon& a : f.stems) {
      const double back = a.path_x_mm.back();
      for (double tip : {lo, hi})
        reach_mm =
            std::max({reach_mm, std::fabs(tip + back - x_min), std::fabs(tip + back - x_max)});
    }
    if (f.two_d) reach_mm = with_z(reach_mm, pitch_mm);
    bottom_mm = r.depth_max_mm;
  } else if (f.vertical && f.two_d) {  // within half a pitch of the point, refined beyond
    const double px = (*s.through_mm)[0];
    const double dx =
        std::max(std::fabs(px + pitch_mm - x_min), std::fabs(x_max - (px - pitch_mm)));
    reach_mm = with_z(dx, pitch_mm);
    bottom_mm = r.depth_min_mm + static_cast<double>(f.nodes) * f.L_mm;
  } else if (f.vertical) {
    reach_mm = x_max - x_min + 1.5 * pitch_mm;
    bottom_mm = r.depth_min_mm + static_cast<double>(f.nodes) * f.L_mm;
  } else {
    const double first_mm = horizontal_span_mm(setup, r, s, f.L_mm)[0] - f.L_mm;
    const double last_mm = first_mm + static_cast<double>(f.nodes + 1) * f.L_mm;
    reach_mm = std::max(std::fabs(last_mm - x_min), std::fabs(x_max - first_mm));
    if (f.two_d) reach_mm = with_z(reach_mm, 0.0);
    bottom_mm = r.depth_max_mm;
  }
  conductor.check_reach(reach_mm, r.depth_min_mm, bottom_mm,
                        "receptor " + r.name + "'s simulated fibre");
}

}  // namespace

std::size_t fibre_nodes(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                        const Receptor& r, const ThresholdSettings& s) {
  check_through_point(setup, s);
  check_fibre_kind(model, r);
  const FibreShape f = fibre_shape(model, setup, r, s);
  check_source_clearance(setup, conductor, r, s, f);
  check_size(model, setup, conductor, r, s, f);
  check_simulated_reach(setup, conductor, r, s, f);
  return f.nodes;
}

FibreRun fibre_run(const FibreModel& model, const Setup& setup, const Conductor& conductor,
                   const Receptor& r, const Waveform& waveform, const ThresholdSettings& s) {
  const double d = r.fibre.diameter_um;
  const std::size_t nodes = fibre_nodes(model, setup, conductor, r, s);
  FibreRun f{nodes, model.internode_um(d) * 1e-3, 0.0, {}, {0}};
  if (is_afferent(r, s)) {
    f.directions = afferent_directions(s);
    for (int dir : f.directions) f.axons.push_back(afferent_for(model, setup, r, s, dir));
  } else {
    f.axons.push_back(model.axon(d, nodes));
  }
  double length_mm = 0.0;  // the longest fibre's: one end time for every direction
  for (const Axon& a : f.axons) length_mm = std::max(length_mm, a.length_um() * 1e-3);
  const double after = s.after_ms > 0 ? s.after_ms : 1.0 + length_mm / (2.0 * d);
  f.tstop_ms = waveform.end_ms() + after;
  return f;
}

// ---- Potentials ----

std::vector<double> potentials_mV(const Conductor& c, const std::vector<double>& weights,
                                  const Axon& axon, double x0, double y0, bool vertical, double z0,
                                  bool three_d, PotentialCache& cache) {
  const std::vector<double>& psi = cache.unit(c, axon, x0, y0, vertical, z0, three_d);
  const std::size_t n = weights.size();
  std::vector<double> ve(axon.centre_um.size());
  for (std::size_t k = 0; k < ve.size(); ++k) {
    double v = 0.0;
    for (std::size_t i = 0; i < n; ++i) v += weights[i] * psi[k * n + i];
    ve[k] = 1e3 * v;  // V -> mV
  }
  return ve;
}

bool PotentialCache::Key::operator<(const Key& o) const {
  return std::tie(model, path, diameter_um, x0_mm, y0_mm, z0_mm, compartments, vertical, three_d) <
         std::tie(o.model, o.path, o.diameter_um, o.x0_mm, o.y0_mm, o.z0_mm, o.compartments,
                  o.vertical, o.three_d);
}

const std::vector<double>& PotentialCache::unit(const Conductor& c, const Axon& axon, double x0,
                                                double y0, bool vertical, double z0, bool three_d) {
  if (!three_d) z0 = 0.0;
  Key key{axon.model, axon.path, axon.diameter_um, x0, y0, z0, axon.centre_um.size(),
          vertical,   three_d};
  auto it = std::lower_bound(entries_.begin(), entries_.end(), key,
                             [](const auto& e, const Key& k) { return e.first < k; });
  if (it != entries_.end() && !(key < it->first)) return it->second;
  const std::size_t n = c.size();
  std::vector<double> psi(axon.centre_um.size() * n);
  // Bounded: past kMaxCached values the cache starts again (callers hold no references).
  stored_ += psi.size();
  if (stored_ > kMaxCached) {
    entries_.clear();
    stored_ = psi.size();
    it = entries_.end();
  }
  for (std::size_t k = 0; k < axon.centre_um.size(); ++k) {
    const double s = axon.centre_um[k] * 1e-3;
    double x = vertical ? x0 : x0 + s, y = vertical ? y0 + s : y0;
    if (!axon.path.empty()) {  // laid along a path from (x0, y0)
      x = x0 + axon.path_x_mm[k];
      y = y0 + axon.path_y_mm[k];
    }
    if (three_d)
      c.unit_potentials_3d(x, y, z0, &psi[k * n]);
    else
      c.unit_potentials(x, y, &psi[k * n]);
  }
  return entries_.insert(it, {std::move(key), std::move(psi)})->second;
}

}  // namespace tp::fibre
