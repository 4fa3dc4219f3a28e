#include "host/terminal.hpp"

#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstring>
#include <exception>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <termios.h>
#include <unistd.h>

#include "core/error.hpp"

namespace tp::host {

static_assert(sizeof(termios) <= 64, "the saved terminal state does not fit");

Terminal::Terminal() {
  fd_ = open("/dev/tty", O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd_ < 0)
    throw Error(ExitCode::failure, std::string("no terminal to ask (/dev/tty: ") +
                                       std::strerror(errno) + "); give --responses -");
  termios t{};
  if (tcgetattr(fd_, &t) == 0) {
    std::memcpy(saved_, &t, sizeof t);
    restore_ = true;
    t.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);  // ISIG kept: Ctrl-C is SIGINT
    t.c_cc[VMIN] = 1;
    t.c_cc[VTIME] = 0;
    tcsetattr(fd_, TCSANOW, &t);
  }
}

Terminal::~Terminal() {
  if (restore_) {
    termios t{};
    std::memcpy(&t, saved_, sizeof t);
    tcsetattr(fd_, TCSANOW, &t);
  }
  close(fd_);
}

int Terminal::key(int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int n = poll(&p, 1, timeout_ms);
  if (n < 0) return -1;  // a signal: the caller looks at its flag
  if (n == 0) return -1;
  if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) return kGone;
  unsigned char c = 0;
  const ssize_t r = read(fd_, &c, 1);
  if (r == 0 || (r < 0 && errno != EINTR && errno != EAGAIN)) return kGone;
  return r == 1 ? c : -1;
}

void Terminal::say(const std::string& text) {
  std::size_t at = 0;
  while (at < text.size()) {
    const ssize_t n = write(fd_, text.data() + at, text.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the terminal is gone: nothing more to say
    at += static_cast<std::size_t>(n);
  }
}

SessionReport run_watched(Transport& transport, const Mix& m, const SessionOptions& opt,
                          const volatile std::sig_atomic_t* signal_flag,
                          const std::function<bool(int)>& stop, bool& stopped) {
  StopSource caller;
  SessionOptions o = opt;
  o.stop = caller.token().with_signals(signal_flag);
  SessionReport rep;
  std::exception_ptr error;
  std::atomic<bool> done{false};
  // The session's thread blocks every signal, so that they reach this one (and interrupt
  // its wait); the handlers' flag is watched by both.
  sigset_t all, old;
  sigfillset(&all);
  // A crash on the session's thread must still reach its handler (the stop frame), which
  // a blocked synchronous signal would not.
  for (const int crash : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS})
    sigdelset(&all, crash);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  std::thread session;
  try {
    session = std::thread([&] {
      try {
        rep = run_session(transport, m, o);
      } catch (...) {
        error = std::current_exception();
      }
      done = true;
    });
  } catch (...) {
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    throw;
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  stopped = false;
  while (!done) {
    if (!caller.requested() && !(signal_flag && *signal_flag) && stop(5))
      caller.request("stopped at the terminal");  // the session stops the output at once
    else if (caller.requested() || (signal_flag && *signal_flag))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  session.join();
  stopped = caller.requested() && !(signal_flag && *signal_flag);
  if (error) std::rethrow_exception(error);
  return rep;
}

}  // namespace tp::host
