#include "pulse_engine.hpp"

#include <algorithm>

namespace tp::fw {
namespace {
const std::int16_t kZeros[8] = {};
}

void PulseEngine::init(OutputStage& stage, Clock& clock, Alarm& alarm, std::uint32_t early_us,
                       std::uint32_t core_hz) {
  early_us_ = early_us;
  spins_per_us_ = core_hz / 3000000u;  // three cycles a turn on a Cortex-M4
  // Two cycles a turn is the fastest the loop can go: a measurement above that is a
  // misreading (a clock read that took less than a tick), and trusting it would make the
  // next wait overshoot its edge by up to 8 x the time left.
  max_spins_per_us_ = core_hz / 2000000u;
  if (max_spins_per_us_ < 1) max_spins_per_us_ = 1;
  stage_ = &stage;
  clock_ = &clock;
  alarm_ = &alarm;
  const std::uint64_t now = clock.now_us();
  alarm.set(now + kHousekeepingUs, now);
}

bool PulseEngine::submit(const PulseJob& job) {
  reg::CriticalSection cs;
  if (job_head_ - job_tail_ == kJobs) {
    ++lost_;
    return false;
  }
  jobs_[job_head_ % kJobs] = job;
  job_head_ = job_head_ + 1;
  // The alarm may be set for later than this pulse (housekeeping): let the engine look now.
  const std::uint64_t now = clock_->now_us();
  alarm_->set(now, now);
  return true;
}

void PulseEngine::start_output() {
  reg::CriticalSection cs;
  finish_requested_ = false;  // a completed output's last pulses are delivered all the same
  if (stop_latched_) return;  // the stop input holds the switches open
  if (stop_requested_)
    restart_pending_ = true;  // after the stopped output's last pulse has ended
  else
    stage_->enable(true);
}

std::uint32_t PulseEngine::stop_output(std::uint64_t& start_us) {
  reg::CriticalSection cs;
  const std::uint32_t dropped = job_head_ - job_tail_;
  if (dropped != 0) start_us = jobs_[job_tail_ % kJobs].start_us;
  job_head_ = job_tail_;  // drop the queue (an in-flight pulse is not in it)
  loaded_ = false;
  finish_requested_ = false;
  restart_pending_ = false;
  if (phase_ == Phase::idle) {
    outputs_off();
  } else {
    stop_requested_ = true;  // after this pulse's balancing phase
  }
  return dropped;
}

void PulseEngine::finish_output() {
  reg::CriticalSection cs;
  if (phase_ == Phase::idle && job_head_ == job_tail_)
    outputs_off();
  else
    finish_requested_ = true;
}

void PulseEngine::outputs_off() {
  // Atomic against the stop input's interrupt: it must not come between the latch's test
  // and output-enable below.
  reg::CriticalSection cs;
  stage_->load(kZeros, 8);
  stage_->latch();
  stage_->enable(false);
  stop_requested_ = false;
  finish_requested_ = false;
  loaded_ = false;
  if (restart_pending_) {  // a new output started while the old one's last pulse ended
    restart_pending_ = false;
    if (!stop_latched_) stage_->enable(true);
  }
}

void PulseEngine::stop_input() {
  stage_->enable(false);
  stop_latched_ = true;
  stop_event_ = true;
  stop_at_us_ = clock_->now_us();  // safe here: now_us() masks every interrupt
}

bool PulseEngine::take_stop(std::uint64_t& at_us) {
  if (!stop_event_) return false;  // the loop's every turn: no critical section
  reg::CriticalSection cs;
  const bool event = stop_event_;
  stop_event_ = false;
  at_us = stop_at_us_;
  return event;
}

void PulseEngine::release_stop() {
  reg::CriticalSection cs;
  if (!stop_event_) stop_latched_ = false;
}

void PulseEngine::sample_if_measured(int edge_index) {
  if (sense_ && edge_index == sense_edge_) sense_->sample(sampled_, current_.channels);
}

bool PulseEngine::pop_record(device::PulseRecord& r) {
  std::uint16_t raw[kSenseChannels];
  std::uint64_t output_us = 0;
  return pop_record(r, output_us, raw);
}

void PulseEngine::readings_done() {
  reg::CriticalSection cs;
  if (unguarded_ != 0) unguarded_ = unguarded_ - 1;
  const std::uint64_t now = clock_->now_us();
  alarm_->set(now, now);  // a pulse may be waiting for it
}

bool PulseEngine::pop_record(device::PulseRecord& r, std::uint64_t& output_us,
                             std::uint16_t* raw) {
  reg::CriticalSection cs;
  if (rec_head_ == rec_tail_) return false;
  const std::uint32_t k = rec_tail_ % kRecords;
  r = records_[k];
  std::copy(samples_[k], samples_[k] + kSenseChannels, raw);
  output_us = record_output_us_[k];
  rec_tail_ = rec_tail_ + 1;
  return true;
}

namespace {
// n turns of a loop of two instructions that touches no peripheral.
void spin(std::uint32_t n) {
  std::uint32_t k = n + 1;
  __asm volatile("1: subs %0, %0, #1\n bne 1b" : "+r"(k)::"cc");
}
}  // namespace

void PulseEngine::edge(std::uint64_t scheduled, int index) {
  // The alarm came up to early_us before the edge: wait for the edge's microsecond.  Most
  // of the wait is the plain loop, an eighth of what is left each time at its measured
  // speed (reading the clock is a peripheral access, slow under QEMU, whose speed per
  // instruction may also change: -icount shift=auto); the last 16 us only read the clock,
  // faster than it ticks, so the reading that releases the edge is its microsecond.
  std::uint64_t now = clock_->now_us();
  for (std::uint32_t i = 0; now < scheduled && i < 100000u; ++i) {
    const std::uint64_t left = scheduled - now;
    if (left >= 16) {
      const auto n = static_cast<std::uint32_t>(left / 8 * spins_per_us_);
      const std::uint64_t before = now;
      spin(n);
      now = clock_->now_us();
      const std::uint64_t took = now - before;
      if (took > 0) {
        const std::uint64_t rate = n / took;
        spins_per_us_ = static_cast<std::uint32_t>(rate < 1                   ? 1
                                                   : rate > max_spins_per_us_ ? max_spins_per_us_
                                                                              : rate);
      }
    } else {
      // The last microseconds: the counter alone, a few instructions a reading (a full
      // now_us() took ~30 under QEMU, nearly a microsecond of its core, so the releasing
      // reading could come 2 us after the edge's microsecond).
      const auto target = static_cast<std::uint32_t>(scheduled);
      std::uint32_t c = Clock::counter();
      for (std::uint32_t k = 0; static_cast<std::int32_t>(c - target) < 0 && k < 1000000u; ++k)
        c = Clock::counter();
      const auto d = static_cast<std::int32_t>(c - target);
      now = d >= 0 ? scheduled + static_cast<std::uint32_t>(d) : clock_->now_us();
    }
  }
  // The edge's time is the reading that released it: the LDAC pulse follows that reading
  // by the same few instructions at every edge.
  edges_[index] = now;
  stage_->latch();
}

void PulseEngine::on_alarm() {
  std::uint64_t next = clock_->now_us() + kHousekeepingUs;
  // Every edge that is due, then the alarm for the next one (or for housekeeping).
  bool more = true;
  for (int guard = 0; guard < 8 && more; ++guard) {
    const std::uint64_t now = clock_->now_us();
    more = false;
    if (phase_ == Phase::idle) {
      // The stop input latched: nothing more starts; the main loop drops the queue.  Nor
      // while the last pulse's readings are unguarded (readings_done).
      if (job_head_ == job_tail_ || stop_latched_ || unguarded_ != 0) break;
      const PulseJob& job = jobs_[job_tail_ % kJobs];
      if (!loaded_) {
        if (job.shape.n != 0)
          load_shape_phase(job, 0);
        else
          stage_->load(job.main, job.channels);
        loaded_ = true;
      }
      // Its slot plus the delay, but never sooner after the previous pulse's start than
      // the core's schedule had it: pulses that queued up behind a late one (a new output
      // waiting for a stopped one's last balancing phase) never come in a burst, nor closer
      // to another pattern's than its pulse and the gap.
      std::uint64_t due = job.slot_us + kDelayUs;
      // Within one output, as the core spaced them; a new output's first pulse, at least
      // its period after the previous output's last (lateness never carries over).
      if (have_last_start_ && job.start_us == last_output_us_ && job.slot_us >= last_slot_us_) {
        const std::uint64_t spacing = job.slot_us - last_slot_us_;
        due = std::max(due, last_start_us_ + spacing);
        // Another pattern's pulse: never closer to this one's measured end than the core
        // left between them (the table's gap), though that edge came a tick or two late.
        if (job.pattern != last_pattern_ && spacing >= last_length_us_)
          due = std::max(due, last_end_us_ + (spacing - last_length_us_));
      } else if (have_last_start_)
        due = std::max(due, last_start_us_ + job.period_us);
      if (now + early_us_ < due) {
        next = std::min(next, due - early_us_);
        break;
      }
      current_ = job;
      job_tail_ = job_tail_ + 1;
      loaded_ = false;
      edge(due, 0);
      // The later edges follow the measured first one: a late start never shortens a phase.
      exec_us_ = edges_[0];
      // The no-burst rule counts from when this pulse started, unless that was only the
      // clock's reading jitter after its due time: propagating a tick of jitter to every
      // later pulse would make them drift later and later (a tick every other pulse).
      last_start_us_ = edges_[0] <= due + kJitterUs ? due : edges_[0];
      last_slot_us_ = current_.slot_us;
      last_output_us_ = current_.start_us;
      last_pattern_ = current_.pattern;
      last_length_us_ =
          std::uint64_t{current_.width_us} + current_.interphase_us + current_.balance_width_us;
      have_last_start_ = true;
      // Sampled before the end of the main phase, or of a shape's strongest.
      sense_edge_ = static_cast<std::uint8_t>(current_.shape.strongest() + 1);
      if (current_.shape.n != 0) {
        last_length_us_ = 0;
        for (std::size_t k = 0; k < current_.shape.n; ++k)
          last_length_us_ += current_.shape.duration_us[k];
        check_shape_phase();
        shape_k_ = 0;
        shape_end_us_ = exec_us_ + current_.shape.duration_us[0];
        phase_ = Phase::shaped;
        load_shape_phase(current_, 1);
        more = true;
        continue;
      }
      stage_->output(latched_main_, current_.channels);
      phase_ = Phase::main;
      stage_->load(current_.interphase_us ? kZeros : current_.balance, current_.channels);
      more = true;
      continue;
    }
    if (phase_ == Phase::shaped) {
      shaped_edge(now, next, more);
      if (!more) break;
      continue;
    }
    const PulseJob& job = current_;
    const std::uint64_t t_gap = exec_us_ + job.width_us;
    const std::uint64_t t_bal = t_gap + job.interphase_us;
    const std::uint64_t t_end = t_bal + job.balance_width_us;
    const std::uint64_t due = phase_ == Phase::main ? t_gap : phase_ == Phase::gap ? t_bal : t_end;
    if (now + early_us_ < due) {
      next = std::min(next, due - early_us_);
      break;
    }
    if (phase_ == Phase::main) sample_if_measured(1);
    if (phase_ == Phase::main && job.interphase_us) {  // main -> gap
      edge(due, 1);
      phase_ = Phase::gap;
      stage_->load(job.balance, job.channels);
    } else if (phase_ != Phase::balance) {  // main or gap -> balance
      edge(due, phase_ == Phase::main ? 1 : 2);
      if (phase_ == Phase::main) edges_[2] = edges_[1];
      stage_->output(latched_balance_, job.channels);
      phase_ = Phase::balance;
      stage_->load(kZeros, job.channels);
    } else {  // balance -> idle
      edge(due, 3);
      finish_pulse();
    }
    more = true;
  }
  // Edges still due when the guard ran out: at once, not after housekeeping's sleep.
  if (more) next = clock_->now_us();
  alarm_->set(next, clock_->now_us());
}

void PulseEngine::load_shape_phase(const PulseJob& job, std::size_t k) {
  device::shape_codes(job.main, job.channels, job.shape, k, loaded_codes_);
  stage_->load(loaded_codes_, job.channels);
}

void PulseEngine::check_shape_phase() {
  std::int16_t out[8];
  stage_->output(out, current_.channels);
  for (std::size_t c = 0; c < current_.channels; ++c)
    if (out[c] != loaded_codes_[c]) {
      readback_faults_ = readback_faults_ + 1;
      return;
    }
}

// A shaped pulse's next edge, when due: the end of phase k (the start of k + 1, whose codes
// were loaded during phase k), checked by read-back, then phase k + 2's codes (or zeros)
// loaded; the last edge ends the pulse.  more: an edge was taken.
void PulseEngine::shaped_edge(std::uint64_t now, std::uint64_t& next, bool& more) {
  const PulseJob& job = current_;
  const std::uint64_t due = shape_end_us_;
  if (now + early_us_ < due) {
    next = std::min(next, due - early_us_);
    more = false;
    return;
  }
  const std::size_t k = shape_k_ + 1u;  // the edge's index: phase k starts (or the end)
  sample_if_measured(static_cast<int>(k));
  edge(due, static_cast<int>(k));
  check_shape_phase();
  more = true;
  if (k >= job.shape.n) {
    finish_pulse();
    return;
  }
  shape_k_ = static_cast<std::uint8_t>(k);
  // Each phase's end: the measured first edge plus the durations so far (never shortened).
  shape_end_us_ = due + job.shape.duration_us[k];
  load_shape_phase(job, k + 1);
}

void PulseEngine::finish_pulse() {
  const PulseJob& job = current_;
  if (rec_head_ - rec_tail_ < kRecords) {
    device::PulseRecord& r = records_[rec_head_ % kRecords];
    r = device::PulseRecord{};
    r.pattern = job.pattern;
    r.t_us = job.slot_us - job.start_us;
    r.slip_us = job.slip_us;
    r.channels = job.channels;
    // The codes the driver wrote and latched for each phase (its copy of the DAC's
    // registers, decoded from the words it sent): the monitor shows its encoding.
    std::copy(latched_main_, latched_main_ + job.channels, r.main);
    std::copy(latched_balance_, latched_balance_ + job.channels, r.balance);
    r.step_nA = job.step_nA;
    r.width_us = job.width_us;
    r.interphase_us = job.interphase_us;
    r.balance_width_us = job.balance_width_us;
    r.measured = true;
    r.start_us = edges_[0] - job.start_us;
    r.measured_width_us = static_cast<std::uint32_t>(edges_[1] - edges_[0]);
    r.measured_interphase_us = static_cast<std::uint32_t>(edges_[2] - edges_[1]);
    r.measured_balance_us = static_cast<std::uint32_t>(edges_[3] - edges_[2]);
    if (job.shape.n != 0) {  // its phases as delivered (codes checked by read-back)
      r.shape = job.shape;
      std::copy(job.main, job.main + job.channels, r.main);  // the base codes
      r.width_us = r.interphase_us = r.balance_width_us = 0;
      r.measured_width_us = r.measured_interphase_us = r.measured_balance_us = 0;
      std::fill(r.balance, r.balance + job.channels, std::int16_t{0});
      for (std::size_t k = 0; k < job.shape.n; ++k)
        r.measured_duration_us[k] = static_cast<std::uint32_t>(edges_[k + 1] - edges_[k]);
    }
    if (sense_) {  // its samples, kept with it; and no next pulse until they are guarded
      std::copy(sampled_, sampled_ + kSenseChannels, samples_[rec_head_ % kRecords]);
      record_output_us_[rec_head_ % kRecords] = job.start_us;
      unguarded_ = unguarded_ + 1;
    }
    r.dropped_before = records_lost_;
    records_lost_ = 0;
    rec_head_ = rec_head_ + 1;
  } else {
    records_lost_ = records_lost_ + 1;
  }
  last_end_us_ = job.shape.n != 0 ? edges_[job.shape.n] : edges_[3];
  phase_ = Phase::idle;
  if (stop_requested_ || (finish_requested_ && job_head_ == job_tail_)) outputs_off();
}

}  // namespace tp::fw
