// make-pulse's request (lib/requests/pulse.hpp): the flags' texts as a PulseRequest (the
// defaults, --profile's combinations with the program's messages, in its order), the
// plan's checks (--csv-pulses) and stderr lines, and the output through the writer.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "error_support.hpp"
#include "requests/pulse.hpp"

using namespace tp;
using tp::test::message_of;

namespace {

// The SAI mode's shape of weights on the paper's array (sums to zero).
Document weights_document() {
  Document d;
  d.weights = std::vector<double>{0, 0, -0.5, 1, -0.5, 0, 0, 0};
  return d;
}

MakePulseOptions with_amplitude(const std::string& amplitude) {
  MakePulseOptions o;
  o.amplitude = amplitude;
  return o;
}

// A path no profile is at: a refusal that comes first shows it was never read.
const char* const kNoFile = "/nonexistent/tp-unit-profile.json";

}  // namespace

TEST_CASE("make-pulse: the flags' defaults as a PulseRequest", "[requests][pulse]") {
  const PulseRequest r = pulse_request_of(weights_document(), with_amplitude("1.5"));
  REQUIRE(r.amplitude_mA);
  CHECK(*r.amplitude_mA == 1.5);
  CHECK(!r.intensity);
  CHECK(!r.profile);
  CHECK(r.frequency_hz == 200.0);
  CHECK(!r.width_us);  // not given: the document's pulse, else 200 us symmetric
  CHECK(!r.balance_width_us);
  CHECK(!r.interphase_us);
  CHECK(r.phases.empty());
  CHECK(!r.count);
  CHECK(!r.duration_s);
  const Stimulus s = make_stimulus(weights_document(), r);
  CHECK(!s.shape.shaped());
  CHECK(s.shape.width_us == 200.0);
  CHECK(s.shape.balance_width_us == 200.0);
  CHECK(s.shape.interphase_us == 0.0);
  MakePulseOptions o = with_amplitude("1");
  o.balance_width = "800";
  o.count = "2";
  o.interphase = "50";
  const PulseRequest given = pulse_request_of(weights_document(), o);
  CHECK(*given.balance_width_us == 800.0);
  CHECK(*given.count == 2);
  CHECK(*given.interphase_us == 50.0);
  CHECK(make_stimulus(weights_document(), given).shape.width_us == 200.0);
}

TEST_CASE("make-pulse: phases, and the document's pulse as the default", "[requests][pulse]") {
  MakePulseOptions o = with_amplitude("1");
  o.phases = "500:0.1,200:1,500:-0.5";
  const MakePulsePlan shaped = plan_make_pulse(weights_document(), o);
  REQUIRE(shaped.stimulus.shape.phases.size() == 3);
  CHECK(shaped.stimulus.shape.phases[0].level == 0.1);
  o.width = "100";
  CHECK(message_of([&] { plan_make_pulse(weights_document(), o); }) ==
        "--phases excludes --width, --balance-width and --interphase");
  // A document that carries a pulse: used when no pulse flag is given, replaced (and said)
  // when one is.
  Document doc = weights_document();
  doc.extra["pulse"] = Json{{"phases", Json::array({Json{{"duration_us", 100}, {"level", 1}},
                                                    Json{{"duration_us", 400}, {"level", -0.25}}})}};
  const MakePulsePlan carried = plan_make_pulse(doc, with_amplitude("1"));
  REQUIRE(carried.stimulus.shape.phases.size() == 2);
  CHECK(carried.stimulus.shape.phases[1].duration_us == 400);
  CHECK(carried.notes.size() == 1);  // the safety figures only
  MakePulseOptions flags = with_amplitude("1");
  flags.width = "150";
  const MakePulsePlan replaced = plan_make_pulse(doc, flags);
  CHECK(!replaced.stimulus.shape.shaped());
  REQUIRE(replaced.notes.size() == 2);
  CHECK(replaced.notes[1] ==
        "the document's pulse (shaped (100 us at 1, 400 us at -0.25)) replaced by the flags' "
        "(150 us biphasic)");
  doc.extra["pulse"] = Json{{"phases", 3}};
  CHECK(message_of([&] { plan_make_pulse(doc, with_amplitude("1")); }) ==
        "weights document: pulse.phases: expected an array of {\"duration_us\", \"level\"}");
}

