// Sessions (lib/host/session): the stop flag is honoured before every step that leads to
// output; a device still running another session's output is stopped first; and sessions
// deliver what was asked or fail saying so (issue 38): live frames by the rule of
// the pattern in force, folded when they queue; a device's completion that delivered fewer
// pulses than scheduled is a failure; a stimulus above the device's throughput is refused
// before anything is sent, and the device refuses it again at start.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cmath>
#include <deque>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>
#include "core/error.hpp"
#include "device/device_core.hpp"
#include "device/frame.hpp"
#include "device_support.hpp"
#include "error_support.hpp"
#include "host/live.hpp"
#include "host/session.hpp"
#include "host/stimulator.hpp"
#include "host/transport.hpp"

using namespace tp;
using tp::test::message_of;

namespace {

Stimulus stimulus(double amplitude_mA, long count = 200) {
  Stimulus s;
  s.currents_mA = {0, 0, -0.5 * amplitude_mA, amplitude_mA, -0.5 * amplitude_mA, 0, 0, 0};
  s.amplitude_mA = amplitude_mA;
  s.count = count;
  return s;
}

Mix mix_of(const Stimulus& s) {
  Mix m;
  m.patterns.push_back(s);
  return m;
}

// A device core behind an in-memory link whose engine loses every `lose`-th pulse, as a
// firmware behind its schedule did, reporting them not delivered (or, with overrun, ending
// the output as the firmware now does).
class LossyDevice final : public host::Transport {
 public:
  LossyDevice(int lose, bool overrun, device::Capabilities caps = {})
      : core_(caps), lose_(lose), overrun_(overrun) {}
  std::string name() const override { return "lossy device"; }
  void write(const std::uint8_t* data, std::size_t n) override {
    advance();
    std::vector<std::uint8_t> out;
    core_.receive(data, n, host::monotonic_us(), out);
    rx_.insert(rx_.end(), out.begin(), out.end());
    for (std::size_t i = 0; i < n; ++i)
      if (decoder_.push(data[i])) sent.push_back(static_cast<device::Msg>(decoder_.frame().type));
  }
  std::size_t read(std::uint8_t* buf, std::size_t max, int timeout_ms) override {
    advance();
    if (rx_.empty()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
      advance();
      return 0;
    }
    std::size_t k = 0;
    while (k < max && !rx_.empty()) {
      buf[k++] = rx_.front();
      rx_.pop_front();
    }
    return k;
  }
  std::vector<device::Msg> sent;

 private:
  void advance() {
    std::uint64_t start = 0;
    std::uint32_t lost = 0;
    core_.advance(host::monotonic_us(), [&](const device::DeliveredPulse& p) {
      if (++emitted_ % static_cast<unsigned>(lose_) == 0) {
        ++lost;
        start = p.start_us;
      }
    });
    if (lost == 0) return;
    if (overrun_)
      core_.overrun(start, lost);
    else
      core_.not_delivered(start, lost);
  }
  device::DeviceCore core_;
  int lose_;
  bool overrun_;
  unsigned emitted_ = 0;
  std::deque<std::uint8_t> rx_;
  device::FrameDecoder decoder_;
};

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

// One link lent to several clients in turn (as hosts that come and go on one device).
struct Borrowed final : host::Transport {
  host::Transport& t;
  explicit Borrowed(host::Transport& x) : t(x) {}
  std::string name() const override { return t.name(); }
  void write(const std::uint8_t* d, std::size_t n) override { t.write(d, n); }
  std::size_t read(std::uint8_t* b, std::size_t m, int ms) override { return t.read(b, m, ms); }
};

Stimulus test_stimulus() {
  Stimulus s;
  s.currents_mA = {0, 0, -0.5, 1, -0.5, 0, 0, 0};
  s.count = 200;
  return s;
}

}  // namespace

