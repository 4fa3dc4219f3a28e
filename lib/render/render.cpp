#include "render/render.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numeric>
#include <tuple>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "device/device_core.hpp"
#include "device/scheduler.hpp"
#include "io/number.hpp"
#include "model/field.hpp"

namespace tp {

namespace {

// "pixel (c, r)": pad r x columns + c as the image's column and row.
std::string pixel_text(long pad, int columns) {
  return "pixel (" + std::to_string(pad % columns) + ", " + std::to_string(pad / columns) + ")";
}

double get_finite(const Json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) bad_input(where + ": no " + key);
  return json_finite(j[key], where + "." + key);
}

}  // namespace

PixelBank pixel_bank_from_json(const Json& j) {
  if (!j.is_object() || !j.contains("bank") || !j.contains("pixels") || !j["pixels"].is_array())
    bad_input("bank: not a bank of pixels (optimize-weights --bank)");
  PixelBank b;
  b.doc = document_from_json(j);
  const ElectrodeArray& a = b.doc.setup.array;
  if (!a.grid()) bad_input("bank: its array is " + a.describe() + ", not a grid of pads");
  b.columns = a.columns;
  b.rows = a.rows;
  b.pad_area_mm2 = a.width_mm * a.length_mm;
  const Json& px = j["pixels"];
  if (px.size() != a.size())
    bad_input("bank: " + count_text(px.size(), "pixel") + " for " + count_text(a.size(), "pad") +
              " (render-tactile needs every pad's pixel: a bank without --at)");
  b.entry.resize(a.size());
  for (std::size_t k = 0; k < px.size(); ++k) {
    const Json& p = px[k];
    const std::string where = "bank: pixels[" + std::to_string(k) + "]";
    const double x = get_finite(p, "x_mm", where), z = get_finite(p, "z_mm", where);
    if (!p.contains("pad") || !p["pad"].is_number_integer() ||
        p["pad"].get<long>() != static_cast<long>(k) || std::abs(x - a.positions_mm[k]) > 1e-6 ||
        std::abs(z - a.z_mm[k]) > 1e-6)
      bad_input(where + ": not pad " + std::to_string(k) + "'s centre");
    if (!p.contains("patterns") || !p["patterns"].is_object()) bad_input(where + ": no patterns");
    for (std::size_t m = 0; m < kPrimaries.size(); ++m) {
      if (!p["patterns"].contains(kPrimaries[m])) continue;
      const Json& e = p["patterns"][kPrimaries[m]];
      const std::string w = where + ".patterns." + kPrimaries[m];
      BankEntry& out = b.entry[k][m];
      out.present = true;
      if (e.is_object() && e.contains("feasible") && !e["feasible"].is_boolean())
        bad_input(w + ".feasible: not true or false");
      if (e.is_object() && e.contains("feasible") && e["feasible"] == false) {
        out.reason = e.contains("reason") && e["reason"].is_string()
                         ? e["reason"].get<std::string>()
                         : "no pattern";
        continue;
      }
      out.feasible = true;
      if (!e.is_object() || !e.contains("weights") || !e["weights"].is_array() ||
          e["weights"].size() != a.size())
        bad_input(w + ".weights: expected " + std::to_string(a.size()) + " values, one per pad");
      double peak = 0;
      for (std::size_t i = 0; i < a.size(); ++i) {
        const double v = json_finite(e["weights"][i], w + ".weights");
        if (std::abs(v) > 1 + 1e-9) bad_input(w + ".weights: |w| above 1");
        peak = std::max(peak, std::abs(v));
        out.weights.push_back(v);
      }
      if (!(peak > 0)) bad_input(w + ".weights: all zero");
      if (!e.contains("peak")) bad_input(w + ": no peak");
      out.peak_x_mm = get_finite(e["peak"], "x_mm", w + ".peak");
      out.peak_y_mm = get_finite(e["peak"], "y_mm", w + ".peak");
      out.peak_z_mm = get_finite(e["peak"], "z_mm", w + ".peak");
      receptor_index(b.doc.setup, kPrimaries[m]);  // the bank's receptors name it
    }
  }
  return b;
}

namespace {
std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    const std::size_t end = std::min(text.find(',', at), text.size());
    out.push_back(text.substr(at, end - at));
    if (end == text.size()) return out;
    at = end + 1;
  }
}
}  // namespace

void parse_rates(const std::string& text, std::array<double, 3>& rate) {
  std::array<bool, 3> given{};
  for (const std::string& item : split_commas(text)) {
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos)
      bad_input("--rates: '" + item + "' is not PRIMARY:HZ (e.g. SAI:200)");
    const std::string name = item.substr(0, colon);
    const auto p = static_cast<std::size_t>(primary_index(name, "--rates"));
    if (given[p]) bad_input("--rates: " + name + " given twice (" + text + "): give each once");
    given[p] = true;
    rate[p] = parse_finite(item.substr(colon + 1), "--rates");
  }
}

std::vector<int> parse_primaries(const std::string& text, const std::string& what) {
  std::vector<int> out;
  for (const std::string& item : split_commas(text)) {
    const int p = primary_index(item, what);
    if (std::find(out.begin(), out.end(), p) != out.end())
      bad_input(what + ": " + item + " given twice");
    out.push_back(p);
  }
  return out;
}

void check_render_options(const RenderOptions& o) {
  const StimulusLimits& l = o.limits;
  for (std::size_t p = 0; p < 3; ++p)
    if (!(o.rate_hz[p] >= l.min_frequency_hz && o.rate_hz[p] <= l.max_frequency_hz))
      bad_input(std::string("--rates: ") + kPrimaries[p] + " " +
                number_beside(o.rate_hz[p], l.min_frequency_hz, l.max_frequency_hz) +
                " Hz outside [" + number_text(l.min_frequency_hz) + ", " +
                number_text(l.max_frequency_hz) + "] Hz");
  auto whole = [](double v, double lo, double hi, const char* name) {
    if (!(v >= lo && v <= hi && v == std::floor(v)))
      bad_input(std::string(name) + ": " + number_beside(v, lo, hi) +
                " us is not a whole number in [" + number_text(lo) + ", " + number_text(hi) +
                "] us");
  };
  whole(o.width_us, l.min_width_us, l.max_width_us, "--width");
  whole(o.interphase_us, 0, 1000, "--interphase");
  whole(o.balance_width_us, o.width_us, l.max_balance_width_us, "--balance-width");
  whole(o.gap_us, l.min_gap_us, l.max_slip_us, "--gap");
  if (!(o.crosstalk >= 0 && o.crosstalk <= 1))
    bad_input("--crosstalk: " + number_beside(o.crosstalk, 0, 1) + " outside [0, 1]");
  if (!(o.duration_s > 0 && o.duration_s <= l.max_duration_s))
    bad_input("--duration: " + number_beside(o.duration_s, 0, l.max_duration_s) +
              " s outside (0, " + number_text(l.max_duration_s) + "] s");
}

