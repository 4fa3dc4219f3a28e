#pragma once
// The person's answers to calibrate's questions: single keys on the terminal (Terminal,
// cbreak mode), or lines on stdin (--responses -, for a program that answers).  Each
// answer says how it was given, so that a stop names the key that made it ("Esc", "q").

#include <csignal>
#include <memory>
#include <optional>
#include <string>

namespace tp::host {

class Terminal;
class LineReader;

// A key as the person knows it: "Esc" for 27, else the character ("q", "Q").
std::string key_name(int key);

struct Answer {
  enum Kind { yes, no, stop } kind = no;
  std::string given;  // the key or the word: "y", "n", "q", "Esc", "quit", ...
};

class Answers {
 public:
  // from_stdin: lines on stdin (y, yes, n, no, q, quit); else the terminal's keys (y, n;
  // q, Q or Esc to stop), a runtime failure when there is no terminal.
  explicit Answers(bool from_stdin);
  ~Answers();
  Answers(const Answers&) = delete;
  Answers& operator=(const Answers&) = delete;

  // To the terminal asked in; to stderr when the answers come from stdin.
  void say(const std::string& text);
  // During a trial (the terminal only): whether a stop key was pressed within timeout_ms,
  // or the terminal has gone.  stop_key_name() names the key.
  bool stop_key(int timeout_ms);
  bool gone() const { return gone_; }
  const std::string& stop_key_name() const { return stop_key_; }
  // The next answer; empty when *flag was set (a signal) while waiting.  A line that is
  // not an answer is bad input naming it; answers that end, or a terminal that has gone,
  // a runtime failure.
  std::optional<Answer> answer(const volatile std::sig_atomic_t* flag);

 private:
  std::unique_ptr<Terminal> tty_;
  std::unique_ptr<LineReader> lines_;
  bool gone_ = false;
  std::string stop_key_;
};

}  // namespace tp::host
