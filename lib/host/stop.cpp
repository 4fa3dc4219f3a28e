#include "host/stop.hpp"

#include "host/signals.hpp"

namespace tp::host {

StopSource::StopSource() : state_(std::make_shared<State>()) {}

void StopSource::request(const std::string& reason) {
  {
    std::lock_guard<std::mutex> lock(state_->m);
    if (state_->asked.load()) return;
    state_->reason = reason;
  }
  state_->asked.store(true);
}

bool StopSource::requested() const { return state_->asked.load(); }

StopToken StopSource::token() const {
  StopToken t;
  t.caller_ = state_;
  return t;
}

StopToken StopToken::with_signals(const volatile std::sig_atomic_t* flag) const {
  StopToken t = *this;
  t.signal_ = flag;
  return t;
}

bool StopToken::requested() const {
  return (signal_ && *signal_ != 0) || (caller_ && caller_->asked.load());
}

StopToken::Why StopToken::why() const {
  const int sig = signal_ ? static_cast<int>(*signal_) : 0;  // read once
  if (sig != 0) {
    if (sig == SIGINT) return {"interrupted (SIGINT)", 128 + sig};
    if (sig == SIGTERM) return {"terminated (SIGTERM)", 128 + sig};
    return {"stopped by " + signal_name(sig), 128 + sig};
  }
  if (caller_ && caller_->asked.load()) {
    std::lock_guard<std::mutex> lock(caller_->m);
    return {caller_->reason, 0};
  }
  return {};
}

}  // namespace tp::host
