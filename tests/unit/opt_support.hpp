// What the optimiser's unit tests share.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

#include "model/field.hpp"

namespace tp::test {

// A 4 x 4 grid of 1 x 1 mm pads at 2 mm under rect3d, fibres 2 mm beyond the pads.
inline Setup grid_4x4() {
  Setup s;
  s.array = ElectrodeArray::grid_of(4, 4, 2.0, 2.0, 1.0, 1.0);
  s.conductor.model = "rect3d";
  s.lateral_margin_mm = 2.0;
  return s;
}


// Runs f with stdout redirected to a temporary file; returns what was written there.
template <class F>
inline std::string stdout_of(F f) {
  std::fflush(stdout);
  FILE* tmp = std::tmpfile();
  const int saved = ::dup(1);
  ::dup2(::fileno(tmp), 1);
  try {
    f();
  } catch (...) {
    std::fflush(stdout);
    ::dup2(saved, 1);
    ::close(saved);
    std::fclose(tmp);
    throw;
  }
  std::fflush(stdout);
  ::dup2(saved, 1);
  ::close(saved);
  std::rewind(tmp);
  std::string out;
  for (int c; (c = std::fgetc(tmp)) != EOF;) out += static_cast<char>(c);
  std::fclose(tmp);
  return out;
}

}  // namespace tp::test
