#pragma once
// A parallel loop with deterministic results: each index's work writes its own slot.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace tp {

// Runs f(i) for i in [0, n) on `threads` threads; the first error (lowest i) is rethrown.
// Each thread started here calls at_exit() before it ends (a library's per-thread state).
template <class F, class G = void (*)()>
void parallel_for(
    std::size_t n, unsigned threads, F&& f, G at_exit = [] {}) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i; (i = next++) < n;) {
      try {
        f(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const unsigned k = static_cast<unsigned>(std::min<std::size_t>(std::max(1u, threads), n));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < k; ++t) {
    try {
      pool.emplace_back([&] {
        work();
        at_exit();
      });
    } catch (...) {  // no more threads to be had: the ones there are do the work
      break;
    }
  }
  work();
  for (auto& t : pool) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace tp
