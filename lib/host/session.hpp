#pragma once
// stimctl's run: identify the device, check the stimulus against the device's
// capabilities and the host's limits, configure, set weights, start, keep the watchdog fed,
// and stop the output however the run ends: the stimulus completes, --duration passes,
// the live input ends, a signal arrives, or anything fails.

#include <csignal>
#include <string>

#include "host/stimulator.hpp"
#include "pulse/stimulus.hpp"

namespace tp::host {

struct SessionOptions {
  double duration_s = -1.0;  // stop after this long (< 0: the stimulus' own duration)
  bool live = false;         // after starting, read weight frames (JSON lines) from input_fd
  int input_fd = 0;
  std::string latency_log;  // live mode: "n t_ns" per weight frame written (benchmarks)
  StimulusLimits limits;    // the host's limits
};

struct SessionReport {
  std::string port;
  std::string end;           // why the output stopped
  int exit_code = 0;         // 0, or 128 + signal
  std::uint32_t pulses = 0;  // delivered, per the device
  std::uint32_t weight_frames = 0;
  double seconds = 0.0;
  int retransmissions = 0;
  device::Capabilities caps;
};

// signal_flag: set (to the signal number) by the caller's signal handler.
SessionReport run_session(Transport& transport, const Stimulus& s, const SessionOptions& opt,
                          const volatile std::sig_atomic_t* signal_flag);

}  // namespace tp::host
