#include "render/plan.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/number.hpp"
#include "model/field.hpp"
#include "render/colouring.hpp"
#include "core/text.hpp"

namespace tp {

void check_plan_inputs(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                       const RenderOptions& o) {
  check_render_options(o);
  // A profile calibrated on an array (calibrate writes its size) fits only that array.
  check_profile_fits(profile, static_cast<std::size_t>(bank.columns) * bank.rows,
                     std::make_pair(bank.columns, bank.rows),
                     "the bank's is " + std::to_string(bank.columns) + " x " +
                         std::to_string(bank.rows));
  if (image.columns != bank.columns || image.rows != bank.rows)
    bad_input("image: " + std::to_string(image.columns) + " x " + std::to_string(image.rows) +
              " pixels for a bank of " + std::to_string(bank.columns) + " x " +
              std::to_string(bank.rows) + " pads");
}

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

const BankEntry& entry_of(const PixelBank& b, const LitPattern& l) {
  return b.entry[static_cast<std::size_t>(l.pad)][static_cast<std::size_t>(l.primary)];
}

LitReach::LitReach(const PixelBank& bank, const std::vector<LitPattern>& lit, unsigned threads)
    : bank_(bank), lit_(lit) {
  const std::size_t n = lit.size();
  const std::size_t pads = bank.pads();
  uses_.assign(n, std::vector<std::uint64_t>((pads + 63) / 64, 0));
  for (std::size_t i = 0; i < n; ++i) {
    const auto& w = entry_of(bank, lit[i]).weights;
    for (std::size_t e = 0; e < pads; ++e)
      if (w[e] != 0) uses_[i][e / 64] |= std::uint64_t{1} << (e % 64);
  }
  // Each used pad's AF alone (1 mA) at every lit pattern's peak, on its receptor.
  unit_.assign(pads, std::vector<double>(n, 0.0));
  std::vector<const Receptor*> receptor(n);
  std::vector<FibreAxis> axis(n);
  for (std::size_t j = 0; j < n; ++j) {
    receptor[j] = &bank.doc.setup.receptors[receptor_index(
        bank.doc.setup, kPrimaries[static_cast<std::size_t>(lit[j].primary)])];
    axis[j] = fibre_axis(*receptor[j]);
  }
  parallel_for(pads, threads, [&](std::size_t e) {
    bool used = false;
    for (std::size_t i = 0; i < n && !used; ++i) used = (uses_[i][e / 64] >> (e % 64)) & 1;
    if (!used) return;
    std::vector<double> one(pads, 0.0);
    one[e] = 1.0;
    const Field f(bank.doc.setup, one);
    for (std::size_t j = 0; j < n; ++j) {
      const BankEntry& t = entry_of(bank, lit[j]);
      unit_[e][j] = f.af_3d(receptor[j]->fibre, axis[j], t.peak_x_mm, t.peak_y_mm, t.peak_z_mm);
    }
  });
  own_.resize(n);
  for (std::size_t j = 0; j < n; ++j) own_[j] = af(j, j);
}

bool LitReach::share_pad(std::size_t i, std::size_t j) const {
  for (std::size_t w = 0; w < uses_[i].size(); ++w)
    if (uses_[i][w] & uses_[j][w]) return true;
  return false;
}

double LitReach::af(std::size_t i, std::size_t j) const {
  const auto& w = entry_of(bank_, lit_[i]).weights;
  double sum = 0;
  for (std::size_t e = 0; e < w.size(); ++e)
    if (w[e] != 0) sum += w[e] * unit_[e][j];
  return sum;
}

double LitReach::crosstalk(std::size_t i, std::size_t j) const {
  if (!(own_[j] > 0)) return HUGE_VAL;
  return std::abs(lit_[i].current_mA * af(i, j)) / (lit_[j].current_mA * own_[j]);
}

std::vector<std::vector<std::size_t>> conflict_graph(const LitReach& reach,
                                                     const std::vector<LitPattern>& lit,
                                                     const std::vector<std::size_t>& nodes,
                                                     const std::vector<long>& kin, double bound,
                                                     unsigned threads) {
  auto kin_of = [&](std::size_t k) {
    return kin[3 * static_cast<std::size_t>(lit[k].pad) + static_cast<std::size_t>(lit[k].primary)];
  };
  std::vector<std::vector<std::size_t>> later(nodes.size());  // conflicts with b > a
  parallel_for(nodes.size(), threads, [&](std::size_t a) {
    for (std::size_t b = a + 1; b < nodes.size(); ++b) {
      const std::size_t i = nodes[a], j = nodes[b];
      if ((!kin.empty() && kin_of(i) != kin_of(j)) || reach.share_pad(i, j) ||
          std::max(reach.crosstalk(i, j), reach.crosstalk(j, i)) > bound)
        later[a].push_back(b);
    }
  });
  std::vector<std::vector<std::size_t>> adj(nodes.size());
  for (std::size_t a = 0; a < nodes.size(); ++a)
    for (const std::size_t b : later[a]) {
      adj[a].push_back(b);
      adj[b].push_back(a);
    }
  return adj;
}

void group_patterns(const PixelBank& bank, const RenderOptions& o, const std::vector<long>& kin,
                    RenderPlan& plan) {
  const LitReach reach(bank, plan.lit, o.threads);
  for (int p = 0; p < 3; ++p) {
    std::vector<std::size_t> nodes;
    for (std::size_t i = 0; i < plan.lit.size(); ++i)
      if (plan.lit[i].primary == p) nodes.push_back(i);
    const std::vector<int> colour =
        dsatur(conflict_graph(reach, plan.lit, nodes, kin, o.crosstalk, o.threads));
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
                std::max(plan.worst_crosstalk, reach.crosstalk(g.members[a], g.members[b]));
      plan.groups.push_back(g);
    }
  }
}

