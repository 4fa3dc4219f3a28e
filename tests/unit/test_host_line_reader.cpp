// The live-line reader (lib/host/line_reader) under random chunks: exactly the lines
// written, in linear time (a property test).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "host/line_reader.hpp"

using namespace tp;

namespace {

long fuzz_iterations(long fallback) {
  const char* env = std::getenv("TP_FUZZ_ITERATIONS");
  return env ? std::max(1L, std::atol(env) / 100) : fallback;
}

}  // namespace

TEST_CASE("live-line reader: random chunks give exactly the lines written, in linear time",
          "[host][live][fuzz]") {
  std::signal(SIGPIPE, SIG_IGN);  // the reader may refuse and close while the writer writes
  SplitMix64 rng{20261123};
  const long cases = fuzz_iterations(300);
  const auto t0 = std::chrono::steady_clock::now();
  long lines_checked = 0, refusals = 0;
  for (long c = 0; c < cases; ++c) {
    const std::size_t cap = 1 + static_cast<std::size_t>(rng.unit() * 4096);
    const double capd = static_cast<double>(cap);
    // The input: random lines (some empty, some over the cap), maybe no final newline.
    std::vector<std::string> expected;
    std::string text;
    const int n = static_cast<int>(rng.unit() * 60);
    for (int i = 0; i < n; ++i) {
      const double kind = rng.unit();
      std::size_t len = kind < 0.2 ? 0 : static_cast<std::size_t>(rng.unit() * capd);
      if (kind > 0.97) len = cap + 1 + static_cast<std::size_t>(rng.unit() * 3 * capd);
      std::string line(len, ' ');
      for (char& ch : line) {
        ch = static_cast<char>(static_cast<int>(rng.unit() * 255) + 1);
        if (ch == '\n') ch = 'x';
      }
      text += line;
      const bool newline = i + 1 < n || rng.unit() < 0.7;
      if (newline) text += '\n';
      if (newline || !line.empty()) expected.push_back(line);  // "" unterminated: no line
    }
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
    std::thread writer([&, w = fds[1]] {
      SplitMix64 wr{rng.next()};
      for (std::size_t off = 0; off < text.size();) {
        const std::size_t k =
            std::min(text.size() - off, 1 + static_cast<std::size_t>(wr.unit() * 9000));
        const ssize_t put = ::write(w, text.data() + off, k);
        if (put <= 0) break;  // the reader refused and closed
        off += static_cast<std::size_t>(put);
      }
      ::close(w);
    });
    host::LineReader reader(fds[0], cap);
    std::vector<std::string> got;
    std::string line;
    bool refused = false;
    try {
      while (true) {
        if (reader.next(line)) {
          got.push_back(line);
        } else if (reader.at_end()) {
          break;
        } else {
          reader.fill(100);
        }
      }
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
      refused = true;
      ++refusals;
    }
    ::close(fds[0]);
    writer.join();
    // Every line before the first over-long one came out intact; that one was refused.
    std::size_t first_long = expected.size();
    for (std::size_t i = 0; i < expected.size(); ++i)
      if (expected[i].size() > cap) {
        first_long = i;
        break;
      }
    CHECK(refused == (first_long < expected.size()));
    REQUIRE(got.size() == std::min(first_long, expected.size()));
    for (std::size_t i = 0; i < got.size(); ++i) CHECK(got[i] == expected[i]);
    lines_checked += static_cast<long>(got.size());
  }
  // Linear: 20 MB of one-byte lines through a pipe in chunks.
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
  const std::size_t count = 10000000;
  std::thread writer([&, w = fds[1]] {
    const std::string chunk(65536, '\n');
    for (std::size_t left = 2 * count; left > 0;) {
      const ssize_t put = ::write(w, chunk.data(), std::min(left, chunk.size()));
      if (put <= 0) break;
      left -= static_cast<std::size_t>(put);
    }
    ::close(w);
  });
  const auto t1 = std::chrono::steady_clock::now();
  host::LineReader reader(fds[0]);
  std::string line;
  std::size_t n = 0;
  while (true) {
    if (reader.next(line))
      ++n;
    else if (reader.at_end())
      break;
    else
      reader.fill(100);
  }
  writer.join();
  ::close(fds[0]);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  CHECK(n == 2 * count);
  CHECK(secs < 10.0);  // quadratic rescanning would take minutes
  WARN("line reader: " << cases << " random cases, " << lines_checked << " lines, " << refusals
                       << " over-long refusals in "
                       << std::chrono::duration<double>(t1 - t0).count() << " s; " << n
                       << " empty lines in " << secs << " s");
}
