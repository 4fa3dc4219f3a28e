#pragma once
// Lines from a non-blocking input (stimctl --live's weight frames), read in linear time
// with bounded memory: each byte is scanned once, consumed lines are dropped in amortised
// O(1), and a line longer than the cap is refused (bad input) instead of buffered.

#include <cstddef>
#include <string>

namespace tp::host {

// The longest live-mode line; a weight frame of 64 channels is under 2 KiB.
inline constexpr std::size_t kMaxLiveLineBytes = std::size_t{1} << 20;  // 1 MiB

class LineReader {
 public:
  explicit LineReader(int fd, std::size_t max_line_bytes = kMaxLiveLineBytes)
      : fd_(fd), max_(max_line_bytes) {}

  // The next complete line already read (without its '\n'), or after end of input the
  // unterminated rest.  False when none is ready.  A line over the cap throws tp::Error
  // (bad input) naming its number.
  bool next(std::string& line);

  // Waits up to timeout_ms for input and reads what is there (one read, at most 64 KiB).
  // False at end of input.  An interrupted wait (EINTR) returns true with nothing read.
  bool fill(int timeout_ms);

  bool at_end() const { return eof_ && begin_ == buf_.size(); }
  std::size_t lines() const { return lines_; }  // lines returned so far

 private:
  void check_length(std::size_t length) const;

  int fd_;
  std::size_t max_;
  std::string buf_;
  std::size_t begin_ = 0;  // first unconsumed byte
  std::size_t scan_ = 0;   // where the search for '\n' resumes
  std::size_t lines_ = 0;
  bool eof_ = false;
};

}  // namespace tp::host
