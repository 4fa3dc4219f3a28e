#pragma once
// A progress line on stderr while long work runs, only when stderr is a terminal:
//
//   optimize-weights: bank 12 of 48 problems, 7.1 s
//
// rewritten in place (carriage return, erase to the end of the line) at most every 0.1 s,
// and erased when the work ends (clear(), or the destructor, also when the work throws), so
// that the program's one-line summary or error follows on a clean line.  When stderr is
// not a terminal (a pipe, a file, a test), nothing at all is written.
//
// The text comes from the library's own loop (a request's progress callback), never from
// a guess of how far the work has come.

#include <chrono>
#include <mutex>
#include <string>

namespace tp::cli {

class ProgressLine {
 public:
  explicit ProgressLine(std::string program);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // Whether stderr is a terminal (else show() does nothing).
  bool active() const { return active_; }
  // "program: TEXT, S s"; the first call shows at once, later ones at most every 0.1 s
  // unless `at_once` (a new stage of the work).  Safe to call from several threads.
  void show(const std::string& text, bool at_once = false);
  // Erases the line, if one is shown.
  void clear();

 private:
  std::string program_;
  bool active_ = false, shown_ = false;
  std::chrono::steady_clock::time_point start_, last_;
  std::mutex m_;
};

}  // namespace tp::cli
