// stimctl's request (lib/host/delivery), which Python's Stimulator shares: the options'
// combinations and their messages, the duration's check, and what the program says while
// and after the output runs.
#include <catch2/catch.hpp>

#include <string>

#include "core/error.hpp"
#include "error_support.hpp"
#include "host/delivery.hpp"

using namespace tp;
using tp::test::code_of;
using tp::test::message_of;

namespace {

Mix one_pattern() {
  Stimulus s;
  s.currents_mA = {0, 0, -0.5, 1, -0.5, 0, 0, 0};
  s.amplitude_mA = 1;
  s.count = 200;
  Mix m;
  m.patterns.push_back(s);
  return m;
}

host::SessionReport report(std::uint32_t pulses, double scheduled) {
  host::SessionReport r;
  r.port = "emu (in-process emulator)";
  r.end = "stimulus complete";
  r.started = true;
  r.pulses = pulses;
  r.scheduled = scheduled;
  r.peak_mA = 1;
  r.seconds = 1.004;
  return r;
}

}  // namespace

TEST_CASE("delivery: the options' combinations, each refused naming its flag", "[host][delivery]") {
  host::DeliveryRequest r;
  CHECK(code_of([&] { host::check_delivery(r); }) == ExitCode::ok);
  r.live = true;
  CHECK(message_of([&] { host::check_delivery(r); }) ==
        "--live: give the stimulus with --stimulus FILE (stdin carries the frames)");
  r.stimulus_path = "s.json";
  CHECK(code_of([&] { host::check_delivery(r); }) == ExitCode::ok);
  r.port = "/dev/ttyACM0";
  r.record_path = "r.jsonl";
  CHECK(message_of([&] { host::check_delivery(r); }) ==
        "--record: only with --port emu (stim-emu has its own)");
  r.record_path.clear();
  r.emu_channels = 16;
  CHECK(message_of([&] { host::check_delivery(r); }) ==
        "--emu-channels: only with --port emu (a device reports its own channels)");
  r.emu_channels.reset();
  r.live = false;
  r.latency_log = "l.txt";
  CHECK(message_of([&] { host::check_delivery(r); }) ==
        "--latency-log: only with --live (it logs live frames)");
}

TEST_CASE("delivery: the duration above 0 and at most the host's longest, quoted as typed",
          "[host][delivery]") {
  host::DeliveryRequest r;
  CHECK(host::delivery_session(r).duration_s < 0);  // the stimulus' own
  r.duration_s = 2.5;
  CHECK(host::delivery_session(r).duration_s == 2.5);
  r.duration_s = 0;
  r.duration_given = "0.0";
  CHECK(message_of([&] { host::delivery_session(r); }) == "--duration: 0.0 s outside (0, 3600] s");
  // From Python (nothing typed): the number, told apart from the bound it passes.
  r.duration_given.clear();
  r.duration_s = 3600.0000001;
  CHECK(message_of([&] { host::delivery_session(r); }) ==
        "--duration: 3600.0000001 s outside (0, 3600] s");
}

TEST_CASE("delivery: the summary counts against the schedule, a live run without an end alone",
          "[host][delivery]") {
  host::DeliveryRequest r;
  const Mix m = one_pattern();
  CHECK(host::session_summary(report(200, 200), m, r) ==
        "emu (in-process emulator): 200 of 200 pulses on 8 channels at 200 Hz, peak 1 mA, 1 s, "
        "0 retransmissions; stimulus complete; output stopped");
  r.live = true;
  r.stimulus_path = "s.json";
  // The live budget (3600 s of pulses) is not what was asked: the count stands alone.
  const std::string open = host::session_summary(report(832, 720000), m, r);
  CHECK(open.find(": 832 pulses on 8 channels") != std::string::npos);
  CHECK(open.find("720000") == std::string::npos);
  CHECK(open.find(", 0 live frames, ") != std::string::npos);
  r.duration_s = 2;
  CHECK(host::session_summary(report(400, 400), m, r).find(": 400 of 400 pulses") !=
        std::string::npos);

  host::SessionProgress p;
  p.seconds = 1.26;
  p.expected_s = 2;
  p.pulses = 250;
  p.scheduled = 400;
  p.frames = 3;
  CHECK(host::progress_text(p, r) == "1.3 of 2.0 s, 250 of 400 pulses, 3 live frames");
  r.duration_s.reset();
  CHECK(host::progress_text(p, r) == "1.3 s, 250 pulses, 3 live frames");
  r.live = false;
  CHECK(host::progress_text(p, r) == "1.3 of 2.0 s, 250 of 400 pulses");
}

TEST_CASE("delivery: the notes before and after a session", "[host][delivery]") {
  host::SessionReport r = report(0, 200);
  CHECK_FALSE(host::preempted_note(r));
  CHECK_FALSE(host::not_started_note(r));
  r.preempted = true;
  r.started = false;
  r.end = "interrupted (SIGINT)";
  CHECK(*host::preempted_note(r) ==
        "emu (in-process emulator) was running another session's output (its host is gone): "
        "stopped it first");
  CHECK(*host::not_started_note(r) ==
        "emu (in-process emulator): interrupted (SIGINT) before the output started; nothing "
        "delivered");
  // A stimulus that carries no thresholds says nothing about them.
  CHECK_FALSE(host::thresholds_note(one_pattern()));
}
