#include "host/line_reader.hpp"

#include <cerrno>
#include <cstring>

#include <poll.h>
#include <unistd.h>

#include "core/error.hpp"

namespace tp::host {

void LineReader::check_length(std::size_t length) const {
  if (length > max_)
    bad_input("input line " + std::to_string(lines_ + 1) + ": longer than " + std::to_string(max_) +
              " bytes");
}

bool LineReader::next(std::string& line) {
  const std::size_t nl = buf_.find('\n', scan_);
  if (nl != std::string::npos) {
    check_length(nl - begin_);
    line.assign(buf_, begin_, nl - begin_);
    begin_ = scan_ = nl + 1;
    ++lines_;
    return true;
  }
  scan_ = buf_.size();
  check_length(buf_.size() - begin_);
  if (eof_ && begin_ < buf_.size()) {
    line.assign(buf_, begin_, std::string::npos);
    begin_ = scan_ = buf_.size();
    ++lines_;
    return true;
  }
  return false;
}

bool LineReader::fill(int timeout_ms) {
  if (eof_) return false;
  // Drop consumed lines once they are at least half the buffer: amortised O(1) per byte.
  if (begin_ > 0 && begin_ * 2 >= buf_.size()) {
    buf_.erase(0, begin_);
    scan_ -= begin_;
    begin_ = 0;
  }
  pollfd p{fd_, POLLIN, 0};
  const int r = ::poll(&p, 1, timeout_ms);
  if (r < 0 && errno != EINTR) failure(std::string("reading input: ") + std::strerror(errno));
  if (r <= 0) return true;
  char chunk[65536];
  const ssize_t n = ::read(fd_, chunk, sizeof chunk);
  if (n < 0) {
    if (errno == EINTR || errno == EAGAIN) return true;
    failure(std::string("reading input: ") + std::strerror(errno));
  }
  if (n == 0) {
    eof_ = true;
    return false;
  }
  buf_.append(chunk, static_cast<std::size_t>(n));
  return true;
}

}  // namespace tp::host
