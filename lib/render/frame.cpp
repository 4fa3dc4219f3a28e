#include "render/frame.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <numeric>

#include "device/device_core.hpp"
#include "device/scheduler.hpp"

namespace tp {

long frame_slots(const FrameProblem& fp, long cycle_us) {
  return static_cast<long>(std::floor(static_cast<double>(cycle_us) / fp.slot_us));
}

bool frame_at_cycle(const FrameProblem& fp, long c, Frame& f) {
  const long slots = frame_slots(fp, c);
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

std::uint64_t hyperperiod_cycles(const std::array<long, 3>& k, std::uint64_t cap) {
  std::uint64_t lcm = 1;
  for (const long kp : k)
    if (kp > 0) {
      lcm = std::lcm(lcm, static_cast<std::uint64_t>(kp));
      if (lcm > cap) return 0;
    }
  return lcm;
}

bool slip_check_fits(const FrameProblem& fp, const Frame& f) {
  const std::uint64_t lcm = hyperperiod_cycles(f.k, std::uint64_t{1} << 20);
  if (lcm == 0) return false;
  long kmax = 1;
  for (std::size_t p = 0; p < 3; ++p) kmax = std::max(kmax, f.k[p]);
  const double end =
      static_cast<double>(kmax + 2 * static_cast<long>(lcm)) * static_cast<double>(f.cycle_us);
  double pulses = 0;
  for (std::size_t p = 0; p < 3; ++p)
    if (f.k[p] > 0)
      pulses += fp.groups[p] *
                (end / (static_cast<double>(f.k[p]) * static_cast<double>(f.cycle_us)) + 1);
  return pulses <= device::kMaxCheckedPulsesHost;
}

bool utilisation_fits(const FrameProblem& fp, const Frame& f) {
  // Each pattern's (length + gap) / period rounded up in units of 2^-20
  // (device::Scheduler::utilisation_q20).
  std::uint64_t q20 = 0;
  const auto work = static_cast<std::uint64_t>(std::ceil(fp.slot_us)) << 20;
  for (std::size_t p = 0; p < 3; ++p)
    if (f.k[p] > 0) {
      const auto period =
          static_cast<std::uint64_t>(f.k[p]) * static_cast<std::uint64_t>(f.cycle_us);
      q20 += static_cast<std::uint64_t>(fp.groups[p]) * ((work + period - 1) / period);
    }
  return q20 <= device::Scheduler::kOneQ20;
}

bool electrode_loads_fit(const FrameProblem& fp, const Frame& f) {
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

bool frame_within_limits(const FrameProblem& fp, const Frame& f) {
  return slip_check_fits(fp, f) && utilisation_fits(fp, f) && electrode_loads_fit(fp, f);
}

bool pack_slots(const FrameProblem& fp, long slots, Frame& f) {
  std::array<std::size_t, 3> order = {0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return (f.k[a] > 0 ? f.k[a] : LONG_MAX) < (f.k[b] > 0 ? f.k[b] : LONG_MAX);
  });
  std::array<std::array<long, 3>, 3> g{};  // gcd of the primaries' periods
  for (std::size_t p = 0; p < 3; ++p)
    for (std::size_t q = 0; q < 3; ++q)
      if (f.k[p] > 0 && f.k[q] > 0) g[p][q] = std::gcd(f.k[p], f.k[q]);
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

bool place_groups(const FrameProblem& fp, Frame& f) {
  const long slots = frame_slots(fp, f.cycle_us);
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

bool better_frame(const Frame& a, const Frame& b) {
  if (a.score != b.score) return a.score > b.score;
  if (a.sum != b.sum) return a.sum > b.sum;
  return a.cycle_us < b.cycle_us;
}

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
    if (!frame_at_cycle(fp, c, f)) continue;
    if (best.score >= 0 && !better_frame(f, best)) continue;
    if (frame_within_limits(fp, f) && place_groups(fp, f)) best = f;
  }
  for (double c = static_cast<double>(hi) * 1.01; best.score < 0 && c <= 1e7; c *= 1.01) {
    if (frame_at_cycle(fp, static_cast<long>(c), f) && frame_within_limits(fp, f) &&
        place_groups(fp, f))
      best = f;
  }
  return best;
}

}  // namespace tp