namespace {

// The fields of the lit patterns, built once.
struct PatternFields {
  const PixelBank& bank;
  const std::vector<LitPattern>& lit;
  std::vector<std::unique_ptr<Field>> field;
  std::vector<double> own;  // each pattern's AF at its own peak (weights, max |w| = 1)
  PatternFields(const PixelBank& b, const std::vector<LitPattern>& l) : bank(b), lit(l) {
    for (const LitPattern& p : lit) {
      const BankEntry& e =
          bank.entry[static_cast<std::size_t>(p.pad)][static_cast<std::size_t>(p.primary)];
      field.push_back(std::make_unique<Field>(bank.doc.setup, e.weights));
      own.push_back(af(field.size() - 1, field.size() - 1));
    }
  }
  // AF of pattern a's weights at pattern b's peak, on b's receptor.
  double af(std::size_t a, std::size_t b) const {
    const LitPattern& pb = lit[b];
    const BankEntry& e =
        bank.entry[static_cast<std::size_t>(pb.pad)][static_cast<std::size_t>(pb.primary)];
    const Receptor& r = bank.doc.setup.receptors[receptor_index(
        bank.doc.setup, kPrimaries[static_cast<std::size_t>(pb.primary)])];
    return field[a]->af_3d(r.fibre, fibre_axis(r), e.peak_x_mm, e.peak_y_mm, e.peak_z_mm);
  }
  // Crosstalk of a onto b at their currents (crosstalk_current: the current each is planned at).
  double onto(std::size_t a, std::size_t b, const std::vector<double>& current) const {
    if (!(own[b] > 0)) return HUGE_VAL;
    return std::abs(current[a] * af(a, b)) / (current[b] * own[b]);
  }
};

const BankEntry& entry_of(const PixelBank& b, const LitPattern& l) {
  return b.entry[static_cast<std::size_t>(l.pad)][static_cast<std::size_t>(l.primary)];
}

// DSatur (D. Brelaz, "New methods to color the vertices of a graph", Commun. ACM 22(4):
// 251-256, 1979): the uncoloured vertex with the most distinct colours among its
// neighbours next (ties: the most uncoloured neighbours, then the lowest index), given the
// least colour none of its neighbours has.  Deterministic.
std::vector<int> dsatur(const std::vector<std::vector<std::size_t>>& adj) {
  const std::size_t n = adj.size();
  std::vector<int> colour(n, -1);
  std::vector<std::vector<char>> seen(n);  // seen[v][c]: a neighbour of v has colour c
  std::vector<int> saturation(n, 0), free_degree(n);
  for (std::size_t v = 0; v < n; ++v) free_degree[v] = static_cast<int>(adj[v].size());
  for (std::size_t done = 0; done < n; ++done) {
    std::size_t best = n;
    for (std::size_t v = 0; v < n; ++v) {
      if (colour[v] >= 0) continue;
      if (best == n || saturation[v] > saturation[best] ||
          (saturation[v] == saturation[best] && free_degree[v] > free_degree[best]))
        best = v;
    }
    int c = 0;
    while (static_cast<std::size_t>(c) < seen[best].size() &&
           seen[best][static_cast<std::size_t>(c)])
      ++c;
    colour[best] = c;
    for (const std::size_t u : adj[best]) {
      --free_degree[u];
      if (seen[u].size() <= static_cast<std::size_t>(c))
        seen[u].resize(static_cast<std::size_t>(c) + 1, 0);
      if (!seen[u][static_cast<std::size_t>(c)]) {
        seen[u][static_cast<std::size_t>(c)] = 1;
        ++saturation[u];
      }
    }
  }
  return colour;
}

std::uint64_t gcd_u64(std::uint64_t a, std::uint64_t b) {
  while (b) {
    const std::uint64_t t = a % b;
    a = b;
    b = t;
  }
  return a;
}

// One frame: a cycle, each primary's period in cycles; scored by the smallest achieved
// over requested rate, then their sum, then the shorter cycle.
struct Frame {
  long cycle_us = 0;
  std::array<long, 3> k{};
  double score = -1, sum = 0;
  // Each primary's groups, in order: (slot, residue): the group fires in that slot of the
  // cycles whose number is the residue modulo k.
  std::array<std::vector<std::pair<int, long>>, 3> place;
  bool packed = false;  // slots shared between primaries (pack_slots)
};

struct FrameProblem {
  std::array<int, 3> groups{};
  std::array<double, 3> period_us{};  // requested
  double slot_us = 0;                 // pulse length + gap
  // Per primary, per electrode: sum over its groups of the squared current times the
  // time both phases take (mA^2 us), and of the charge both phases carry (mA us).
  std::array<std::vector<double>, 3> square, charge;
  double max_rms_mA = 0, max_mean_mA = 0;
  bool loads = true;
  mutable long packing_work = 0;  // pack_slots' steps so far, bounded by kMaxPackingWork
};

// pack_slots' steps over one plan: a bound on its time (about 0.1 s), deterministic.
constexpr long kMaxPackingWork = 20'000'000;

std::uint64_t gcd_u64(std::uint64_t a, std::uint64_t b);

// The groups in slots that primaries may share: a group of period k (cycles) at residue r
// and one of period k' at r' in the same slot meet iff r = r' modulo gcd(k, k'), so a slot
// holds any groups whose residues differ so.  First fit, the primaries of shortest period
// first; false when some group finds no place (or the work bound is reached).
bool pack_slots(const FrameProblem& fp, long slots, Frame& f) {
  std::array<std::size_t, 3> order = {0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return (f.k[a] > 0 ? f.k[a] : LONG_MAX) < (f.k[b] > 0 ? f.k[b] : LONG_MAX);
  });
  std::array<std::array<long, 3>, 3> g{};  // gcd of the primaries' periods
  for (std::size_t p = 0; p < 3; ++p)
    for (std::size_t q = 0; q < 3; ++q)
      if (f.k[p] > 0 && f.k[q] > 0)
        g[p][q] = static_cast<long>(
            gcd_u64(static_cast<std::uint64_t>(f.k[p]), static_cast<std::uint64_t>(f.k[q])));
  // taken[slot][q][p]: residue classes modulo g[q][p] that q's groups hold in the slot.
  std::vector<std::array<std::array<std::vector<char>, 3>, 3>> taken(
      static_cast<std::size_t>(slots));
  for (std::size_t p = 0; p < 3; ++p) f.place[p].clear();
  for (const std::size_t p : order) {
    for (int i = 0; i < fp.groups[p]; ++i) {
      bool placed = false;
      for (long j = 0; j < slots && !placed; ++j) {
        auto& t = taken[static_cast<std::size_t>(j)];
        for (long r = 0; r < f.k[p] && !placed; ++r) {
          if ((fp.packing_work += 3) > kMaxPackingWork) return false;
          bool free = true;
          for (std::size_t q = 0; q < 3 && free; ++q)
            if (!t[q][p].empty() && t[q][p][static_cast<std::size_t>(r % g[q][p])]) free = false;
          if (!free) continue;
          for (std::size_t q = 0; q < 3; ++q)
            if (f.k[q] > 0) {
              auto& mark = t[p][q];
              if (mark.empty()) mark.assign(static_cast<std::size_t>(g[p][q]), 0);
              mark[static_cast<std::size_t>(r % g[p][q])] = 1;
            }
          f.place[p].emplace_back(static_cast<int>(j), r);
          placed = true;
        }
      }
      if (!placed) return false;
    }
  }
  return true;
}

