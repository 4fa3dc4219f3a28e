#include "cli/progress.hpp"

#include <cstdio>

#include <unistd.h>

namespace tp::cli {

ProgressLine::ProgressLine(std::string program)
    : program_(std::move(program)),
      active_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

ProgressLine::~ProgressLine() {
  clear();
}

void ProgressLine::show(const std::string& text, bool at_once) {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(m_);
  const auto now = std::chrono::steady_clock::now();
  if (shown_ && !at_once && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  shown_ = true;
  const double s = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r%s: %s, %.1f s\033[K", program_.c_str(), text.c_str(), s);
  std::fflush(stderr);
}

void ProgressLine::clear() {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(m_);
  if (!shown_) return;
  shown_ = false;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
}

}  // namespace tp::cli
