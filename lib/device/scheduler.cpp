#include "device/scheduler.hpp"

namespace tp::device {
namespace {

std::uint64_t gcd64(std::uint64_t a, std::uint64_t b) {
  while (b != 0) {
    const std::uint64_t t = a % b;
    a = b;
    b = t;
  }
  return a;
}

}  // namespace

void Scheduler::set_table(std::uint16_t n, std::uint16_t gap_us) {
  n_ = n > kMaxPatterns ? kMaxPatterns : n;
  gap_ = gap_us;
  for (std::uint16_t i = 0; i < n_; ++i) {
    period_[i] = 0;
    phase_[i] = 0;
    length_[i] = 0;
    max_[i] = 0;
  }
  heap_n_ = 0;
}

void Scheduler::set_timing(std::uint16_t i, std::uint32_t period_us, std::uint32_t phase_us,
                           std::uint32_t length_us, std::uint32_t max_pulses) {
  if (i >= n_) return;
  period_[i] = period_us;
  phase_[i] = phase_us;
  length_[i] = length_us;
  max_[i] = max_pulses;
}

std::uint64_t Scheduler::utilisation_q20() const {
  const std::uint64_t gap = n_ > 1 ? gap_ : 0;
  std::uint64_t u = 0;
  for (std::uint16_t i = 0; i < n_; ++i) {
    if (period_[i] == 0) continue;  // not yet set
    const std::uint64_t work = (std::uint64_t{length_[i]} + gap) << 20;
    u += (work + period_[i] - 1) / period_[i];
  }
  return u;
}

std::uint32_t Scheduler::worst_slip(std::uint32_t limit_us, std::uint32_t max_pulses) {
  if (n_ <= 1) return 0;
  // The closed bound: sum over the other patterns of (length + gap), largest for the
  // pattern of the shortest pulse.
  std::uint64_t sum = 0, least = UINT64_MAX, hyper = 1;
  std::uint32_t phase_max = 0;
  for (std::uint16_t i = 0; i < n_; ++i) {
    if (period_[i] == 0) return UINT32_MAX;  // a pattern not yet set
    const std::uint64_t w = std::uint64_t{length_[i]} + gap_;
    sum += w;
    if (w < least) least = w;
    if (phase_[i] > phase_max) phase_max = phase_[i];
    // The hyperperiod, given up once it is beyond any run (2^36 us: 19 hours).
    if (hyper != 0) {
      hyper = hyper / gcd64(hyper, period_[i]) * period_[i];
      if (hyper > (std::uint64_t{1} << 36)) hyper = 0;
    }
  }
  const std::uint64_t bound = sum - least;
  if (bound <= limit_us) return static_cast<std::uint32_t>(bound);
  if (hyper == 0) return UINT32_MAX;
  // The exact schedule over [0, phase_max + 2 H), if it is short enough.
  const std::uint64_t end = phase_max + 2 * hyper;
  std::uint64_t pulses = 0;
  for (std::uint16_t i = 0; i < n_; ++i) pulses += (end - phase_[i]) / period_[i] + 1;
  if (pulses > max_pulses) return UINT32_MAX;
  std::uint32_t saved[kMaxPatterns];
  for (std::uint16_t i = 0; i < n_; ++i) {
    saved[i] = max_[i];
    max_[i] = 0;
  }
  reset(0);
  std::uint64_t worst = 0;
  while (!done()) {
    const ScheduledPulse p = next();
    if (p.slot_us >= end) break;
    if (p.start_us - p.slot_us > worst) worst = p.start_us - p.slot_us;
    delivered();
  }
  for (std::uint16_t i = 0; i < n_; ++i) max_[i] = saved[i];
  reset(0);
  return worst > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(worst);
}

void Scheduler::reset(std::uint64_t t0_us) {
  heap_n_ = 0;
  for (std::uint16_t i = 0; i < n_; ++i) {
    next_[i] = t0_us + phase_[i];
    count_[i] = 0;
    if (period_[i] != 0) heap_[heap_n_++] = i;
  }
  free_us_ = t0_us;
  heapify();
}

ScheduledPulse Scheduler::next() const {
  const std::uint16_t p = heap_[0];
  ScheduledPulse s;
  s.pattern = p;
  s.slot_us = next_[p];
  s.start_us = next_[p] > free_us_ ? next_[p] : free_us_;
  return s;
}

void Scheduler::delivered() {
  const ScheduledPulse s = next();
  const std::uint16_t p = s.pattern;
  free_us_ = s.start_us + length_[p] + (n_ > 1 ? gap_ : 0);
  ++count_[p];
  if (max_[p] != 0 && count_[p] >= max_[p]) {  // done: out of the heap
    heap_[0] = heap_[--heap_n_];
  } else {
    next_[p] += period_[p];
  }
  if (heap_n_ > 0) sift_down(0);
}

void Scheduler::skip_late(std::uint64_t now_us, std::uint64_t max_late_us) {
  bool moved = false;
  for (std::uint16_t k = 0; k < heap_n_; ++k) {
    const std::uint16_t p = heap_[k];
    if (now_us > next_[p] + max_late_us) {
      const std::uint64_t late = now_us - max_late_us - next_[p];
      next_[p] += (late / period_[p] + 1) * period_[p];
      moved = true;
    }
  }
  if (moved) heapify();
}

void Scheduler::sift_down(std::uint16_t at) {
  while (true) {
    const std::uint32_t l = 2u * at + 1, r = l + 1;
    std::uint16_t best = at;
    if (l < heap_n_ && before(heap_[l], heap_[best])) best = static_cast<std::uint16_t>(l);
    if (r < heap_n_ && before(heap_[r], heap_[best])) best = static_cast<std::uint16_t>(r);
    if (best == at) return;
    const std::uint16_t t = heap_[at];
    heap_[at] = heap_[best];
    heap_[best] = t;
    at = best;
  }
}

void Scheduler::heapify() {
  for (std::uint16_t k = heap_n_ / 2; k-- > 0;) sift_down(k);
}

}  // namespace tp::device