// The frame for cycle c, if it satisfies every limit.
bool try_frame(const FrameProblem& fp, long c, Frame& f) {
  const long slots = static_cast<long>(std::floor(static_cast<double>(c) / fp.slot_us));
  if (slots < 1) return false;
  f.cycle_us = c;
  f.score = HUGE_VAL;
  f.sum = 0;
  long columns = 0;
  double share = 0;
  for (std::size_t p = 0; p < 3; ++p) {
    if (fp.groups[p] == 0) {
      f.k[p] = 0;
      continue;
    }
    long k = std::max(
        1L, static_cast<long>(std::ceil(fp.period_us[p] / static_cast<double>(c) - 1e-12)));
    if (static_cast<double>(k) * static_cast<double>(c) < fp.period_us[p] - 1e-9) ++k;
    if (static_cast<double>(k) * static_cast<double>(c) > 1e7) return false;  // a 10 s period
    f.k[p] = k;
    columns += (fp.groups[p] + k - 1) / k;
    share += static_cast<double>(fp.groups[p]) / static_cast<double>(k);
    const double ratio = fp.period_us[p] / (static_cast<double>(k) * static_cast<double>(c));
    f.score = std::min(f.score, ratio);
    f.sum += ratio;
  }
  f.packed = columns > slots;
  return share <= static_cast<double>(slots) + 1e-9;  // each group takes 1/k of a slot
}

// The groups' places: each primary its own slots (when they suffice), else pack_slots.
bool place_groups(const FrameProblem& fp, Frame& f) {
  const long slots = static_cast<long>(std::floor(static_cast<double>(f.cycle_us) / fp.slot_us));
  if (f.packed) return pack_slots(fp, slots, f);
  int column = 0;
  for (std::size_t p = 0; p < 3; ++p) {
    f.place[p].clear();
    for (int i = 0; i < fp.groups[p]; ++i)
      f.place[p].emplace_back(column + static_cast<int>(i / f.k[p]), i % f.k[p]);
    if (fp.groups[p] > 0) column += static_cast<int>((fp.groups[p] + f.k[p] - 1) / f.k[p]);
  }
  return true;
}

bool frame_loads_ok(const FrameProblem& fp, const Frame& f) {
  // The device's exact slip check must be able to run: the pulses in max phase + 2
  // hyperperiods (device::kMaxCheckedPulsesHost).
  std::uint64_t lcm = 1;
  long kmax = 1;
  for (std::size_t p = 0; p < 3; ++p)
    if (f.k[p] > 0) {
      const auto k = static_cast<std::uint64_t>(f.k[p]);
      lcm = lcm / gcd_u64(lcm, k) * k;
      kmax = std::max(kmax, f.k[p]);
      if (lcm > (1u << 20)) return false;
    }
  const double end =
      static_cast<double>(kmax + 2 * static_cast<long>(lcm)) * static_cast<double>(f.cycle_us);
  double pulses = 0;
  for (std::size_t p = 0; p < 3; ++p)
    if (f.k[p] > 0)
      pulses += fp.groups[p] *
                (end / (static_cast<double>(f.k[p]) * static_cast<double>(f.cycle_us)) + 1);
  if (pulses > device::kMaxCheckedPulsesHost) return false;
  // The utilisation as the device sums it: each pattern's (length + gap) / period rounded
  // up in units of 2^-20 (device::Scheduler::utilisation_q20).
  std::uint64_t q20 = 0;
  const auto work = static_cast<std::uint64_t>(std::ceil(fp.slot_us)) << 20;
  for (std::size_t p = 0; p < 3; ++p)
    if (f.k[p] > 0) {
      const auto period =
          static_cast<std::uint64_t>(f.k[p]) * static_cast<std::uint64_t>(f.cycle_us);
      q20 += static_cast<std::uint64_t>(fp.groups[p]) * ((work + period - 1) / period);
    }
  if (q20 > device::Scheduler::kOneQ20) return false;
  if (!fp.loads) return true;
  const std::size_t n = fp.square[0].size();
  for (std::size_t e = 0; e < n; ++e) {
    double sq = 0, q = 0;
    for (std::size_t p = 0; p < 3; ++p)
      if (f.k[p] > 0) {
        const double period = static_cast<double>(f.k[p]) * static_cast<double>(f.cycle_us);
        sq += fp.square[p][e] / period;
        q += fp.charge[p][e] / period;
      }
    if (sq > fp.max_rms_mA * fp.max_rms_mA || q > fp.max_mean_mA) return false;
  }
  return true;
}

bool better(const Frame& a, const Frame& b) {
  if (a.score != b.score) return a.score > b.score;
  if (a.sum != b.sum) return a.sum > b.sum;
  return a.cycle_us < b.cycle_us;
}

