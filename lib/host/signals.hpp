#pragma once
// stimctl's signals: every way the process can be ended stops the output first.
//
//  - Every catchable signal whose default action ends (or suspends) the process (SIGHUP,
//    SIGINT, SIGQUIT, SIGTERM, SIGUSR1/2, SIGALRM, SIGVTALRM, SIGPROF, SIGIO, SIGPWR,
//    SIGSTKFLT, SIGXCPU, SIGXFSZ, SIGTSTP, SIGTTIN, SIGTTOU and the real-time signals) sets
//    a flag; the session sees it, stops the output, and the program exits 128 + signal.
//    SIGPIPE is ignored (a closed pipe is an I/O error, handled like any other).  A signal
//    the parent already ignores (nohup's SIGHUP; SIGINT and SIGQUIT of a background job in
//    a script) stays ignored: it cannot end the process.
//  - A crash (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS) writes a
//    prepared stop frame straight to the port (write(2) is async-signal-safe), then dies
//    with the signal's default action.  The device's watchdog is the last line.
//  - SIGKILL and SIGSTOP cannot be caught: the device's watchdog stops the output.

#include <csignal>
#include <string>

namespace tp::host {

// Installs the handlers above; returns the flag the handlers set (to the signal number).
const volatile std::sig_atomic_t* install_stop_handlers();

// The signals install_stop_handlers() turns into a flag (for tests).
const int* stop_signals(int& count);

// After the port is open: a crash writes a stop frame to this descriptor (-1: none).
void arm_emergency_stop(int fd);

// arm_emergency_stop(fd) for as long as it lives, disarmed (-1) however its scope ends:
// declared after the transport, so that it is disarmed before the port is closed.
class EmergencyStopArmed {
 public:
  explicit EmergencyStopArmed(int fd) { arm_emergency_stop(fd); }
  ~EmergencyStopArmed() { arm_emergency_stop(-1); }
  EmergencyStopArmed(const EmergencyStopArmed&) = delete;
  EmergencyStopArmed& operator=(const EmergencyStopArmed&) = delete;
};

// "SIGINT", "SIGRTMIN+3", ...
std::string signal_name(int sig);

}  // namespace tp::host
