// The host side of a session: the stop flag is honoured before every step that leads to
// output; the live-line reader and the live-frame parser under random input (property
// tests: whatever arrives, they return the right lines / a checked frame, or refuse it as
// bad input, never anything else).
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/splitmix.hpp"
#include "device/frame.hpp"
#include "host/line_reader.hpp"
#include "host/session.hpp"
#include "host/transport.hpp"

using namespace tp;

namespace {

long fuzz_iterations(long fallback) {
  const char* env = std::getenv("TP_FUZZ_ITERATIONS");
  return env ? std::max(1L, std::atol(env) / 100) : fallback;
}

// The in-process emulator, with a tap on the frames the host writes: when the frame of
// type `trip` is written, the stop flag is raised (as a signal handler would, mid-request).
class TrippingTransport final : public host::Transport {
 public:
  TrippingTransport(device::Msg trip, volatile std::sig_atomic_t& flag)
      : inner_(host::open_transport("emu", 115200, {})), trip_(trip), flag_(flag) {}
  std::string name() const override { return "tripping emu"; }
  void write(const std::uint8_t* data, std::size_t n) override {
    for (std::size_t i = 0; i < n; ++i)
      if (decoder_.push(data[i])) {
        const auto type = static_cast<device::Msg>(decoder_.frame().type);
        sent.push_back(type);
        if (type == trip_) flag_ = SIGINT;
      }
    inner_->write(data, n);
  }
  std::size_t read(std::uint8_t* buf, std::size_t max, int timeout_ms) override {
    return inner_->read(buf, max, timeout_ms);
  }
  std::vector<device::Msg> sent;

 private:
  std::unique_ptr<host::Transport> inner_;
  device::Msg trip_;
  volatile std::sig_atomic_t& flag_;
  device::FrameDecoder decoder_;
};

Stimulus test_stimulus() {
  Stimulus s;
  s.currents_mA = {0, 0, -0.5, 1, -0.5, 0, 0, 0};
  s.count = 200;
  return s;
}

}  // namespace

TEST_CASE("a signal during identify or configuring starts nothing", "[host][session][signal]") {
  for (device::Msg trip : {device::Msg::identify, device::Msg::status, device::Msg::configure,
                           device::Msg::set_weights}) {
    volatile std::sig_atomic_t flag = 0;
    TrippingTransport t(trip, flag);
    host::SessionOptions opt;
    opt.stop = host::StopToken().with_signals(&flag);
    const host::SessionReport r = host::run_session(t, test_stimulus(), opt);
    INFO("signal raised while sending message type " << static_cast<int>(trip));
    CHECK_FALSE(r.started);
    CHECK(r.exit_code == 128 + SIGINT);
    CHECK(std::find(t.sent.begin(), t.sent.end(), device::Msg::start) == t.sent.end());
    CHECK(r.pulses == 0);
  }
  // Raised while start is on the line: the output starts, and is stopped at once.
  volatile std::sig_atomic_t flag = 0;
  TrippingTransport t(device::Msg::start, flag);
  const auto t0 = std::chrono::steady_clock::now();
  host::SessionOptions opt;
  opt.stop = host::StopToken().with_signals(&flag);
  const host::SessionReport r = host::run_session(t, test_stimulus(), opt);
  CHECK(r.started);
  CHECK(r.exit_code == 128 + SIGINT);
  CHECK(t.sent.back() == device::Msg::status);  // the final status, after stop
  CHECK(std::find(t.sent.begin(), t.sent.end(), device::Msg::stop) != t.sent.end());
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(200));
}

TEST_CASE("a device still running another session's output is stopped first", "[host][session]") {
  // One emulator, two clients in turn: the first starts a long stimulus and vanishes
  // without stopping it (as a killed host), the second must stop it before configuring.
  auto link = host::open_transport("emu", 115200, {});
  struct Borrowed final : host::Transport {
    host::Transport& t;
    explicit Borrowed(host::Transport& x) : t(x) {}
    std::string name() const override { return t.name(); }
    void write(const std::uint8_t* d, std::size_t n) override { t.write(d, n); }
    std::size_t read(std::uint8_t* b, std::size_t m, int ms) override { return t.read(b, m, ms); }
  } borrowed{*link};
  host::StimulatorClient first(borrowed);
  const auto caps = first.identify();
  device::PulseConfig cfg;
  cfg.max_pulses = 100000;
  first.configure(cfg);
  first.set_weights(host::quantize_currents(test_stimulus().currents_mA, caps, 2.0));
  first.start();
  REQUIRE(first.status().state == device::State::running);
  Stimulus s = test_stimulus();
  s.count = 10;
  const host::SessionReport r = host::run_session(borrowed, s, {});
  CHECK(r.preempted);
  CHECK(r.end == "stimulus complete");
  CHECK(r.pulses == 10);
}

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

TEST_CASE("a live frame that names currents_mA twice is refused", "[host][live]") {
  const Stimulus s = test_stimulus();
  const device::Capabilities caps;
  const StimulusLimits lim;
  const std::string one = "[0, 0, -0.5, 1, -0.5, 0, 0, 0]";
  const std::string two = "[0, 0, -1, 2, -1, 0, 0, 0]";
  CHECK(host::parse_live_frame("{\"currents_mA\": " + one + "}", 1, s, lim, caps).size() == 8);
  try {
    host::parse_live_frame("{\"currents_mA\": " + one + ", \"currents_mA\": " + two + "}", 3, s,
                           lim, caps);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK(std::string(e.what()) == "input line 3: key \"currents_mA\" appears twice in one object");
  }
}

