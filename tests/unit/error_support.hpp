// What the unit tests of refusals share: the exit code or the message a call throws.
#pragma once

#include <functional>
#include <string>

#include "core/error.hpp"

namespace tp::test {

// The code of the Error f throws, ExitCode::ok if it throws none.
inline ExitCode code_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.code();
  }
  return ExitCode::ok;
}

// The message of the Error f throws, "" if it throws none.
inline std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace tp::test