// The best frame: every whole cycle from one slot up to the longest requested period (or
// the slots every group needs alone), then, while none fits, longer ones by 1 %.
Frame plan_frame(const FrameProblem& fp) {
  Frame best;
  long lo = static_cast<long>(std::ceil(fp.slot_us));
  int all = 0;
  double longest = 0;
  for (std::size_t p = 0; p < 3; ++p) {
    all += fp.groups[p];
    if (fp.groups[p]) longest = std::max(longest, fp.period_us[p]);
  }
  const long hi = std::max(static_cast<long>(std::ceil(longest)),
                           static_cast<long>(std::ceil(all * fp.slot_us)));
  Frame f;
  for (long c = lo; c <= hi; ++c) {
    if (!try_frame(fp, c, f)) continue;
    if (best.score >= 0 && !better(f, best)) continue;
    if (frame_loads_ok(fp, f) && place_groups(fp, f)) best = f;
  }
  for (double c = static_cast<double>(hi) * 1.01; best.score < 0 && c <= 1e7; c *= 1.01) {
    if (try_frame(fp, static_cast<long>(c), f) && frame_loads_ok(fp, f) && place_groups(fp, f))
      best = f;
  }
  return best;
}

}  // namespace

double crosstalk(const PixelBank& bank, int primary, long a, double ia, long b, double ib) {
  std::vector<LitPattern> lit = {{a, primary, 1, ia}, {b, primary, 1, ib}};
  const PatternFields f(bank, lit);
  return f.onto(0, 1, {ia, ib});
}

namespace {

// The lit patterns of an image, pixel-major, at the profile's currents.
std::vector<LitPattern> lit_patterns(const PixelBank& bank, const Profile& profile,
                                     const PadIntensities& image, const RenderOptions& o) {
  std::vector<LitPattern> lit;
  for (std::size_t pad = 0; pad < bank.pads(); ++pad)
    for (int p = 0; p < 3; ++p) {
      const BankEntry& e = bank.entry[pad][static_cast<std::size_t>(p)];
      const double v = image.value[pad][static_cast<std::size_t>(p)];
      if (!(v > 0)) continue;
      const std::string where = "image " + pixel_text(static_cast<long>(pad), bank.columns) +
                                " lights " + kPrimaries[static_cast<std::size_t>(p)];
      if (!e.present) bad_input(where + ", which the bank has no patterns for");
      if (!e.feasible) bad_input(where + ", whose pattern the bank could not find: " + e.reason);
      LitPattern l;
      l.pad = static_cast<long>(pad);
      l.primary = p;
      l.intensity = v;
      l.current_mA = profile.current_mA(p, l.pad, v);
      if (l.current_mA > o.limits.max_current_mA)
        bad_input(where + " at " + number_beside(l.current_mA, o.limits.max_current_mA) +
                  " mA, above the current limit");
      lit.push_back(l);
    }
  return lit;
}

// Which lit patterns fire together: per primary, the conflict graph (a shared pad, the
// crosstalk bound broken in either direction, or another kin) coloured by DSatur.  Sets
// the plan's groups, groups_per_primary and worst_crosstalk.  kin: by 3 x pad + primary
// (empty: every pattern the same kin).
void group_patterns(const PixelBank& bank, const RenderOptions& o, const std::vector<long>& kin,
                    RenderPlan& plan) {
  const std::size_t n = plan.lit.size();
  const std::size_t pads = bank.pads();
  // Which pads each pattern uses.
  std::vector<std::vector<std::uint64_t>> uses(n, std::vector<std::uint64_t>((pads + 63) / 64, 0));
  for (std::size_t i = 0; i < n; ++i) {
    const auto& w = entry_of(bank, plan.lit[i]).weights;
    for (std::size_t e = 0; e < pads; ++e)
      if (w[e] != 0) uses[i][e / 64] |= std::uint64_t{1} << (e % 64);
  }
  auto share_pad = [&](std::size_t i, std::size_t j) {
    for (std::size_t w = 0; w < uses[i].size(); ++w)
      if (uses[i][w] & uses[j][w]) return true;
    return false;
  };
  auto other_kin = [&](std::size_t i, std::size_t j) {
    if (kin.empty()) return false;
    auto at = [&](std::size_t k) {
      return kin[3 * static_cast<std::size_t>(plan.lit[k].pad) +
                 static_cast<std::size_t>(plan.lit[k].primary)];
    };
    return at(i) != at(j);
  };
  // Each pad's AF alone (1 mA) at every lit pattern's peak, on its receptor: a pattern's
  // AF anywhere is its weights' sum of these (the field is linear in the currents).
  std::vector<std::vector<double>> unit(pads, std::vector<double>(n, 0.0));
  std::vector<const Receptor*> receptor(n);
  std::vector<FibreAxis> axis(n);
  for (std::size_t j = 0; j < n; ++j) {
    receptor[j] = &bank.doc.setup.receptors[receptor_index(
        bank.doc.setup, kPrimaries[static_cast<std::size_t>(plan.lit[j].primary)])];
    axis[j] = fibre_axis(*receptor[j]);
  }
  parallel_for(pads, o.threads, [&](std::size_t e) {
    bool used = false;
    for (std::size_t i = 0; i < n && !used; ++i) used = (uses[i][e / 64] >> (e % 64)) & 1;
    if (!used) return;
    std::vector<double> one(pads, 0.0);
    one[e] = 1.0;
    const Field f(bank.doc.setup, one);
    for (std::size_t j = 0; j < n; ++j) {
      const BankEntry& t = entry_of(bank, plan.lit[j]);
      unit[e][j] = f.af_3d(receptor[j]->fibre, axis[j], t.peak_x_mm, t.peak_y_mm, t.peak_z_mm);
    }
  });
  auto af = [&](std::size_t i, std::size_t j) {  // pattern i's AF at pattern j's peak
    const auto& w = entry_of(bank, plan.lit[i]).weights;
    double sum = 0;
    for (std::size_t e = 0; e < pads; ++e)
      if (w[e] != 0) sum += w[e] * unit[e][j];
    return sum;
  };
  std::vector<double> own(n);
  for (std::size_t j = 0; j < n; ++j) own[j] = af(j, j);
  auto cross = [&](std::size_t i, std::size_t j) {  // i onto j
    if (!(own[j] > 0)) return HUGE_VAL;
    return std::abs(plan.lit[i].current_mA * af(i, j)) / (plan.lit[j].current_mA * own[j]);
  };
  for (int p = 0; p < 3; ++p) {
    std::vector<std::size_t> nodes;
    for (std::size_t i = 0; i < n; ++i)
      if (plan.lit[i].primary == p) nodes.push_back(i);
    std::vector<std::vector<std::size_t>> later(nodes.size());  // conflicts with b > a
    parallel_for(nodes.size(), o.threads, [&](std::size_t a) {
      for (std::size_t b = a + 1; b < nodes.size(); ++b) {
        const std::size_t i = nodes[a], j = nodes[b];
        if (other_kin(i, j) || share_pad(i, j) || std::max(cross(i, j), cross(j, i)) > o.crosstalk)
          later[a].push_back(b);
      }
    });
    std::vector<std::vector<std::size_t>> adj(nodes.size());
    for (std::size_t a = 0; a < nodes.size(); ++a)
      for (const std::size_t b : later[a]) {
        adj[a].push_back(b);
        adj[b].push_back(a);
      }
    const std::vector<int> colour = dsatur(adj);
    const int colours = nodes.empty() ? 0 : *std::max_element(colour.begin(), colour.end()) + 1;
    plan.groups_per_primary[static_cast<std::size_t>(p)] = colours;
    for (int c = 0; c < colours; ++c) {
      RenderGroup g;
      g.primary = p;
      for (std::size_t a = 0; a < nodes.size(); ++a)
        if (colour[a] == c) g.members.push_back(nodes[a]);
      for (std::size_t a = 0; a < g.members.size(); ++a)
        for (std::size_t b = 0; b < g.members.size(); ++b)
          if (a != b)
            plan.worst_crosstalk =
                std::max(plan.worst_crosstalk, cross(g.members[a], g.members[b]));
      plan.groups.push_back(g);
    }
  }
}

// The frame for the groups' currents (by group, by pad): sets the plan's cycle, slots,
// periods, rates and whether (and by what) they were lowered.
Frame frame_for(const RenderOptions& o, const std::vector<std::vector<double>>& currents,
                RenderPlan& plan) {
  const std::size_t pads = currents.empty() ? 0 : currents[0].size();
  FrameProblem fp;
  fp.groups = plan.groups_per_primary;
  for (std::size_t p = 0; p < 3; ++p) fp.period_us[p] = 1e6 / o.rate_hz[p];
  fp.slot_us = o.width_us + o.interphase_us + o.balance_width_us + o.gap_us;
  fp.max_rms_mA = o.load_margin * o.limits.max_rms_current_mA;
  fp.max_mean_mA = o.load_margin * o.limits.max_mean_current_mA;
  for (std::size_t p = 0; p < 3; ++p) {
    fp.square[p].assign(pads, 0.0);
    fp.charge[p].assign(pads, 0.0);
  }
  const double scale = o.width_us / o.balance_width_us;
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    const auto p = static_cast<std::size_t>(plan.groups[g].primary);
    for (std::size_t e = 0; e < pads; ++e) {
      const double i = currents[g][e];
      fp.square[p][e] += i * i * o.width_us + i * scale * i * scale * o.balance_width_us;
      fp.charge[p][e] += 2 * std::abs(i) * o.width_us;
    }
  }
  const Frame best = plan_frame(fp);
  if (best.score < 0)
    throw Error(ExitCode::failure,
                "render: no frame of at most 10 s periods keeps every electrode's RMS and mean "
                "current within the limits");
  FrameProblem free = fp;
  free.packing_work = 0;  // a budget of its own
  free.loads = false;
  const Frame unloaded = plan_frame(free);
  plan.cycle_us = static_cast<double>(best.cycle_us);
  plan.slots = static_cast<int>(std::floor(plan.cycle_us / fp.slot_us));
  plan.k = best.k;
  for (std::size_t p = 0; p < 3; ++p)
    plan.rate_hz[p] = best.k[p] > 0 ? 1e6 / (static_cast<double>(best.k[p]) * plan.cycle_us) : 0.0;
  plan.lowered = best.score < 0.995;
  // The share of the device's time the requested rates would take.
  plan.requested_utilisation = 0;
  for (std::size_t p = 0; p < 3; ++p)
    plan.requested_utilisation += fp.groups[p] * fp.slot_us / fp.period_us[p];
  if (plan.lowered)
    plan.limited_by = best.score < unloaded.score      ? "the electrodes' RMS and mean current"
                      : plan.requested_utilisation > 1 ? "the device's time"
                                                       : "the frame's slots";
  return best;
}

