#pragma once
// One error type for the whole project, carrying the exit status it maps to.
// Exit statuses are fixed for every program:
//   0  success
//   1  runtime failure (I/O error, device lost, solver failure)
//   2  bad input or usage (nothing was written to stdout, nothing was sent)

#include <stdexcept>
#include <string>

#include "core/text.hpp"

namespace tp {

enum class ExitCode : int { ok = 0, failure = 1, bad_input = 2 };

// The message is kept printable (core/text.hpp): user text quoted in it can carry no
// control character and no invalid UTF-8 to a terminal or to Python.
class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message)
      : std::runtime_error(printable(message)), code_(code) {}
  ExitCode code() const noexcept { return code_; }

 private:
  ExitCode code_;
};

// An end the program has already told the user in its own words (stimctl's summary names
// why the output stopped): the entry point (cli::run) exits with its status and prints no
// second line.  Anywhere else it is an Error like any other.
class Told : public Error {
 public:
  using Error::Error;
};

// Bad input or usage: exit status 2.
[[noreturn]] inline void bad_input(const std::string& message) {
  throw Error(ExitCode::bad_input, message);
}

// Runtime failure: exit status 1.
[[noreturn]] inline void failure(const std::string& message) {
  throw Error(ExitCode::failure, message);
}

}  // namespace tp
