#pragma once
// The person at the device (calibrate): the controlling terminal in cbreak mode (keys
// read one at a time, not echoed; Ctrl-C still a signal), restored however the program
// ends short of a crash; and a stimulus delivered while watching for a stop key.

#include <csignal>
#include <functional>
#include <string>

#include "host/session.hpp"

namespace tp::host {

class Terminal {
 public:
  // Opens /dev/tty; a runtime failure (exit 1) when there is none.
  Terminal();
  ~Terminal();
  Terminal(const Terminal&) = delete;
  Terminal& operator=(const Terminal&) = delete;
  // The next key within timeout_ms (0: do not wait), else -1 (also when a signal
  // interrupted the wait); kGone when the terminal has hung up or fails.
  int key(int timeout_ms);
  static constexpr int kGone = -2;
  void say(const std::string& text);  // written to the terminal

 private:
  int fd_ = -1;
  bool restore_ = false;
  unsigned char saved_[64] = {};  // the struct termios as it was
};

// Delivers m as run_session does, on a thread of its own that leaves the signals to the
// caller's, while stop(timeout_ms) is asked every few milliseconds (and *signal_flag
// watched): once either says stop, the session's stop token does, and it stops the output
// at once.  Returns its report; `stopped` says whether stop() ended it.
SessionReport run_watched(Transport& transport, const Mix& m, const SessionOptions& opt,
                          const volatile std::sig_atomic_t* signal_flag,
                          const std::function<bool(int)>& stop, bool& stopped);

}  // namespace tp::host