// Each pattern's pulses in o.duration_s at its period; bad input when the duration holds
// none (it is never stretched to one).
long pulse_count(const RenderOptions& o, int primary, double period_us) {
  const double count = std::floor(o.duration_s * 1e6 / period_us + 1e-9);
  if (count < 1) {
    const double least_s = std::ceil(period_us / 100) / 1e4;  // rounded up, 0.1 ms
    bad_input("--duration: the stimulus's " + number_text(o.duration_s) +
              " s is shorter than one period of " + kPrimaries[static_cast<std::size_t>(primary)] +
              " at its planned " + number_text(std::round(1e8 / period_us) / 100) + " Hz (" +
              number_text(period_us / 1e6) + " s): give --duration " + number_text(least_s) +
              " or more");
  }
  return static_cast<long>(count);
}

// The groups as the frame placed them: their slots and turns, and the mix.
void build_mix(const PixelBank& bank, const RenderOptions& o,
               const std::vector<std::vector<double>>& currents, const Frame& best,
               RenderPlan& plan) {
  const double slot_us = o.width_us + o.interphase_us + o.balance_width_us + o.gap_us;
  std::array<std::size_t, 3> next{};
  plan.mix.gap_us = o.gap_us;
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    RenderGroup& grp = plan.groups[g];
    const auto p = static_cast<std::size_t>(grp.primary);
    const auto [slot, turn] = best.place[p][next[p]++];
    grp.slot = slot;
    grp.turn = static_cast<int>(turn);
    Stimulus s;
    s.currents_mA = currents[g];
    s.shape.width_us = o.width_us;
    s.shape.interphase_us = o.interphase_us;
    s.shape.balance_width_us = o.balance_width_us;
    const double period = static_cast<double>(best.k[p]) * plan.cycle_us;
    s.shape.frequency_hz = 1e6 / period;
    s.count = pulse_count(o, grp.primary, period);
    s.phase_us = grp.turn * plan.cycle_us + grp.slot * slot_us;
    double peak = 0;
    for (const double i : s.currents_mA) peak = std::max(peak, std::abs(i));
    s.amplitude_mA = peak;
    s.max_current_mA = o.limits.max_current_mA;
    s.electrode_area_mm2 = bank.pad_area_mm2;
    Json pixels = Json::array(), intensity = Json::array(), mA = Json::array();
    for (const std::size_t i : grp.members) {
      pixels.push_back(plan.lit[i].pad);
      intensity.push_back(plan.lit[i].intensity);
      mA.push_back(plan.lit[i].current_mA);
    }
    s.carried = {{"primary", kPrimaries[p]},
                 {"pixels", pixels},
                 {"intensities", intensity},
                 {"pixel_currents_mA", mA}};
    plan.mix.patterns.push_back(std::move(s));
  }
}

