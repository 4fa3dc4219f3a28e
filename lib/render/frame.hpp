#pragma once
// The frame scheduler (docs/rendering.md, "The pulse budget"): the groups (device
// patterns) take turns in a cycle of C us holding J = floor(C / (L + gap)) slots, L the
// pulse's length.  Primary p's period is k_p x C: each of its groups fires in one slot of
// every k_p-th cycle, at a residue r (the cycles n = r modulo k_p).  Two groups in one slot,
// of periods k and k' at residues r and r', meet iff r = r' modulo gcd(k, k'), so no two
// pulses ever meet and nothing is deferred.  plan_frame chooses C and the k_p.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace tp {

// What the frame must hold: each primary's groups and requested period, one slot's
// length, and (with loads) each electrode's RMS and mean current over the groups.
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
inline constexpr long kMaxPackingWork = 20'000'000;

// One frame: a cycle, each primary's period in cycles (0: no groups); scored by the
// smallest achieved over requested rate, then their sum, then the shorter cycle.
struct Frame {
  long cycle_us = 0;
  std::array<long, 3> k{};
  double score = -1, sum = 0;  // score < 0: no frame
  // Each primary's groups, in order: (slot, residue): the group fires in that slot of the
  // cycles whose number is the residue modulo k.
  std::array<std::vector<std::pair<int, long>>, 3> place;
  bool packed = false;  // slots shared between primaries (pack_slots)
};

// The slots a cycle of cycle_us holds.
long frame_slots(const FrameProblem& fp, long cycle_us);

// The frame's periods for cycle c: each primary's smallest k with k x c at least its
// requested period, and the score.  False when the groups' shares (1/k of a slot each)
// exceed the slots, a period would pass 10 s, or no slot fits.
bool frame_at_cycle(const FrameProblem& fp, long c, Frame& f);

// The cycles after which every primary's groups fire again: the lcm of the k_p (1 when no
// primary has groups), or 0 when that is above `cap`.
std::uint64_t hyperperiod_cycles(const std::array<long, 3>& k, std::uint64_t cap);

// The limits on a frame's periods: the device's exact slip check can run over it (its
// pulses in max phase + 2 hyperperiods, device::kMaxCheckedPulsesHost), the device's
// utilisation as it sums it (in units of 2^-20) is at most 1, and (fp.loads) each
// electrode's RMS and mean current are within fp's bounds.
bool slip_check_fits(const FrameProblem& fp, const Frame& f);
bool utilisation_fits(const FrameProblem& fp, const Frame& f);
bool electrode_loads_fit(const FrameProblem& fp, const Frame& f);
bool frame_within_limits(const FrameProblem& fp, const Frame& f);

// The groups in slots that primaries may share (residues that never meet): first fit, the
// primaries of shortest period first; false when some group finds no place or
// kMaxPackingWork is reached.
bool pack_slots(const FrameProblem& fp, long slots, Frame& f);
// The groups' places: each primary its own slots when they suffice (not f.packed), else
// pack_slots.
bool place_groups(const FrameProblem& fp, Frame& f);

// a before b: the higher score, then the higher sum, then the shorter cycle.
bool better_frame(const Frame& a, const Frame& b);

// The best frame that satisfies every limit and places every group: every whole cycle from
// one slot up to the longest requested period (or the slots every group needs alone),
// then, while none fits, longer ones by 1 %, up to 10 s.  Its score is below 0 when none
// does.
Frame plan_frame(const FrameProblem& fp);

}  // namespace tp