TEST_CASE("make-pulse: --profile's combinations, in the program's order", "[requests][pulse]") {
  const Document doc = weights_document();
  // stdin cannot carry both, refused before any number is parsed.
  MakePulseOptions o = with_amplitude("abc");
  o.profile = "-";
  CHECK(message_of([&] { pulse_request_of(doc, o); }) == "--profile -: stdin carries the weights");
  o.input = "weights.json";  // a file carries them: stdin is free for the profile
  CHECK(message_of([&] { pulse_request_of(doc, o); }) == "--amplitude: not a number 'abc'");
  // The profile is read only with --intensity and without --amplitude.
  o = with_amplitude("1");
  o.profile = kNoFile;
  CHECK(message_of([&] { pulse_request_of(doc, o); }) ==
        "give --amplitude MA, or --intensity V with --profile");
  o.amplitude.clear();
  CHECK(message_of([&] { pulse_request_of(doc, o); }) == "--profile: needs --intensity");
  // A document without weights: the profile is not read; the stimulus refuses.
  o.intensity = "0.5";
  const Document none;
  CHECK(message_of([&] { plan_make_pulse(none, o); }) == "weights document: no 'weights'");
  CHECK_THAT(message_of([&] { pulse_request_of(doc, o); }), Catch::StartsWith("profile: "));
  // Neither: make_stimulus's message.
  CHECK(message_of([&] { plan_make_pulse(doc, MakePulseOptions{}); }) ==
        "give --amplitude MA, or --intensity V with --profile");
}

TEST_CASE("make-pulse: --csv-pulses is checked with --format csv only, before any line",
          "[requests][pulse]") {
  MakePulseOptions o = with_amplitude("1");
  o.csv_pulses = "0";
  CHECK(message_of([&] { plan_make_pulse(weights_document(), o); }).empty());
  o.csv = true;
  CHECK(message_of([&] { plan_make_pulse(weights_document(), o); }) ==
        "--csv-pulses: 0 outside [1, 100000]");
  o.csv_pulses = "100001";
  CHECK(message_of([&] { plan_make_pulse(weights_document(), o); }) ==
        "--csv-pulses: 100001 outside [1, 100000]");
  o.csv_pulses = "1.5";
  CHECK_THAT(message_of([&] { plan_make_pulse(weights_document(), o); }),
             Catch::StartsWith("--csv-pulses: "));
}

TEST_CASE("make-pulse: the safety figures' line and the output through the writer",
          "[requests][pulse]") {
  Document doc = weights_document();
  MakePulseOptions o = with_amplitude("1");
  o.count = "1";
  MakePulsePlan plan = plan_make_pulse(doc, o);
  REQUIRE(plan.notes.size() == 1);  // no thresholds carried: no second line
  CHECK(plan.notes[0] ==
        "8 channels, 1 pulses at 200 Hz; peak 1 mA, charge/phase 200 nC, 4 uC/cm2, RMS "
        "0.2828427125 mA, net charge 0 nC");
  std::string text;
  const auto sink = [&](std::string_view b) { text.append(b); };
  write_make_pulse(plan, sink);
  CHECK(text.front() == '{');
  CHECK(text.find("\"currents_mA\"") != std::string::npos);
  o.csv = true;
  plan = plan_make_pulse(doc, o);
  CHECK(plan.csv_pulses == 3);
  text.clear();
  write_make_pulse(plan, sink);
  CHECK(
      text.rfind("t_us,ch0_mA,ch1_mA,ch2_mA,ch3_mA,ch4_mA,ch5_mA,ch6_mA,ch7_mA\n0,0,0,0,0,0,0,0,0\n"
                 "0,0,0,-0.5,1,-0.5,0,0,0\n",
                 0) == 0);
}