void check_plan_inputs(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                       const RenderOptions& o) {
  check_render_options(o);
  // A profile calibrated on an array (calibrate writes its size) fits only that array.
  if (profile.carried.contains("array")) {
    const Json& a = profile.carried["array"];
    const bool same = a.is_object() && a.contains("columns") && a.contains("rows") &&
                      a["columns"] == bank.columns && a["rows"] == bank.rows;
    if (!same)
      bad_input("profile: calibrated on an array of " + a.dump() + ", the bank's is " +
                std::to_string(bank.columns) + " x " + std::to_string(bank.rows));
  }
  if (image.columns != bank.columns || image.rows != bank.rows)
    bad_input("image: " + std::to_string(image.columns) + " x " + std::to_string(image.rows) +
              " pixels for a bank of " + std::to_string(bank.columns) + " x " +
              std::to_string(bank.rows) + " pads");
}

// The plan: lit patterns, their groups (kin as group_patterns takes it), the frame, the mix.
RenderPlan plan_with_kin(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                         const RenderOptions& o, const std::vector<long>& kin) {
  check_plan_inputs(bank, profile, image, o);
  RenderPlan plan;
  plan.requested_hz = o.rate_hz;
  plan.lit = lit_patterns(bank, profile, image, o);
  if (plan.lit.empty()) return plan;
  group_patterns(bank, o, kin, plan);
  // Each group's currents (its members share no pad).
  std::vector<std::vector<double>> currents(plan.groups.size(),
                                            std::vector<double>(bank.pads(), 0.0));
  for (std::size_t g = 0; g < plan.groups.size(); ++g)
    for (const std::size_t i : plan.groups[g].members) {
      const LitPattern& l = plan.lit[i];
      const auto& w = entry_of(bank, l).weights;
      for (std::size_t e = 0; e < bank.pads(); ++e) currents[g][e] += l.current_mA * w[e];
    }
  const Frame best = frame_for(o, currents, plan);
  build_mix(bank, o, currents, best, plan);
  return plan;
}

std::string rates_text(const RenderPlan& plan) {
  std::string out;
  for (std::size_t p = 0; p < 3; ++p) {
    if (plan.groups_per_primary[p] == 0) continue;
    if (!out.empty()) out += ", ";
    out += std::string(kPrimaries[p]) + " " + number_text(std::round(plan.rate_hz[p] * 100) / 100) +
           " Hz (" + number_text(plan.requested_hz[p]) + " requested; " +
           count_text(static_cast<std::size_t>(plan.groups_per_primary[p]), "group") + ")";
  }
  return out;
}

// A sequence's stimulus read back: each pattern's primary, pixels and the currents they
// were made at (render-tactile --sequence's carried keys).
Sequence sequence_of(const Mix& m, std::size_t pads) {
  Sequence q;
  q.mix = m;
  std::vector<char> seen(3 * pads, 0);
  for (std::size_t g = 0; g < m.patterns.size(); ++g) {
    const Json& c = m.patterns[g].carried;
    const std::string where = "stimulus: pattern " + std::to_string(g);
    if (!c.contains("primary") || !c["primary"].is_string() || !c.contains("pixels") ||
        !c["pixels"].is_array() || c["pixels"].empty() || !c.contains("pixel_currents_mA") ||
        !c["pixel_currents_mA"].is_array() || c["pixel_currents_mA"].size() != c["pixels"].size())
      bad_input(where +
                " is not a sequence's (render-tactile --sequence: a primary, its pixels "
                "and their pixel_currents_mA)");
    q.primary.push_back(primary_index(c["primary"].get<std::string>(), where + ": primary"));
    q.pads.emplace_back();
    q.made_mA.emplace_back();
    for (std::size_t k = 0; k < c["pixels"].size(); ++k) {
      const long pad = json_int(c["pixels"][k], where + ": pixels");
      const double mA = json_finite(c["pixel_currents_mA"][k], where + ": pixel_currents_mA");
      if (pad < 0 || static_cast<std::size_t>(pad) >= pads)
        bad_input(where + "'s pixel " + std::to_string(pad) + " is not one of the bank's " +
                  count_text(pads, "pad"));
      if (!(mA > 0)) bad_input(where + ": pixel_currents_mA: not above 0");
      char& s = seen[3 * static_cast<std::size_t>(pad) + static_cast<std::size_t>(q.primary[g])];
      if (s) bad_input(where + ": pixel " + std::to_string(pad) + " in two patterns");
      s = 1;
      q.pads[g].push_back(pad);
      q.made_mA[g].push_back(mA);
    }
  }
  return q;
}

// The share of a pixel's made current that intensity v asks under the profile.
double share_of(const Sequence& q, const Profile& profile, std::size_t g, std::size_t k, double v) {
  return profile.current_mA(q.primary[g], q.pads[g][k], v) / q.made_mA[g][k];
}

constexpr double kShareTolerance = 1e-9;  // shares this close are the same (rounding)

}  // namespace

RenderPlan plan_render(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                       const RenderOptions& o) {
  return plan_with_kin(bank, profile, image, o, {});
}

std::string plan_summary(const RenderPlan& plan) {
  return count_text(plan.lit.size(), "lit pattern") + " in " +
         count_text(plan.groups.size(), "group") + ", cycle " + number_text(plan.cycle_us) +
         " us of " + count_text(static_cast<std::size_t>(plan.slots), "slot") +
         ", worst crosstalk " + number_text(std::round(plan.worst_crosstalk * 1e4) / 1e4) +
         "; refresh " + rates_text(plan);
}

