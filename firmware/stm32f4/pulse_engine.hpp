#pragma once
// Executes the pulses the device core emits, on time: each pulse's main phase, gap and
// balancing phase, edge by edge, from the SysTick alarm, with the DAC's next codes loaded
// during the phase before and latched on the edge.  The device core (main loop) decides
// which pulses happen; the engine only delivers them, and measures each edge on the
// microsecond clock for the monitor.
//
// Pulses leave kDelayUs after their slot, so that the first pulse after a start is as
// punctual as the rest, and never sooner after the previous pulse's start than the core's
// schedule put them (its slots: a pattern's period, or another pattern's pulse and the
// gap); each pulse's later edges follow its measured first edge, so no phase is ever
// shortened.  A shaped pulse (PulseJob::shape.n > 0) has n phases, each base x units_k
// codes for its duration, latched edge by edge the same way; at each edge the DAC's output
// is read back and compared with the phase's codes (a mismatch is an output fault).
// Stopping drops every queued pulse; a pulse that has begun completes all its phases (its
// charge must be returned), then the outputs go to 0 and output-enable low.  An output started meanwhile waits for that.

#include <cstdint>

#include "device/pulse_record.hpp"
#include "hw.hpp"
#include "output_stage.hpp"
#include "sense.hpp"

namespace tp::fw {

struct PulseJob {
  std::uint64_t slot_us = 0;  // the core's start (device time): its slot plus its slip
  std::uint16_t pattern = 0;  // its pattern's index
  std::uint32_t slip_us = 0;
  std::uint64_t start_us = 0;  // the start command's time
  std::uint8_t channels = 0;
  std::int16_t main[8] = {};     // a shaped pulse's base codes (phase k: main x units_k)
  std::int16_t balance[8] = {};  // biphasic only
  device::Shape shape;           // n == 0: biphasic (main, gap, balance)
  std::uint16_t width_us = 0, interphase_us = 0, balance_width_us = 0;
  std::uint32_t period_us = 0;  // its pattern's
  std::uint32_t step_nA = 0;
};

class PulseEngine {
 public:
  static constexpr std::uint64_t kDelayUs = 500;
  static constexpr std::uint64_t kHousekeepingUs = 1000;  // the alarm's longest sleep
  // An edge whose reading came this late is on time (the clock's read jitter).
  static constexpr std::uint64_t kJitterUs = 2;

  // early_us: how long before an edge the alarm wakes the engine, which then waits on the
  // clock for the edge's microsecond.  A few microseconds on a real MCU, whose SysTick is
  // exact; a millisecond under QEMU, where an idle CPU's virtual time advances by the
  // host's real sleeping time and so can overshoot a deadline by the host's wake-up delay.
  void init(OutputStage& stage, Clock& clock, Alarm& alarm, std::uint32_t early_us,
            std::uint32_t core_hz);

  // A board that measures: each pulse sampled before its main phase's end (a shape's
  // strongest phase), the samples kept with its record.
  void set_sense(Sense* sense) { sense_ = sense; }

  // Main loop.
  bool submit(const PulseJob& job);  // false: the queue is full (the pulse is not delivered)
  void start_output();               // output-enable high
  // See above.  Returns how many queued pulses it dropped (never delivered) and, through
  // start_us, the start command's time of the output they belonged to.
  std::uint32_t stop_output(std::uint64_t& start_us);
  void finish_output();  // the queued pulses first (a completed stimulus)
  bool pop_record(device::PulseRecord& r);
  // The same, with the pulse's samples (set_sense) and its output's start command.
  bool pop_record(device::PulseRecord& r, std::uint64_t& output_us, std::uint16_t* raw);
  // A board that measures: no pulse starts while a delivered pulse's readings are still to
  // be guarded (the main loop calls this once the core has them, after following the
  // core), so a guard that trips always stops the output before the next pulse, whatever
  // the rate; at the rates the device reports, the loop keeps up.
  void readings_done();