TEST_CASE("an amplitude is the current of a weight-1 electrode of the pattern in force",
          "[host][live]") {
  const device::Capabilities caps;
  host::LiveState state(mix_of(stimulus(0.1)), StimulusLimits{}, caps);
  // The stimulus's own: 0.05 of its 0.1 mA is half scale.
  state.add(host::parse_live_line("{\"amplitudes\": [0.05]}", "line 1"));
  CHECK(state.take().scales->at(0) == device::kFullScale / 2);
  // After a currents frame, its pattern: weights [1, -1, ...] at 1 mA, so 0.05 mA is 0.05
  // of it (it was half of the new codes: 0.5 mA).
  state.add(host::parse_live_line("{\"currents_mA\": [1, -1, 0, 0, 0, 0, 0, 0]}", "line 2"));
  state.add(host::parse_live_line("{\"amplitudes\": [0.05]}", "line 3"));
  const host::LiveState::Update u = state.take();
  REQUIRE(u.codes);
  REQUIRE(u.scales);
  CHECK(u.frames == 2);
  const double delivered_mA =
      (*u.codes)[0] * caps.dac_step_nA * 1e-6 * u.scales->at(0) / device::kFullScale;
  CHECK(delivered_mA == Approx(0.05).epsilon(0.01));
  // Its amplitude is its largest current: above it is refused, naming the line.
  CHECK(
      message_of([&] { state.add(host::parse_live_line("{\"amplitudes\": [1.5]}", "line 4")); }) ==
      "line 4: amplitude 1.5 mA for pattern 0 outside [0, 1] mA (the current of its weight-1 "
      "electrode)");
}

TEST_CASE("frames that queue are folded: the last of each kind, a currents frame first",
          "[host][live]") {
  host::LiveState state(mix_of(stimulus(1.0)), StimulusLimits{}, device::Capabilities{});
  for (int k = 0; k < 3000; ++k)
    state.add(host::parse_live_line(
        "{\"amplitudes\": [" + std::to_string(0.001 * (k % 1000)) + "]}", "line"));
  state.add(host::parse_live_line("{\"amplitudes\": [0]}", "last"));
  host::LiveState::Update u = state.take();
  CHECK(u.frames == 3001);
  CHECK_FALSE(u.codes);
  CHECK(*u.scales == std::vector<std::uint16_t>{0});  // the fade's end, at once
  CHECK(state.take().empty());
  // An amplitude before a currents frame is superseded by it (new codes at full scale).
  state.add(host::parse_live_line("{\"amplitudes\": [0.2]}", "a"));
  state.add(host::parse_live_line("{\"currents_mA\": [0, 0, -0.2, 0.4, -0.2, 0, 0, 0]}", "c"));
  u = state.take();
  CHECK(u.codes);
  CHECK_FALSE(u.scales);
}

TEST_CASE("a flood of lines is taken a turn at a time, never past the keep-alive's time",
          "[host][live]") {
  // 60000 amplitude frames of 28 bytes (1.7 MB).  A turn's 17 reads of 64 KiB would hold
  // 39789 of them; its 5 ms parse at most a few thousand on any machine (a frame takes
  // microseconds), so the first pump stops by its time, well before 30000.  The rest come,
  // in order, in later turns.
  char path[] = "/tmp/tp-flood-XXXXXX";
  const int fd = mkstemp(path);
  REQUIRE(fd >= 0);
  unlink(path);
  std::string text;
  const int n = 60000;
  for (int k = 0; k < n; ++k)
    text += "{\"amplitudes\": [" + std::to_string(0.001 * (k % 1000)) + "]}\n\n";
  REQUIRE(write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()));
  REQUIRE(lseek(fd, 0, SEEK_SET) == 0);
  host::LineSource source(fd);
  host::LiveState state(mix_of(stimulus(1.0)), StimulusLimits{}, device::Capabilities{});
  CHECK(source.pump(state, 0));
  host::LiveState::Update u = state.take();
  const long first = u.frames;
  CHECK(first > 0);
  CHECK(first < 30000);
  long total = first, turns = 1;
  bool open = true;
  while (open && turns < 100000) {
    open = source.pump(state, 0);
    u = state.take();
    total += u.frames;
    ++turns;
  }
  CHECK_FALSE(open);
  CHECK(total == n);
  host::LiveState last(mix_of(stimulus(1.0)), StimulusLimits{}, device::Capabilities{});
  last.add(host::parse_live_line(
      "{\"amplitudes\": [" + std::to_string(0.001 * ((n - 1) % 1000)) + "]}", "last"));
  CHECK(*u.scales == *last.take().scales);  // the last frame's, in force at the end
  close(fd);
}