std::string lowered_text(const RenderPlan& plan, const std::string& what) {
  if (!plan.lowered) return "";
  return "the " + what + "'s pulses at the requested rates would take " +
         number_text(std::round(plan.requested_utilisation * 1000) / 10) +
         " % of the device's time: rates lowered by " + plan.limited_by + ", every lit pixel kept";
}

SequenceFrames::SequenceFrames(int columns, int rows) : columns_(columns), rows_(rows) {
  const std::size_t n = static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows);
  first_.columns = columns;
  first_.rows = rows;
  first_.value.assign(n, {0.0, 0.0, 0.0});
  lit_.assign(3 * n, 0);
  kin_.assign(3 * n, 0);
}

void SequenceFrames::add(const PadIntensities& frame, const std::string& where) {
  if (frame.columns != columns_ || frame.rows != rows_ || frame.value.size() != first_.value.size())
    bad_input(where + ": " + std::to_string(frame.columns) + " x " + std::to_string(frame.rows) +
              " pixels for a bank of " + std::to_string(columns_) + " x " + std::to_string(rows_) +
              " pads");
  if (count_++ == 0) first_ = frame;
  // Kin refined: the same kin before and the same intensity now (ids by first appearance).
  std::map<std::pair<long, double>, long> next;
  for (std::size_t pad = 0; pad < frame.value.size(); ++pad)
    for (std::size_t p = 0; p < 3; ++p) {
      const double v = frame.value[pad][p];
      if (v > 0) lit_[3 * pad + p] = 1;
      long& k = kin_[3 * pad + p];
      k = next.emplace(std::pair{k, v}, static_cast<long>(next.size())).first->second;
    }
}

RenderPlan plan_sequence(const PixelBank& bank, const Profile& profile,
                         const SequenceFrames& frames, const RenderOptions& o) {
  PadIntensities any;
  any.columns = bank.columns;
  any.rows = bank.rows;
  any.value.assign(bank.pads(), {0.0, 0.0, 0.0});
  // Kin: the frames' and the same range (so one amplitude sets both alike); without
  // frames, each its own.
  std::vector<long> kin(3 * bank.pads());
  std::map<std::tuple<long, double, double>, long> ids;
  for (std::size_t pad = 0; pad < bank.pads(); ++pad)
    for (std::size_t p = 0; p < 3; ++p) {
      const bool lit = frames.count() > 0 ? frames.lit(pad, p)
                                          : bank.entry[pad][p].feasible && profile.primary[p];
      if (!lit) continue;
      any.value[pad][p] = 1.0;
      const PrimaryRange& r = profile.range(static_cast<int>(p), static_cast<long>(pad));
      const long frame_kin =
          frames.count() > 0 ? frames.kin(pad, p) : static_cast<long>(3 * pad + p);
      kin[3 * pad + p] = ids.emplace(std::tuple{frame_kin, r.threshold_mA, r.comfort_mA},
                                     static_cast<long>(ids.size()))
                             .first->second;
    }
  RenderPlan plan = plan_with_kin(bank, profile, any, o, kin);
  if (plan.lit.empty()) return plan;
  plan.mix.start_amplitudes_mA = frames.count() == 0
                                     ? std::vector<double>(plan.mix.patterns.size(), 0.0)
                                     : frame_amplitudes(sequence_of(plan.mix, bank.pads()), profile,
                                                        frames.first(), "frame 1");
  return plan;
}

RenderPlan plan_sequence(const PixelBank& bank, const Profile& profile,
                         const std::vector<PadIntensities>& frames, const RenderOptions& o) {
  SequenceFrames s(bank.columns, bank.rows);
  for (std::size_t f = 0; f < frames.size(); ++f)
    s.add(frames[f], "frame " + std::to_string(f + 1));
  return plan_sequence(bank, profile, s, o);
}

Json sequence_to_json(const RenderPlan& sequence, const PixelBank& bank) {
  Json j = mix_to_json(sequence.mix);
  j["array"] = array_to_json(bank.doc.setup.array);
  return j;
}

double sequence_duration_s(std::size_t frames, double fps, const StimulusLimits& limits) {
  const double s = (static_cast<double>(frames) + 1) / fps;
  if (s > limits.max_duration_s)
    bad_input("--sequence: " + count_text(frames, "frame") + " at " + number_text(fps) +
              " fps and one frame period more last " + number_text(s) +
              " s, longer than a stimulus may (" + number_text(limits.max_duration_s) +
              " s): split the sequence, or give a higher --fps");
  return s;
}

Sequence sequence_from_json(const Json& j, const PixelBank& bank, const Profile& profile,
                            const std::string& what) {
  const Json mine = array_to_json(bank.doc.setup.array);
  if (!j.is_object() || !j.contains("array"))
    bad_input(what +
              ": records no array (render-tactile --sequence writes the bank's): make "
              "the sequence again with --sequence");
  if (j["array"] != mine) {
    const Json& a = j["array"];
    const bool grid = a.is_object() && a.contains("grid") && a["grid"].is_object() &&
                      a["grid"].contains("columns") && a["grid"].contains("rows");
    const std::string theirs =
        grid ? a["grid"]["columns"].dump() + " x " + a["grid"]["rows"].dump() : "";
    const std::string ours = std::to_string(bank.columns) + " x " + std::to_string(bank.rows);
    bad_input(what + ": a sequence made for " +
              (grid && theirs != ours
                   ? theirs + " pads (columns x rows), not the bank's " + ours
                   : "the array " + a.dump() + ", not the bank's " + mine.dump()) +
              ": give the bank it was made with, or make the sequence again with this one");
  }
  const Mix m = mix_from_json(j);
  if (m.patterns[0].currents_mA.size() != bank.pads())
    bad_input(what + ": " + count_text(m.patterns[0].currents_mA.size(), "channel") +
              " for a bank of " + count_text(bank.pads(), "pad"));
  Sequence q = sequence_of(m, bank.pads());
  // The profile against the currents each pixel was made at: never more (the pattern holds
  // no more), and a pattern's pixels in one proportion (one amplitude scales them all).
  for (std::size_t g = 0; g < q.pads.size(); ++g)
    for (std::size_t k = 0; k < q.pads[g].size(); ++k) {
      const std::string pixel = pixel_text(q.pads[g][k], bank.columns) + "'s " +
                                kPrimaries[static_cast<std::size_t>(q.primary[g])];
      const double top = share_of(q, profile, g, k, 1.0);
      if (top > 1 + kShareTolerance)
        bad_input(what + ": the profile gives " + pixel + " up to " +
                  number_text(profile.current_mA(q.primary[g], q.pads[g][k], 1.0)) +
                  " mA, above the " + number_text(q.made_mA[g][k]) +
                  " mA its pattern was made for (another profile): make the sequence again "
                  "with this profile");
      const double v = 1.0 / 255;  // the lowest intensity: the threshold's share
      if (k > 0 && (std::abs(top - share_of(q, profile, g, 0, 1.0)) > kShareTolerance ||
                    std::abs(share_of(q, profile, g, k, v) - share_of(q, profile, g, 0, v)) >
                        kShareTolerance))
        bad_input(what + ": the profile gives " + pixel + " another range than " +
                  pixel_text(q.pads[g][0], bank.columns) +
                  ", which fires with it as one pattern: make the sequence again with this "
                  "profile");
    }
  return q;
}

