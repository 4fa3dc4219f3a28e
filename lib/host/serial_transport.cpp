// The serial backend: every libserialport call goes through check(), which turns a
// negative sp_return into tp::Error with sp_last_error_message().  Every blocking call
// carries an explicit timeout.

#include <libserialport.h>

#include <cerrno>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.hpp"
#include "host/transport.hpp"

namespace tp::host {

void take_exclusively(int fd, const std::string& path);  // posix_transport.cpp

namespace {

// A frame is at most ~410 bytes stuffed; at 9600 baud that is ~430 ms, so a whole frame
// always fits in this write timeout on any usable line, and a stuck port is detected.
constexpr unsigned kWriteTimeoutMs = 1000;

int check(sp_return r, const std::string& what) {
  if (r >= 0) return r;
  std::string msg = what + ": ";
  if (r == SP_ERR_FAIL) {
    char* m = sp_last_error_message();
    msg += m ? m : "failed";
    sp_free_error_message(m);
  } else if (r == SP_ERR_ARG) {
    msg += "invalid argument";
  } else if (r == SP_ERR_MEM) {
    msg += "out of memory";
  } else {
    msg += "not supported";
  }
  failure(msg);
}

class SerialTransport final : public Transport {
 public:
  SerialTransport(const std::string& path, int baud) : path_(path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISCHR(st.st_mode))
      bad_input("--port: '" + path + "' is not a serial port (not a character device)");
    if (sp_get_port_by_name(path.c_str(), &port_) != SP_OK)
      bad_input("--port: no serial port '" + path + "'");
    try {
      open_exclusively(baud);
    } catch (...) {
      if (fd_ >= 0) ::close(fd_);
      close_port();
      throw;
    }
  }
  ~SerialTransport() override {
    if (fd_ >= 0) ::close(fd_);
    close_port();
  }
  std::string name() const override { return path_; }
  int native_handle() const override { return fd_; }

  void write(const std::uint8_t* data, std::size_t n) override {
    const int written =
        check(sp_blocking_write(port_, data, n, kWriteTimeoutMs), path_ + ": write");
    if (static_cast<std::size_t>(written) != n)
      failure(path_ + ": write timed out (device not reading)");
  }

  std::size_t read(std::uint8_t* buf, std::size_t max, int timeout_ms) override {
    const int got = check(sp_blocking_read_next(port_, buf, max, static_cast<unsigned>(timeout_ms)),
                          path_ + ": read");
    return static_cast<std::size_t>(got);
  }

 private:
  void open_exclusively(int baud) {
    // The lock first, on a descriptor of our own: sp_open changes the line (DTR, RTS,
    // termios), which must not happen to a port another stimctl holds.
    const int lock_fd = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (lock_fd < 0) failure("cannot open " + path_ + ": " + std::strerror(errno));
    if (!::isatty(lock_fd)) {
      ::close(lock_fd);
      bad_input("--port: '" + path_ + "' is not a serial port (not a terminal)");
    }
    if (::flock(lock_fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      ::close(lock_fd);
      if (e == EWOULDBLOCK) failure(path_ + ": in use by another program (port locked)");
      failure(path_ + ": cannot lock: " + std::strerror(e));
    }
    fd_ = lock_fd;
    check(sp_open(port_, SP_MODE_READ_WRITE), "cannot open " + path_);
    opened_ = true;
    int fd = -1;
    check(sp_get_port_handle(port_, &fd), path_ + ": handle");
    if (::ioctl(fd, TIOCEXCL) != 0)
      failure(path_ + ": cannot open exclusively (TIOCEXCL): " + std::strerror(errno));
    check(sp_set_baudrate(port_, baud), path_ + ": baud rate");
    check(sp_set_bits(port_, 8), path_ + ": data bits");
    check(sp_set_parity(port_, SP_PARITY_NONE), path_ + ": parity");
    check(sp_set_stopbits(port_, 1), path_ + ": stop bits");
    check(sp_set_flowcontrol(port_, SP_FLOWCONTROL_NONE), path_ + ": flow control");
  }
  void close_port() {
    if (port_) {
      if (opened_) sp_close(port_);
      sp_free_port(port_);
      port_ = nullptr;
    }
  }
  std::string path_;
  sp_port* port_ = nullptr;
  bool opened_ = false;
  int fd_ = -1;  // our own descriptor of the port, holding the lock
};

}  // namespace

std::unique_ptr<Transport> make_serial_transport(const std::string& path, int baud) {
  return std::make_unique<SerialTransport>(path, baud);
}

std::vector<std::string> list_serial_ports() {
  sp_port** ports = nullptr;
  check(sp_list_ports(&ports), "listing serial ports");
  std::vector<std::string> out;
  for (sp_port** p = ports; *p; ++p) {
    const char* desc = sp_get_port_description(*p);
    out.push_back(std::string(sp_get_port_name(*p)) + "\t" + (desc ? desc : ""));
  }
  sp_free_port_list(ports);
  return out;
}

}  // namespace tp::host
