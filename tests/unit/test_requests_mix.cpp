// mix-stimuli's request (lib/requests/mix.hpp): the inputs' and the intensities' checks
// with the program's messages, the staggered phases against their closed form, given
// phases, and the rescale to the person's range.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "requests/mix.hpp"

using namespace tp;

namespace {

Stimulus pattern(double frequency_hz, const std::string& mode = "") {
  Stimulus s;
  s.currents_mA = {1.0, -1.0};
  s.shape.frequency_hz = frequency_hz;
  s.count = 10;
  s.amplitude_mA = 1.0;
  if (!mode.empty()) s.carried["mode"] = mode;
  return s;
}

Mix single(const Stimulus& s) {
  Mix m;
  m.patterns.push_back(s);
  return m;
}

template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::bad_input);
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("mix request: the inputs' names are checked before any is read") {
  CHECK(refusal([] { check_mix_inputs({"a.json", "-", "b.json", "-"}); }) ==
        "- (stdin) given more than once");
  CHECK(refusal([] { check_mix_inputs(std::vector<std::string>(device::kMaxPatterns + 1, "f")); }) ==
        std::to_string(device::kMaxPatterns + 1) + " inputs, more than a device holds (" +
            std::to_string(device::kMaxPatterns) + " patterns)");
  CHECK(refusal([] { check_mix_inputs({"a.json", "-"}); }) == "accepted");
  MixRequest r;
  Mix two = single(pattern(100));
  two.patterns.push_back(pattern(50));
  CHECK(refusal([&] { add_mix_input(r, "m.json", two); }) == "m.json: already a mix; give its parts");
  CHECK(r.patterns.empty());
}

TEST_CASE("mix request: --intensities and --profile together, one intensity per input") {
  MixRequest r;
  add_mix_input(r, "-", single(pattern(100)));
  add_mix_input(r, "b.json", single(pattern(50)));
  CHECK(refusal([&] { check_mix_intensities(r, true, false, false); }) ==
        "--intensities and --profile: give both, or neither");
  CHECK(refusal([&] { check_mix_intensities(r, false, true, false); }) ==
        "--intensities and --profile: give both, or neither");
  CHECK(refusal([&] { check_mix_intensities(r, true, true, true); }) ==
        "--profile -: stdin is an input");
  r.intensities = std::vector<double>{0.5};
  CHECK(refusal([&] { check_mix_intensities(r, true, true, false); }) ==
        "--intensities: 1 for 2 inputs");
  r.intensities = std::vector<double>{0.5, 0.5};
  CHECK(refusal([&] { check_mix_intensities(r, true, true, false); }) == "accepted");
}

TEST_CASE("mix request: staggered phases follow the previous patterns' pulses and gaps") {
  MixRequest r;
  r.gap_us = 150;
  for (const char* n : {"a", "b", "c"}) add_mix_input(r, n, single(pattern(100)));
  const Mix m = run_mix(r);
  REQUIRE(m.patterns.size() == 3);
  const double step = 200 + 0 + 200 + 150;  // width + interphase + balance + gap
  CHECK(m.patterns[0].phase_us == 0);
  CHECK(m.patterns[1].phase_us == Approx(step));
  CHECK(m.patterns[2].phase_us == Approx(2 * step));
  CHECK(m.gap_us == 150);
  r.phases_us = std::vector<double>{0, 5000};
  CHECK(refusal([&] { run_mix(r); }) == "--phase: 2 phases for 3 patterns");
  r.phases_us = std::vector<double>{0, 5000, 1000};
  CHECK(run_mix(r).patterns[1].phase_us == 5000);
}

TEST_CASE("mix request: intensities rescale each pattern to the person's range") {
  MixRequest r;
  add_mix_input(r, "ra.json", single(pattern(30, "RA")));
  add_mix_input(r, "x.json", single(pattern(200)));
  Profile p;
  p.primary[0] = PrimaryRange{0.4, 1.2};
  r.profile = p;
  r.intensities = std::vector<double>{0.5, 0.5};
  CHECK(refusal([&] { run_mix(r); }) ==
        "x.json: names no mode (make-pulse carries optimize-weights' mode)");
  r.patterns.pop_back();
  r.names.pop_back();
  r.intensities = std::vector<double>{0.5};
  const Mix m = run_mix(r);
  CHECK(m.patterns[0].amplitude_mA == Approx(0.8));  // 0.4 + 0.5 (1.2 - 0.4)
  CHECK(m.patterns[0].currents_mA[0] == Approx(0.8));
  CHECK(m.patterns[0].currents_mA[1] == Approx(-0.8));
}