TEST_CASE("a live frame is told by its one key, never by the text of the line", "[host][live]") {
  const std::string two_keys =
      "line 1: expected {\"currents_mA\": [...]} or {\"amplitudes\": "
      "[...]}, one key, got 2";
  CHECK(message_of([] { host::parse_live_line("{\"amplitudes\": [0.05], \"x\": 1}", "line 1"); }) ==
        two_keys);
  CHECK(message_of([] {
          host::parse_live_line("{\"note\": \"amplitudes\", \"currents_mA\": [1, -1]}", "line 1");
        }) == two_keys);
  const host::LiveFrame f =
      host::parse_live_line("{\"currents_mA\": [0.5, -0.5, 0, 0, 0, 0, 0, 0]}", "line 2");
  CHECK(f.kind == host::LiveFrame::Kind::currents);
  CHECK(message_of([] { host::parse_live_line("{\"amplitudes\": 0.5}", "line 3"); }) ==
        "line 3: amplitudes must be a list of numbers");
}

TEST_CASE("a completion with fewer pulses than scheduled is a failure, naming both",
          "[host][session]") {
  // The device reports its stimulus complete having delivered 2 of every 3 pulses (the
  // firmware's engine behind its schedule, before the overrun fault): exit 0 before.
  LossyDevice lossy(3, false);
  const std::string m =
      message_of([&] { host::run_session(lossy, mix_of(stimulus(1.0, 30)), {}); });
  CHECK(m ==
        "the device delivered 20 of the 30 pulses scheduled and reported the stimulus "
        "complete: the stimulus was not delivered as asked (a device that cannot keep up "
        "with its rate: docs/safety.md)");
  CHECK(std::count(lossy.sent.begin(), lossy.sent.end(), device::Msg::stop) == 1);
}

TEST_CASE("a device that falls behind ends the output (overrun), and the host says so",
          "[host][session][device]") {
  LossyDevice lossy(10, true);
  const std::string m =
      message_of([&] { host::run_session(lossy, mix_of(stimulus(1.0, 200)), {}); });
  CHECK_THAT(m, Catch::Matchers::StartsWith(
                    "device stopped the output: it could not deliver a pulse on time"));
  CHECK_THAT(m, Catch::Matchers::Contains("of 200 pulses delivered"));
}

TEST_CASE("a stimulus above the device's throughput is refused before anything is sent",
          "[host][session][device]") {
  device::Capabilities caps;
  caps.max_pulse_rate_hz = 500;
  Mix m;
  for (int k = 0; k < 3; ++k) {
    Stimulus s = stimulus(0.5, 20);
    s.shape.frequency_hz = 200;
    s.phase_us = 1000 * k;
    m.patterns.push_back(s);
  }
  LossyDevice device(1000000, false, caps);
  CHECK(message_of([&] { host::run_session(device, m, {}); }) ==
        "the stimulus asks 600 pulses a second over its 3 patterns; the device delivers at "
        "most 500 a second on time (its measured throughput): lower the rates or use fewer "
        "patterns (docs/safety.md)");
  CHECK(device.sent == std::vector<device::Msg>{device::Msg::identify});
  m.patterns.pop_back();  // 400 a second: delivered
  CHECK(host::run_session(device, m, {}).pulses == 40);
}

// Issue 39: the session stops through its token (a caller's StopSource or a signal's flag),
// never a global; the output stops first, and the report says which stop it was.
TEST_CASE("a stop asked before the start sends nothing but identify", "[host][session]") {
  host::StopSource caller;
  caller.request("closed by the test");
  caller.request("a second reason is ignored");
  host::SessionOptions opt;
  opt.stop = caller.token();
  LossyDevice device(1000000, false);
  const host::SessionReport r = host::run_session(device, mix_of(stimulus(0.5)), opt);
  CHECK_FALSE(r.started);
  CHECK(r.end == "closed by the test");
  CHECK(r.exit_code == 0);
  CHECK(device.sent.empty());
}

