#pragma once
// A session's stop, asked from outside the session: by a signal (the flag that
// install_stop_handlers() returns, signals.hpp) or by the caller (Python's close(), a key
// at calibrate's terminal, a test), through a StopSource.  The session polls its token
// before every step that could start output and at every turn of its keep-alive loop; a
// stop ends the output first, then the run (docs/safety.md).

#include <atomic>
#include <csignal>
#include <memory>
#include <mutex>
#include <string>

namespace tp::host {

class StopToken;

// The caller's side: request() from any thread, once or more (the first reason stays).
class StopSource {
 public:
  StopSource();
  void request(const std::string& reason);
  bool requested() const;
  StopToken token() const;

 private:
  friend class StopToken;
  struct State {
    std::atomic<bool> asked{false};
    mutable std::mutex m;
    std::string reason;
  };
  std::shared_ptr<State> state_;
};

// The session's side: a copyable view of a StopSource, a signal flag, both, or neither
// (a default token never stops).
class StopToken {
 public:
  StopToken() = default;
  // This token, also stopped by a signal handler's flag (set to the signal number).
  StopToken with_signals(const volatile std::sig_atomic_t* flag) const;
  bool requested() const;
  // After requested(): a signal's end ("interrupted (SIGINT)", exit code 128 + signal), or
  // the caller's reason (exit code 0: the caller decides).  A signal takes precedence.
  struct Why {
    std::string reason;
    int exit_code = 0;
  };
  Why why() const;

 private:
  friend class StopSource;
  const volatile std::sig_atomic_t* signal_ = nullptr;
  std::shared_ptr<const StopSource::State> caller_;
};

}  // namespace tp::host
