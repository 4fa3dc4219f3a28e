#pragma once
// stimctl's run: identify the device, check the stimulus and the device against the
// host's limits, stop any output the device is still running for another (dead) host,
// configure a new session, set weights, start, keep the session's watchdog fed, and stop
// the output however the run ends: the stimulus completes, --duration passes, the live
// input ends, a signal arrives, or anything fails.

#include <atomic>
#include <csignal>
#include <functional>
#include <string>
#include <vector>

#include "host/stimulator.hpp"
#include "pulse/mix.hpp"
#include "host/stop.hpp"
#include "pulse/stimulus.hpp"

namespace tp::host {

class FrameSource;  // host/live.hpp

// While the output runs, about every 0.25 s (stimctl's progress line).
struct SessionProgress {
  double seconds = 0;         // since the start
  double expected_s = 0;      // when the device should be done (live: its pulse budget's end)
  std::uint32_t pulses = 0;   // delivered so far, per the device
  double scheduled = 0;       // pulses scheduled
  std::uint32_t frames = 0;   // live frames taken
  // Protocol 7, a device that measures: each channel's last reading (empty otherwise).
  std::vector<device::ChannelMeasurement> measured;
};

struct SessionOptions {
  double duration_s = -1.0;  // stop after this long (< 0: the stimulus' own duration; live
                             // mode: until the input ends, at most limits.max_duration_s)
  bool live = false;         // after starting, take live frames (host/live.hpp) from
  FrameSource* frames = nullptr;  // here (required in live mode): JSON lines on a file
                                  // descriptor (stimctl), or a queue in memory (Python)
  std::string latency_log;  // live mode: "n t_ns" per update sent (n from 1; benchmarks)
  StimulusLimits limits;    // the host's limits
  // A stop from outside (host/stop.hpp): a signal's flag, the caller's StopSource, or both.
  // The output stops; the report's end says why, its exit code is 128 + the signal, or 0
  // for the caller's stop (the caller decides).
  StopToken stop;
  std::function<void(const SessionProgress&)> progress;
  // Protocol 7: called with each channel's last reading whenever the session reads them
  // (with each progress, when a guard stops the output, at the end).
  std::function<void(const std::vector<device::ChannelMeasurement>&)> measurements;
  // A probe (stimctl --check-impedance): a guard of the device stopping the output ends the
  // run (its end says which), not a failure; the readings are in the report.
  bool probe = false;
  // Protocol 7, a device that measures: a pad's lost contact pauses only the patterns that
  // drive it, delivered at probe_mA until a probe finds the contact again (stimctl
  // --contact-loss suspend); false: the whole output stops (the device's default).
  bool suspend_on_contact_loss = false;
  double probe_mA = 0.05;
  // Protocol 7: hold each pattern's pulse energy against its reference impedances as the
  // skin changes (stimctl --hold-sensation; host/hold.hpp).  Not with live mode.
  bool hold_sensation = false;
};

struct SessionReport {
  std::string port;
  std::string end;           // why the output stopped
  int exit_code = 0;         // 0, or 128 + signal
  bool started = false;      // the output was started
  bool preempted = false;    // the device was running another session: stopped first
  std::uint32_t pulses = 0;  // delivered, per the device
  double scheduled = 0;      // pulses the stimulus scheduled (cut by --duration; live: the
                             // budget): on completion, the device must have delivered them
  std::uint32_t weight_frames = 0;  // live frames taken (folded ones included)
  double peak_mA = 0.0;  // largest |current| sent to the device (as the DAC makes it)
  double seconds = 0.0;
  int retransmissions = 0;
  // The device's receiver at the end (status): damaged frames, bytes with line errors,
  // bytes lost to overruns.
  std::uint32_t rx_errors = 0, line_errors = 0, overruns = 0;
  device::Capabilities caps;
  // Protocol 7, a device that measures: each channel's last reading at the end.
  std::vector<device::ChannelMeasurement> measured;
  std::uint32_t suspended_pulses = 0;  // delivered at the probe while a pad had no contact
  double hold_headroom = 0;  // --hold-sensation: the ceiling over each amplitude (0: not held)
};

// What a session sends to a device of these capabilities, once every check is made: the
// stimulus, its duration, the device's capabilities and the stimulus against them (the
// host's limits narrowed to the device's, the codes as the DAC makes them, the loads, the
// timing).  Nothing is sent: bad input names the first limit broken.  A program checks a
// whole procedure with it before its first output (calibrate: every trial at its ceiling).
struct SessionPlan {
  device::Capabilities caps;
  StimulusLimits limits;              // the host's, narrowed to the device's
  bool table = false;                 // protocol 4's table, else one configuration
  device::PulseConfig single;         // a single stimulus's configuration
  std::vector<std::int16_t> codes;    // pattern 0's codes
  std::vector<device::PatternTiming> timings;          // a table's, one per pattern
  std::vector<std::vector<std::int16_t>> table_codes;  // a table's, one per pattern
  double pulses = 0;                  // scheduled, over every pattern
  double expected_s = 0;              // when the device should be done
};
SessionPlan plan_session(const device::Capabilities& caps, const Mix& m,
                         const SessionOptions& opt);

// Refuses (bad input, naming both values) a device the host cannot drive safely: a
// watchdog longer than kMaxDeviceWatchdogMs or shorter than kMinDeviceWatchdogMs, more
// channels than the protocol carries.
void check_device(const device::Capabilities& caps);

// The device's own check of the codes it is sent (device::ChannelLoad, in integers): each
// electrode's RMS and mean current summed over the patterns, as the DAC makes them; bad
// input naming the electrode after `where`.
void check_load(const device::ChannelLoad& load, const device::Capabilities& caps,
                const std::string& where);

// The current limit in force for a stimulus: its own max_current_mA or the limits'
// (already narrowed to the device's), whichever is lower.  No code sent exceeds it.
double current_limit_mA(const Stimulus& s, const StimulusLimits& lim);

// One live frame, {"currents_mA": [...]}: parsed, checked like the stimulus itself (the
// shape of `s`, limits `lim`) and quantised for the device within current_limit_mA.  Bad
// input names the line.
std::vector<std::int16_t> parse_live_frame(const std::string& line, std::size_t line_number,
                                           const Stimulus& s, const StimulusLimits& lim,
                                           const device::Capabilities& caps);

// The guards a session gives a device that measures (protocol 7): its patterns' smallest
// electrode area (at most the protocol's 4000 mm^2) and the limits' Shannon k, each
// rounded down (the stricter way), and what a lost contact does (opt's suspension, probe).
device::Guards guards_of(const Mix& m, const SessionOptions& opt);
// What a guard's trip says (stimctl's one line): the channel, the time from the start and
// the cause, in the words "contact", "compliance" or "density".
std::string guard_trip_text(const device::MeasurementsHead& h, const device::Capabilities& caps);

// Checked before every step that could start output, and at every turn of the keep-alive
// loop: opt.stop.  A mix of several patterns goes to the device as a table (protocol 4),
// after the same checks across patterns the device makes (check_mix, and the codes'
// load); live mode then takes amplitude frames {"amplitudes": [...]} (a single stimulus
// takes those and weight frames).  The run's steps are SessionRun's, in session.cpp:
// prepare (every check), open the output (preempt, configure, start), keep alive (frames,
// status, watchdog), finish (the count delivered against the count scheduled).
SessionReport run_session(Transport& transport, const Mix& m, const SessionOptions& opt);
SessionReport run_session(Transport& transport, const Stimulus& s, const SessionOptions& opt);

}  // namespace tp::host