TEST_CASE("a signal's flag in the token ends the run as 128 + the signal",
          "[host][session]") {
  volatile std::sig_atomic_t flag = 0;
  host::StopSource caller;
  host::SessionOptions opt;
  opt.stop = caller.token().with_signals(&flag);
  CHECK_FALSE(opt.stop.requested());
  flag = SIGTERM;
  caller.request("closed by the test");  // the signal takes precedence
  CHECK(opt.stop.why().reason == "terminated (SIGTERM)");
  CHECK(opt.stop.why().exit_code == 128 + SIGTERM);
  flag = 0;
  CHECK(opt.stop.why().reason == "closed by the test");
  CHECK(opt.stop.why().exit_code == 0);
  CHECK(host::StopToken().why().reason.empty());
}

TEST_CASE("a stop asked while the output runs stops it, and the device is told",
          "[host][session]") {
  host::StopSource caller;
  host::SessionOptions opt;
  opt.stop = caller.token();
  LossyDevice device(1000000, false);
  Stimulus s = stimulus(0.5, 2000);  // 10 s at 200 Hz
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    caller.request("closed by the test");
  });
  const host::SessionReport r = host::run_session(device, mix_of(s), opt);
  stopper.join();
  CHECK(r.started);
  CHECK(r.end == "closed by the test");
  CHECK(r.exit_code == 0);
  CHECK(r.pulses < 2000);
  const auto start = std::find(device.sent.begin(), device.sent.end(), device::Msg::start);
  REQUIRE(start != device.sent.end());
  CHECK(std::find(start, device.sent.end(), device::Msg::stop) != device.sent.end());
  CHECK(device.sent.back() == device::Msg::status);  // the final status, after the stop
}


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
  Borrowed borrowed{*link};
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