std::vector<double> frame_amplitudes(const Sequence& q, const Profile& profile,
                                     const PadIntensities& frame, const std::string& where) {
  // Where each (pad, primary) is: its pattern and member.
  std::vector<std::pair<long, std::size_t>> at(3 * frame.value.size(), {-1, 0});
  for (std::size_t g = 0; g < q.pads.size(); ++g)
    for (std::size_t k = 0; k < q.pads[g].size(); ++k) {
      const auto pad = static_cast<std::size_t>(q.pads[g][k]);
      if (pad >= frame.value.size())
        bad_input("stimulus: pattern " + std::to_string(g) + "'s pixel " + std::to_string(pad) +
                  " is not one of the frame's " + count_text(frame.value.size(), "pixel"));
      at[3 * pad + static_cast<std::size_t>(q.primary[g])] = {static_cast<long>(g), k};
    }
  for (std::size_t pad = 0; pad < frame.value.size(); ++pad)
    for (std::size_t p = 0; p < 3; ++p)
      if (frame.value[pad][p] > 0 && at[3 * pad + p].first < 0)
        bad_input(where + ": " + pixel_text(static_cast<long>(pad), frame.columns) + " lights " +
                  kPrimaries[p] + ", which the sequence's stimulus has no pattern for");
  std::vector<double> a(q.pads.size(), 0.0);
  for (std::size_t g = 0; g < q.pads.size(); ++g) {
    const auto p = static_cast<std::size_t>(q.primary[g]);
    auto v = [&](std::size_t k) { return frame.value[static_cast<std::size_t>(q.pads[g][k])][p]; };
    const double share = share_of(q, profile, g, 0, v(0));
    for (std::size_t k = 1; k < q.pads[g].size(); ++k)
      if (std::abs(share_of(q, profile, g, k, v(k)) - share) > kShareTolerance)
        bad_input(where + ": " + pixel_text(q.pads[g][0], frame.columns) + " and " +
                  pixel_text(q.pads[g][k], frame.columns) + " fire as one " + kPrimaries[p] +
                  " pattern of the sequence's stimulus (its frames lit them alike), but this "
                  "frame lights them unlike: make the sequence from these frames");
    if (share > 1 + kShareTolerance)
      bad_input(where + ": " + pixel_text(q.pads[g][0], frame.columns) + " asks " +
                number_text(profile.current_mA(q.primary[g], q.pads[g][0], v(0))) + " mA of " +
                kPrimaries[p] + ", above the " + number_text(q.made_mA[g][0]) +
                " mA its pattern was made for: make the sequence again with this profile");
    a[g] = std::min(share, 1.0) * q.mix.patterns[g].amplitude_mA;
  }
  return a;
}

PadIntensities frame_from_json(const Json& j, int columns, int rows, const std::string& where) {
  if (!j.is_object() || !j.contains("rgb") || !j["rgb"].is_array())
    bad_input(where + ": expected {\"rgb\": [[R, G, B], ...]}");
  const Json& a = j["rgb"];
  const auto n = static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows);
  if (a.size() != n)
    bad_input(where + ": " + count_text(a.size(), "pixel") + " for " + std::to_string(columns) +
              " x " + std::to_string(rows) + " pads");
  PadIntensities f;
  f.columns = columns;
  f.rows = rows;
  for (std::size_t k = 0; k < n; ++k) {
    if (!a[k].is_array() || a[k].size() != 3)
      bad_input(where + ": pixel " + std::to_string(k) + " is not [R, G, B]");
    std::array<double, 3> v{};
    for (std::size_t c = 0; c < 3; ++c) {
      if (!a[k][c].is_number_integer() || a[k][c].get<long>() < 0 || a[k][c].get<long>() > 255)
        bad_input(where + ": pixel " + std::to_string(k) + ": not a whole number from 0 to 255");
      v[c] = static_cast<double>(a[k][c].get<long>()) / 255.0;
    }
    f.value.push_back(v);
  }
  return f;
}

Json plan_to_json(const RenderPlan& p) {
  Json j = {{"format", "tactile-primaries/render-plan/1"}};
  Json rates = Json::object();
  for (std::size_t i = 0; i < 3; ++i)
    if (p.groups_per_primary[i] > 0)
      rates[kPrimaries[i]] = {{"requested_hz", p.requested_hz[i]},
                              {"rate_hz", p.rate_hz[i]},
                              {"groups", p.groups_per_primary[i]},
                              {"period_cycles", p.k[i]}};
  j["rates"] = rates;
  j["cycle_us"] = p.cycle_us;
  j["slots"] = p.slots;
  j["lit"] = p.lit.size();
  j["worst_crosstalk"] = p.worst_crosstalk;
  j["requested_utilisation"] = p.requested_utilisation;
  j["lowered"] = p.lowered;
  if (p.lowered) j["limited_by"] = p.limited_by;
  Json groups = Json::array();
  for (const RenderGroup& g : p.groups) {
    Json px = Json::array();
    for (const std::size_t i : g.members) px.push_back(p.lit[i].pad);
    groups.push_back({{"primary", kPrimaries[static_cast<std::size_t>(g.primary)]},
                      {"slot", g.slot},
                      {"turn", g.turn},
                      {"pixels", px}});
  }
  j["groups"] = groups;
  return j;
}

}  // namespace tp
