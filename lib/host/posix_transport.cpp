// The POSIX termios backend, for pseudo-terminals (stim-emu's, socat's).  libserialport
// cannot open a pseudo-terminal on Linux: its port lookup needs a /sys/class/tty entry,
// and sp_open() fails on TIOCMGET, which ptys do not implement (no modem lines).  Real
// serial ports go through libserialport (serial_transport.cpp).

#include <cerrno>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include "core/error.hpp"
#include "host/transport.hpp"

namespace tp::host {
namespace {

// Same reason as the serial backend's: a whole frame fits in it on any usable line.
constexpr int kWriteTimeoutMs = 1000;

speed_t speed_of(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 921600:
      return B921600;
    default:
      bad_input("--baud: " + std::to_string(baud) + " is not a standard rate for this port");
  }
}

}  // namespace

// Two hosts must never share a line: an advisory lock that every stimctl takes (it holds
// for root too, and is released by the kernel when the holder dies), and TIOCEXCL, which
// makes the kernel refuse further opens by other (non-root) programs.
void take_exclusively(int fd, const std::string& path) {
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    ::close(fd);
    if (e == EWOULDBLOCK) failure(path + ": in use by another program (port locked)");
    failure(path + ": cannot lock: " + std::strerror(e));
  }
  if (::ioctl(fd, TIOCEXCL) != 0) {
    const int e = errno;
    ::close(fd);
    failure(path + ": cannot open exclusively (TIOCEXCL): " + std::strerror(e));
  }
}

namespace {

class PosixTtyTransport final : public Transport {
 public:
  PosixTtyTransport(const std::string& path, int baud) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
      if (errno == ENOENT) bad_input("--port: no such port '" + path + "'");
      if (errno == EISDIR) bad_input("--port: '" + path + "' is a directory, not a serial port");
      if (errno == EBUSY) failure(path + ": in use by another program (opened exclusively)");
      failure("cannot open " + path + ": " + std::strerror(errno));
    }
    if (!::isatty(fd_)) {
      ::close(fd_);
      bad_input("--port: '" + path + "' is not a serial port (not a terminal)");
    }
    take_exclusively(fd_, path);
    termios t{};
    if (tcgetattr(fd_, &t) != 0) failure(path + ": " + std::strerror(errno));
    cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    cfsetispeed(&t, speed_of(baud));
    cfsetospeed(&t, speed_of(baud));
    if (tcsetattr(fd_, TCSANOW, &t) != 0)
      failure(path + ": cannot configure: " + std::strerror(errno));
    tcflush(fd_, TCIOFLUSH);
  }
  ~PosixTtyTransport() override { ::close(fd_); }
  std::string name() const override { return path_; }
  int native_handle() const override { return fd_; }

  void write(const std::uint8_t* data, std::size_t n) override {
    std::size_t off = 0;
    while (off < n) {
      pollfd p{fd_, POLLOUT, 0};
      const int r = ::poll(&p, 1, kWriteTimeoutMs);
      if (r == 0) failure(path_ + ": write timed out (device not reading)");
      if (r < 0) {
        if (errno == EINTR) continue;
        failure(path_ + ": " + std::strerror(errno));
      }
      if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) failure(path_ + ": device lost");
      const ssize_t w = ::write(fd_, data + off, n - off);
      if (w < 0) {
        if (errno == EAGAIN || errno == EINTR) continue;
        failure(path_ + ": write: " + std::strerror(errno));
      }
      off += static_cast<std::size_t>(w);
    }
  }

  std::size_t read(std::uint8_t* buf, std::size_t max, int timeout_ms) override {
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, timeout_ms);
    if (r == 0 || (r < 0 && errno == EINTR)) return 0;
    if (r < 0) failure(path_ + ": " + std::strerror(errno));
    if (p.revents & POLLIN) {
      const ssize_t n = ::read(fd_, buf, max);
      if (n > 0) return static_cast<std::size_t>(n);
      if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
      failure(path_ + ": device lost (" +
              (n == 0 ? std::string("end of file") : std::strerror(errno)) + ")");
    }
    if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) failure(path_ + ": device lost (line hung up)");
    return 0;
  }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace

bool is_pseudo_terminal(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) return false;
  const unsigned maj = major(st.st_rdev);
  return maj >= 136 && maj <= 143;  // UNIX98 pty slaves (Documentation/admin-guide/devices.txt)
}

std::unique_ptr<Transport> make_posix_transport(const std::string& path, int baud) {
  return std::make_unique<PosixTtyTransport>(path, baud);
}

}  // namespace tp::host
