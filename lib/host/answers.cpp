#include "host/answers.hpp"

#include <cstdio>
#include <ctime>

#include "core/error.hpp"
#include "host/line_reader.hpp"
#include "host/terminal.hpp"

namespace tp::host {
namespace {

constexpr int kEsc = 27;

bool is_stop_key(int k) {
  return k == 'q' || k == 'Q' || k == kEsc;
}

std::string trimmed(const std::string& line) {
  const auto b = line.find_first_not_of(" \t\r");
  const auto e = line.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : line.substr(b, e - b + 1);
}

}  // namespace

std::string key_name(int key) {
  if (key == kEsc) return "Esc";
  return std::string(1, static_cast<char>(key));
}

Answers::Answers(bool from_stdin) {
  if (from_stdin)
    lines_ = std::make_unique<LineReader>(0, 4096);
  else
    tty_ = std::make_unique<Terminal>();
}

Answers::~Answers() = default;

void Answers::say(const std::string& text) {
  if (tty_)
    tty_->say(text);
  else
    std::fprintf(stderr, "%s", text.c_str());
}

bool Answers::stop_key(int timeout_ms) {
  if (!tty_) {
    timespec ts{0, static_cast<long>(timeout_ms) * 1000000};
    nanosleep(&ts, nullptr);
    return false;
  }
  const int k = tty_->key(timeout_ms);
  if (k == Terminal::kGone) gone_ = true;
  if (is_stop_key(k)) stop_key_ = key_name(k);
  return gone_ || is_stop_key(k);
}

std::optional<Answer> Answers::answer(const volatile std::sig_atomic_t* flag) {
  while (!*flag) {
    if (tty_) {
      const int k = tty_->key(100);
      if (k == Terminal::kGone) failure("the terminal is gone; nothing running");
      if (k == 'y' || k == 'Y') return Answer{Answer::yes, key_name(k)};
      if (k == 'n' || k == 'N') return Answer{Answer::no, key_name(k)};
      if (is_stop_key(k)) return Answer{Answer::stop, key_name(k)};
      continue;
    }
    std::string line;
    if (lines_->next(line)) {
      const std::string word = trimmed(line);
      if (word == "y" || word == "yes") return Answer{Answer::yes, word};
      if (word == "n" || word == "no") return Answer{Answer::no, word};
      if (word == "q" || word == "quit") return Answer{Answer::stop, word};
      bad_input("--responses: line " + std::to_string(lines_->lines()) + ": '" + word +
                "' is not y, n or q");
    }
    if (lines_->at_end()) failure("--responses: the answers ended before the calibration did");
    lines_->fill(100);
  }
  return std::nullopt;
}

}  // namespace tp::host