  // The stop input (its interrupt, above the engine's): the electrode switches are already
  // open; the queue is dropped and the pulse in flight ends with them open (it is recorded
  // and counted whole), and no output starts (start_output) until release_stop().  Main
  // loop: take_stop() reports the press once, with its time; release_stop() clears the
  // latch when a new session's output starts, unless another press is still to be taken.
  void stop_input();
  bool take_stop(std::uint64_t& at_us);
  void release_stop();
  bool stop_latched() const { return stop_latched_; }
  std::uint32_t lost_pulses() const { return lost_; }
  // Shaped-pulse edges whose read-back codes were not the phase's (an output fault).
  std::uint32_t readback_faults() const { return readback_faults_; }

  // The SysTick interrupt.
  void on_alarm();

 private:
  enum class Phase : std::uint8_t { idle, main, gap, balance, shaped };
  static constexpr std::uint32_t kJobs = 32, kRecords = 8;
  void sample_if_measured(int edge_index);  // before edge edge_index
  void drop_latched();
  void edge(std::uint64_t scheduled, int index);
  void finish_pulse();
  void shaped_edge(std::uint64_t now, std::uint64_t& next, bool& more);
  void load_shape_phase(const PulseJob& job, std::size_t k);  // zeros when k == n
  void check_shape_phase();  // the read-back codes against the phase's (expected_)

  OutputStage* stage_ = nullptr;
  Clock* clock_ = nullptr;
  Alarm* alarm_ = nullptr;
  std::uint32_t early_us_ = 2;
  std::uint32_t spins_per_us_ = 56;      // the wait loop's speed, as last measured
  std::uint32_t max_spins_per_us_ = 84;  // its fastest possible speed (2 cycles a turn)
  PulseJob jobs_[kJobs];
  volatile std::uint32_t job_head_ = 0, job_tail_ = 0;
  device::PulseRecord records_[kRecords];
  std::uint16_t samples_[kRecords][kSenseChannels] = {};
  std::uint64_t record_output_us_[kRecords] = {};
  Sense* sense_ = nullptr;
  std::uint16_t sampled_[kSenseChannels] = {};  // the pulse in flight's
  std::uint8_t sense_edge_ = 1;                  // the edge it is sampled before
  volatile bool stop_latched_ = false, stop_event_ = false;
  std::uint64_t stop_at_us_ = 0;
  volatile std::uint32_t unguarded_ = 0;  // measured pulses whose readings the core lacks
  volatile std::uint32_t rec_head_ = 0, rec_tail_ = 0;
  volatile std::uint32_t records_lost_ = 0;
  std::uint32_t lost_ = 0;
  // Interrupt state.
  Phase phase_ = Phase::idle;
  bool loaded_ = false;          // the head job's main codes are in the DAC's inputs
  PulseJob current_;             // the pulse in flight (out of the queue)
  std::uint64_t exec_us_ = 0;    // its first edge, scheduled
  std::uint64_t edges_[device::kMaxPhases + 1] = {};  // its edges, measured
  std::uint8_t shape_k_ = 0;          // a shaped pulse's phase in flight
  std::uint64_t shape_end_us_ = 0;    // and that phase's end, scheduled
  std::int16_t loaded_codes_[8] = {};  // the codes loaded for the next edge
  volatile std::uint32_t readback_faults_ = 0;
  std::int16_t latched_main_[8] = {}, latched_balance_[8] = {};  // read back from the DAC
  volatile bool stop_requested_ = false;
  volatile bool finish_requested_ = false;
  volatile bool restart_pending_ = false;
  std::uint64_t last_start_us_ = 0;   // the previous pulse's measured start
  std::uint64_t last_slot_us_ = 0;    // and its slot
  std::uint64_t last_output_us_ = 0;  // and its output's start command
  std::uint64_t last_end_us_ = 0;     // and its measured end
  std::uint64_t last_length_us_ = 0;  // and its configured length
  std::uint16_t last_pattern_ = 0;
  bool have_last_start_ = false;
  void outputs_off();
};

}  // namespace tp::fw
