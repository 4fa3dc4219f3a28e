#include "host/signals.hpp"

#include <array>
#include <cstring>
#include <vector>

#include <unistd.h>

#include "device/frame.hpp"
#include "device/protocol.hpp"

namespace tp::host {
namespace {

volatile std::sig_atomic_t g_signal = 0;
volatile int g_port_fd = -1;
// The emergency stop frame, prepared before any signal can need it.  A leading flag ends
// whatever frame was half-written when the crash came; its payload differs from any stop
// the host sends, so the device never takes it for a retransmission.
std::array<std::uint8_t, 64> g_stop_frame{};
std::size_t g_stop_frame_len = 0;

void on_stop_signal(int sig) {
  if (g_signal == 0) g_signal = sig;
}

void on_crash(int sig) {
  const int fd = g_port_fd;
  if (fd >= 0 && g_stop_frame_len > 0) {
    const ssize_t ignored = ::write(fd, g_stop_frame.data(), g_stop_frame_len);
    (void)ignored;
  }
  // SA_RESETHAND restored the default action: die of the same signal.
  ::raise(sig);
}

std::vector<int> stop_signal_list() {
  std::vector<int> s = {SIGHUP,  SIGINT, SIGQUIT, SIGTERM, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM,
                        SIGPROF, SIGIO,  SIGPWR,  SIGXCPU, SIGXFSZ, SIGTSTP, SIGTTIN, SIGTTOU};
#ifdef SIGSTKFLT
  s.push_back(SIGSTKFLT);
#endif
  for (int r = SIGRTMIN; r <= SIGRTMAX; ++r) s.push_back(r);
  return s;
}

}  // namespace

const int* stop_signals(int& count) {
  static const std::vector<int> list = stop_signal_list();
  count = static_cast<int>(list.size());
  return list.data();
}

const volatile std::sig_atomic_t* install_stop_handlers() {
  std::vector<std::uint8_t> frame{device::kFlag};
  device::encode_frame(
      device::Frame{
          0xE5, static_cast<std::uint8_t>(device::Msg::stop), {'E', 'S', 'T', 'O', 'P', '!'}},
      frame);
  if (frame.size() <= g_stop_frame.size()) {
    std::memcpy(g_stop_frame.data(), frame.data(), frame.size());
    g_stop_frame_len = frame.size();
  }
  int n = 0;
  const int* sigs = stop_signals(n);
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (int i = 0; i < n; ++i) {
    // A signal the parent set to be ignored (nohup's SIGHUP; SIGINT and SIGQUIT of a
    // background job in a script) stays ignored, as POSIX programs do: it cannot end the
    // process, so the session goes on under a living host.
    struct sigaction old {};
    if (sigaction(sigs[i], nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaction(sigs[i], &sa, nullptr);
  }
  struct sigaction crash {};
  crash.sa_handler = on_crash;
  crash.sa_flags = static_cast<int>(SA_RESETHAND);  // 0x80000000: the flag bit
  sigemptyset(&crash.sa_mask);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS})
    sigaction(sig, &crash, nullptr);
  std::signal(SIGPIPE, SIG_IGN);  // a closed pipe must not kill us before the output stops
  return &g_signal;
}

void arm_emergency_stop(int fd) {
  g_port_fd = fd;
}

std::string signal_name(int sig) {
  if (sig >= SIGRTMIN && sig <= SIGRTMAX)
    return sig == SIGRTMIN ? "SIGRTMIN" : "SIGRTMIN+" + std::to_string(sig - SIGRTMIN);
  const char* abbrev = sigabbrev_np(sig);
  return abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

}  // namespace tp::host