std::vector<std::vector<double>> group_currents(const PixelBank& bank, const RenderPlan& plan) {
  std::vector<std::vector<double>> currents(plan.groups.size(),
                                            std::vector<double>(bank.pads(), 0.0));
  for (std::size_t g = 0; g < plan.groups.size(); ++g)
    for (const std::size_t i : plan.groups[g].members) {
      const LitPattern& l = plan.lit[i];
      const auto& w = entry_of(bank, l).weights;
      for (std::size_t e = 0; e < bank.pads(); ++e) currents[g][e] += l.current_mA * w[e];
    }
  return currents;
}

FrameProblem frame_problem(const RenderOptions& o, const std::vector<std::vector<double>>& currents,
                           const RenderPlan& plan) {
  const std::size_t pads = currents.empty() ? 0 : currents[0].size();
  FrameProblem fp;
  fp.groups = plan.groups_per_primary;
  for (std::size_t p = 0; p < 3; ++p) fp.period_us[p] = 1e6 / o.rate_hz[p];
  fp.slot_us = slot_us(o);
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
  return fp;
}

Frame frame_for(const RenderOptions& o, const std::vector<std::vector<double>>& currents,
                RenderPlan& plan) {
  const FrameProblem fp = frame_problem(o, currents, plan);
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

namespace {

// A group's pattern: its currents, the pulse, its period's count and its phase in the frame.
Stimulus group_stimulus(const PixelBank& bank, const RenderOptions& o,
                        const std::vector<double>& currents, const RenderGroup& grp, long k,
                        double cycle_us) {
  Stimulus s;
  s.currents_mA = currents;
  s.shape.width_us = o.width_us;
  s.shape.interphase_us = o.interphase_us;
  s.shape.balance_width_us = o.balance_width_us;
  const double period = static_cast<double>(k) * cycle_us;
  s.shape.frequency_hz = 1e6 / period;
  s.count = pulse_count(o, grp.primary, period);
  s.phase_us = grp.turn * cycle_us + grp.slot * slot_us(o);
  double peak = 0;
  for (const double i : s.currents_mA) peak = std::max(peak, std::abs(i));
  s.amplitude_mA = peak;
  s.max_current_mA = o.limits.max_current_mA;
  s.electrode_area_mm2 = bank.pad_area_mm2;
  return s;
}

}  // namespace

void build_mix(const PixelBank& bank, const RenderOptions& o,
               const std::vector<std::vector<double>>& currents, const Frame& frame,
               RenderPlan& plan) {
  std::array<std::size_t, 3> next{};
  plan.mix.gap_us = o.gap_us;
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    RenderGroup& grp = plan.groups[g];
    const auto p = static_cast<std::size_t>(grp.primary);
    const auto [slot, turn] = frame.place[p][next[p]++];
    grp.slot = slot;
    grp.turn = static_cast<int>(turn);
    Stimulus s = group_stimulus(bank, o, currents[g], grp, frame.k[p], plan.cycle_us);
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

RenderPlan plan_with_kin(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                         const RenderOptions& o, const std::vector<long>& kin) {
  check_plan_inputs(bank, profile, image, o);
  RenderPlan plan;
  plan.requested_hz = o.rate_hz;
  plan.lit = lit_patterns(bank, profile, image, o);
  if (plan.lit.empty()) return plan;
  group_patterns(bank, o, kin, plan);
  const std::vector<std::vector<double>> currents = group_currents(bank, plan);
  const Frame frame = frame_for(o, currents, plan);
  build_mix(bank, o, currents, frame, plan);
  return plan;
}

RenderPlan plan_render(const PixelBank& bank, const Profile& profile, const PadIntensities& image,
                       const RenderOptions& o) {
  return plan_with_kin(bank, profile, image, o, {});
}

namespace {

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

}  // namespace

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
