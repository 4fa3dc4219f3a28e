#pragma once
// The device's pulse scheduler (docs/protocol.md, "Scheduling"): several patterns, each
// periodic (its period, its phase from the start), share one output stage.  Portable: no
// OS calls, no allocation (fixed tables of kMaxPatterns), so the emulators and the
// firmware run exactly this code, and the host checks a table with it before sending it.
//
// The rule: pulses go in the order of their nominal slots (start + phase + k x period;
// equal slots: the lower pattern index first).  A pulse starts at its slot, or later when
// the previous pulse's end plus the gap has not yet come: it is deferred (its slip), never
// dropped.  In a table of one pattern nothing is ever deferred (its own period holds the
// pulse and its off time: phase_fits).
//
// Bounded slip.  With every pulse followed by its gap (service time L + gap) and
// utilisation U = sum (L + gap) / period <= 1, this is a first-come-first-served queue:
// the work ahead of a pulse of pattern p, over any busy stretch, is at most
// sum over q != p of (L_q + gap) (each other pattern has at most one slot more than its
// rate gives; p's own earlier pulses are within its rate), so no slip exceeds that sum.
// Where that sum is above the bound, worst_slip simulates the schedule exactly over its
// first phase_max + 2 hyperperiods: from the second hyperperiod on, the backlog at its
// start can only shrink (Lindley's recursion with U <= 1), so no later slip is larger.
// Removing pulses (a pattern's count reached) never increases another's wait.

#include <cstdint>

namespace tp::device {

inline constexpr std::uint16_t kMaxPatterns = 256;

struct ScheduledPulse {
  std::uint16_t pattern = 0;
  std::uint64_t slot_us = 0;   // nominal: start + phase + k x period
  std::uint64_t start_us = 0;  // when it starts: slot + slip
};

class Scheduler {
 public:
  // A table of n patterns (1 to kMaxPatterns) with this gap between pulses.
  void set_table(std::uint16_t n, std::uint16_t gap_us);
  // Pattern i's timing: length_us = width + interphase + balance width; max_pulses 0: no
  // limit.  Callers check each value's range first (period > length, phase < period).
  void set_timing(std::uint16_t i, std::uint32_t period_us, std::uint32_t phase_us,
                  std::uint32_t length_us, std::uint32_t max_pulses);
  std::uint16_t patterns() const { return n_; }
  std::uint16_t gap_us() const { return gap_; }

  // Utilisation sum (length + gap) / period, conservatively in units of 2^-20 (each
  // term rounded up); a table of one pattern counts its length only.
  std::uint64_t utilisation_q20() const;
  static constexpr std::uint64_t kOneQ20 = std::uint64_t{1} << 20;

  // The largest slip any pulse of the table can have, from the closed bound or an exact
  // simulation of at most max_pulses pulses; UINT32_MAX when neither bounds it.  Leaves the
  // scheduler reset (call reset before a run).  Needs utilisation <= 1.
  std::uint32_t worst_slip(std::uint32_t limit_us, std::uint32_t max_pulses);

  // Starts a run at t0: each pattern's first slot at t0 + phase.
  void reset(std::uint64_t t0_us);
  bool done() const { return heap_n_ == 0; }  // every pattern has delivered its count
  ScheduledPulse next() const;                // needs !done()
  void delivered();                           // the pulse next() gave has gone
  // Slots more than max_late_us before now are skipped (not delivered, not counted): an
  // emulator whose process was descheduled never delivers a burst.
  void skip_late(std::uint64_t now_us, std::uint64_t max_late_us);
  std::uint32_t count(std::uint16_t i) const { return count_[i]; }

 private:
  bool before(std::uint16_t a, std::uint16_t b) const {
    return next_[a] < next_[b] || (next_[a] == next_[b] && a < b);
  }
  void sift_down(std::uint16_t at);
  void heapify();

  std::uint16_t n_ = 0, gap_ = 0;
  std::uint32_t period_[kMaxPatterns] = {};
  std::uint32_t phase_[kMaxPatterns] = {};
  std::uint32_t length_[kMaxPatterns] = {};
  std::uint32_t max_[kMaxPatterns] = {};
  // A run's state.
  std::uint64_t next_[kMaxPatterns] = {};  // the next slot
  std::uint32_t count_[kMaxPatterns] = {};
  std::uint16_t heap_[kMaxPatterns] = {};  // patterns still to deliver, earliest slot first
  std::uint16_t heap_n_ = 0;
  std::uint64_t free_us_ = 0;  // the earliest start the previous pulse allows
};

}  // namespace tp::device