TEST_CASE("a session whose output another session took over fails, never reports success",
          "[host][session]") {
  auto link = host::open_transport("emu", 115200, {});
  Borrowed a{*link}, b{*link};
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

TEST_CASE("bad input once the output runs stops it first, and the message says so",
          "[host][session][live]") {
  // A live frame refused after the start (stimctl: a line of the wrong length): the session
  // stops the device's output before the error leaves it, and the message ends saying so.
  struct BadFrame final : host::FrameSource {
    bool pump(host::LiveState&, int) override {
      bad_input("input line 1: 2 currents for 8 channels");
    }
  } bad;
  volatile std::sig_atomic_t flag = 0;  // raised by nothing: the host never sends an ack
  TrippingTransport t(device::Msg::ack, flag);
  host::SessionOptions opt;
  opt.live = true;
  opt.frames = &bad;
  const std::string said = message_of([&] { host::run_session(t, mix_of(test_stimulus()), opt); });
  CHECK(said == "input line 1: 2 currents for 8 channels; output stopped");
  const auto start = std::find(t.sent.begin(), t.sent.end(), device::Msg::start);
  REQUIRE(start != t.sent.end());
  CHECK(std::find(start, t.sent.end(), device::Msg::stop) != t.sent.end());
}

namespace {

// A device that answers identify with given capability bytes (and nothing else).
class IdentifyOnly final : public host::Transport {
 public:
  explicit IdentifyOnly(std::vector<std::uint8_t> caps) : caps_(std::move(caps)) {}
  std::string name() const override { return "identify-only device"; }
  void write(const std::uint8_t* data, std::size_t n) override {
    for (std::size_t i = 0; i < n; ++i)
      if (decoder_.push(data[i])) {
        std::vector<std::uint8_t> body{decoder_.frame().type, 0};
        body.insert(body.end(), caps_.begin(), caps_.end());
        std::vector<std::uint8_t> out;
        device::encode_frame(
            device::Frame{decoder_.frame().seq, static_cast<std::uint8_t>(device::Msg::ack), body},
            out);
        rx_.insert(rx_.end(), out.begin(), out.end());
      }
  }
  std::size_t read(std::uint8_t* buf, std::size_t max, int) override {
    std::size_t k = 0;
    while (k < max && !rx_.empty()) {
      buf[k++] = rx_.front();
      rx_.pop_front();
    }
    return k;
  }

 private:
  std::vector<std::uint8_t> caps_;
  device::FrameDecoder decoder_;
  std::deque<std::uint8_t> rx_;
};

std::vector<std::uint8_t> caps_bytes(std::uint8_t protocol, std::size_t size) {
  device::Capabilities c;
  c.protocol = protocol;
  c.max_pulse_rate_hz = 1209;
  c.features = device::kFeatureShapedPulses;
  std::vector<std::uint8_t> b;
  device::put_capabilities(b, c);
  b.resize(size);
  return b;
}

device::Capabilities identify(const std::vector<std::uint8_t>& caps) {
  IdentifyOnly dev(caps);
  host::StimulatorClient client(dev);
  return client.identify();
}

}  // namespace

TEST_CASE("the host speaks protocols 5 to 7, a version 5 device without shaped pulses",
          "[host][session]") {
  const device::Capabilities v7 = identify(caps_bytes(7, device::kCapabilitiesSize));
  CHECK(v7.protocol == 7);
  CHECK(v7.shaped_pulses());
  const device::Capabilities v6 = identify(caps_bytes(6, device::kCapabilitiesSizeV6));
  CHECK(v6.protocol == 6);
  CHECK(v6.shaped_pulses());
  CHECK(v6.max_phases == 16);
  CHECK(v6.max_edge_rate_hz == 160000);
  CHECK(v6.compliance_V == 0);
  const device::Capabilities v5 = identify(caps_bytes(5, device::kCapabilitiesSizeV5));
  CHECK(v5.protocol == 5);
  CHECK(!v5.shaped_pulses());
  CHECK(v5.max_phases == 0);
  CHECK(v5.max_edge_rate_hz == 4 * 1209);
  CHECK(v5.max_pulse_rate_hz == 1209);
  for (int other : {4, 8})
    CHECK(message_of([&] {
            identify(caps_bytes(static_cast<std::uint8_t>(other), device::kCapabilitiesSize));
          }) ==
          "device speaks protocol version " + std::to_string(other) +
              "; stimctl speaks versions 5 to 7");
  // The length must be the one of its version.
  CHECK(message_of([] { identify(caps_bytes(5, device::kCapabilitiesSize)); }) ==
        "device sent malformed capabilities");
  CHECK(message_of([] { identify(caps_bytes(6, device::kCapabilitiesSize)); }) ==
        "device sent malformed capabilities");
  CHECK(message_of([] { identify(caps_bytes(7, device::kCapabilitiesSizeV6)); }) ==
        "device sent malformed capabilities");
}

TEST_CASE("the in-process emulator delivers a shaped pulse and records its phases",
          "[host][session]") {
  char path[] = "/tmp/tp-shaped-XXXXXX";
  const int fd = mkstemp(path);
  REQUIRE(fd >= 0);
  close(fd);
  {
    host::EmulatorOptions emu;
    emu.caps.channels = 4;
    emu.record_path = path;
    auto link = host::open_transport("emu", 115200, emu);
    // Raw frames (the client's set_shape is the host's next step): one request, its result.
    std::uint8_t seq = 0;
    auto ask = [&](device::Msg type, const std::vector<std::uint8_t>& payload,
                   std::vector<std::uint8_t>* body = nullptr) {
      std::vector<std::uint8_t> bytes;
      device::encode_frame(device::Frame{++seq, static_cast<std::uint8_t>(type), payload}, bytes);
      link->write(bytes.data(), bytes.size());
      device::FrameDecoder d;
      std::uint8_t buf[512];
      for (int tries = 0; tries < 10; ++tries) {
        const std::size_t n = link->read(buf, sizeof buf, 10);
        for (std::size_t i = 0; i < n; ++i)
          if (d.push(buf[i])) {
            if (body) body->assign(d.frame().payload.begin() + 2, d.frame().payload.end());
            return static_cast<device::Result>(d.frame().payload[1]);
          }
      }
      FAIL("no acknowledgement");
      return device::Result::ok;
    };
    std::vector<std::uint8_t> ident;
    REQUIRE(ask(device::Msg::identify, {}, &ident) == device::Result::ok);
    const auto caps = device::decode_capabilities(ident, 0);
    REQUIRE(caps);
    CHECK(caps->shaped_pulses());  // the emulators claim shapes: their records are checked here
    const std::uint32_t token = 0x5AFE;
    std::vector<std::uint8_t> table;
    device::put_u32(table, token);
    device::put_u16(table, 1);
    table.push_back(4);
    device::put_u16(table, 100);
    REQUIRE(ask(device::Msg::configure_table, table) == device::Result::ok);
    const auto t = device::shaped_timing(5000, {{500, 1}, {200, 10}, {50, 0}, {500, -5}}, 0, 3);
    REQUIRE(ask(device::Msg::set_shape, device::shape_frame(token, 0, t)) == device::Result::ok);
    std::vector<std::uint8_t> codes;
    device::put_u32(codes, token);
    device::put_u16(codes, 0);
    const auto sparse = device::encode_sparse({100, -60, -40, 0});
    codes.insert(codes.end(), sparse.begin(), sparse.end());
    REQUIRE(ask(device::Msg::set_codes, codes) == device::Result::ok);
    REQUIRE(ask(device::Msg::start, device::with_session(token, {})) == device::Result::ok);
    std::vector<std::uint8_t> status;
    for (int k = 0; k < 100; ++k) {  // 3 pulses 5 ms apart: complete in 10 ms
      REQUIRE(ask(device::Msg::status, {}, &status) == device::Result::ok);
      if (device::decode_status(status, 0)->fault == device::Fault::completed) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    CHECK(device::decode_status(status, 0)->pulses == 3);
  }
  std::ifstream in(path);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    CHECK(j["t_s"].get<double>() == Approx(0.005 * n).margin(1e-9));
    CHECK(j["phases"] == nlohmann::json::parse(
                             R"([{"duration_us": 500, "units": 1}, {"duration_us": 200, "units": 10},
                                 {"duration_us": 50, "units": 0}, {"duration_us": 500, "units": -5}])"));
    CHECK(j["unit_currents_mA"] == nlohmann::json::array({0.0977, -0.05862, -0.03908, 0}));
    CHECK(j["net_charge_nC"] == nlohmann::json::array({0, 0, 0, 0}));
    ++n;
  }
  CHECK(n == 3);
  std::remove(path);
}

TEST_CASE("a shaped stimulus is planned as a table, or refused before anything is sent",
          "[host][session]") {
  Mix m;
  Stimulus s;
  s.currents_mA = {1.0, -0.5, -0.5, 0};
  s.count = 10;
  s.shape.phases = {{500, 0.1}, {200, 1}, {50, 0}, {500, -0.5}};
  m.patterns = {s};
  host::SessionOptions opt;
  device::Capabilities caps;
  caps.channels = 4;
  caps.features = device::kFeatureShapedPulses;
  const host::SessionPlan plan = host::plan_session(caps, m, opt);
  CHECK(plan.table);
  REQUIRE(plan.timings.size() == 1);
  CHECK(plan.timings[0].shape.n == 4);
  CHECK(plan.timings[0].shape.units[1] == 10);  // U = 10
  // Base codes: 1 mA at level 1 is 10 x 102 codes of 977 nA (0.99654 mA).
  CHECK(plan.table_codes[0] == std::vector<std::int16_t>{102, -51, -51, 0});
  // A device without shapes: the firmware today, and any version 5 device.
  device::Capabilities none = caps;
  none.features = 0;
  CHECK(message_of([&] { host::plan_session(none, m, opt); }) ==
        "the device cannot deliver shaped pulses (pulse.phases): its capabilities claim none");
  none.protocol = 5;
  CHECK(message_of([&] { host::plan_session(none, m, opt); }) ==
        "the device speaks protocol 5: it cannot deliver shaped pulses (pulse.phases; protocol 6)");
  // A device whose shortest phase is 100 us: the 50 us gap is outside its limits (the
  // host's check with the device's limits, before the device's own rules).
  device::Capabilities slow = caps;
  slow.min_width_us = 100;
  CHECK(message_of([&] { host::plan_session(slow, m, opt); }) ==
        "phase 3: duration 50 us outside [100, 8000] us");
  // More edges a second than the device makes: 5 edges at 200 Hz.
  device::Capabilities edges = caps;
  edges.max_edge_rate_hz = 999;
  CHECK(message_of([&] { host::plan_session(edges, m, opt); }) ==
        "the stimulus asks 1000 phase edges a second; the device makes at most 999 a second on "
        "time: lower the rates or use fewer phases (docs/safety.md)");
  // Fewer phases than the shape has.
  device::Capabilities few = caps;
  few.max_phases = 3;
  CHECK(message_of([&] { host::plan_session(few, m, opt); }) ==
        "4 phases, more than the device's 3");
}