TEST_CASE("a live frame is checked as the device checks its codes: RMS as the DAC makes it",
          "[host][live]") {
  Stimulus s = test_stimulus();
  s.shape.width_us = s.shape.balance_width_us = 250;
  s.shape.frequency_hz = 1000;
  const device::Capabilities caps;  // 977 nA a code
  const StimulusLimits lim;
  // 1.41421356 mA, 250 + 250 us at 1 kHz: RMS 0.99999999 mA; 1448 codes make 1.0003 mA.
  const std::string over =
      "{\"currents_mA\": [0, 0, 0, 0, -0.70710678, 0, 1.41421356, -0.70710678]}";
  try {
    host::parse_live_frame(over, 4, s, lim, caps);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    CHECK_THAT(e.what(), Catch::Matchers::StartsWith("input line 4: electrode 6: RMS 1.0003"));
    CHECK_THAT(e.what(), Catch::Matchers::Contains("as the DAC makes them"));
  }
  const std::string under = "{\"currents_mA\": [0, 0, 0, 0, -0.7066, 0, 1.4132, -0.7066]}";
  CHECK(host::parse_live_frame(under, 5, s, lim, caps)[6] == 1446);
}

TEST_CASE("live frames: random JSON is a checked frame or bad input, nothing else",
          "[host][live][fuzz]") {
  SplitMix64 rng{7};
  const Stimulus s = test_stimulus();
  const device::Capabilities caps;
  const StimulusLimits lim;
  auto number = [&]() -> std::string {
    const double k = rng.unit();
    if (k < 0.1) return "1e999";
    if (k < 0.15) return "-1e999";
    if (k < 0.2) return "1e-999";
    if (k < 0.25) return "-0";
    if (k < 0.3) return "123456789012345678901234567890";
    if (k < 0.35) return std::to_string(static_cast<long>(rng.next() >> 1));
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", (rng.unit() - 0.5) * std::pow(10.0, rng.unit() * 10 - 6));
    return b;
  };
  std::function<std::string(int)> value = [&](int depth) -> std::string {
    const double k = rng.unit();
    if (depth > 6 || k < 0.4) return number();
    if (k < 0.5) return "\"s\"";
    if (k < 0.55) return rng.unit() < 0.5 ? "true" : "null";
    const int n = static_cast<int>(rng.unit() * 10);
    std::string out = k < 0.8 ? "[" : "{";
    for (int i = 0; i < n; ++i) {
      if (i) out += ",";
      if (out[0] == '{')
        out += rng.unit() < 0.5 ? "\"currents_mA\":" : "\"k" + std::to_string(i) + "\":";
      out += value(depth + 1);
    }
    return out + (out[0] == '[' ? "]" : "}");
  };
  const long cases = fuzz_iterations(20000);
  long accepted = 0;
  for (long c = 0; c < cases; ++c) {
    std::string line;
    const double k = rng.unit();
    if (k < 0.4) {  // a frame of 8 currents, some valid
      line = "{\"currents_mA\": [";
      const double a = rng.unit() * 2.2;
      std::vector<double> v = {0, 0, -a / 2, a, -a / 2, 0, 0, 0};
      for (std::size_t i = 0; i < v.size(); ++i) {
        char b[40];
        std::snprintf(b, sizeof b, "%.17g", v[i]);
        line += (i ? "," : "") + (rng.unit() < 0.05 ? number() : std::string(b));
      }
      line += "]}";
    } else if (k < 0.8) {
      line = value(0);
    } else {  // byte mutations of a valid frame, or deep nesting
      line = "{\"currents_mA\": [0, 0, -0.5, 1, -0.5, 0, 0, 0]}";
      for (int m = static_cast<int>(rng.unit() * 4); m >= 0; --m)
        line[static_cast<std::size_t>(rng.unit() * static_cast<double>(line.size()))] =
            static_cast<char>(rng.unit() * 256);
      if (rng.unit() < 0.01) line = std::string(100000, '[');
    }
    try {
      const auto codes = host::parse_live_frame(line, 1, s, lim, caps);
      ++accepted;
      long sum = 0;
      for (std::int16_t x : codes) {
        CHECK(std::abs(int{x}) <= caps.max_code());
        sum += x;
      }
      CHECK(sum == 0);
      CHECK(codes.size() == 8);
      // and what the device's own load check accepts
      device::ChannelLoad load;
      device::add_dense(load, codes, pattern_timing(s, 0));
      CHECK(load.within(caps));
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::bad_input);
    }
  }
  CHECK(accepted > 0);
  WARN("live frames: " << cases << " random lines, " << accepted << " accepted");
}

TEST_CASE("a session whose output another session took over fails, never reports success",
          "[host][session]") {
  auto link = host::open_transport("emu", 115200, {});
  struct Borrowed final : host::Transport {
    host::Transport& t;
    explicit Borrowed(host::Transport& x) : t(x) {}
    std::string name() const override { return t.name(); }
    void write(const std::uint8_t* d, std::size_t n) override { t.write(d, n); }
    std::size_t read(std::uint8_t* b, std::size_t m, int ms) override { return t.read(b, m, ms); }
  } a{*link}, b{*link};
  host::StimulatorClient first(a), second(b);
  const auto caps = first.identify();
  device::PulseConfig cfg;
  cfg.max_pulses = 100000;
  const auto codes = host::quantize_currents(test_stimulus().currents_mA, caps, 2.0);
  first.configure(cfg);
  first.set_weights(codes);
  first.start();
  second.stop();  // a host that ignores the lock stops it and starts its own
  second.configure(cfg);
  second.set_weights(codes);
  second.start();
  try {
    first.keepalive();
    FAIL("the first session's keep-alive reported success");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::failure);
    CHECK(std::string(e.what()).find("another session") != std::string::npos);
  }
  second.stop();
}
