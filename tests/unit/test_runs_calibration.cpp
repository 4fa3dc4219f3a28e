// calibrate's request and session (lib/requests/calibrate, lib/runs/calibration_run): the
// typed options parsed with their flags' names; a whole session over the in-process
// emulator with a scripted observer (what it is told, the log, the profile); its refusals
// and stops, each with its message and nothing left behind that should not be.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <csignal>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "error_support.hpp"
#include "render_support.hpp"
#include "psych/calibration.hpp"
#include "requests/calibrate.hpp"
#include "runs/calibration_run.hpp"

using namespace tp;
using tp::render_test::two_pads;
using tp::test::code_of;
using tp::test::message_of;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

// An observer who feels what is above threshold_mA and finds too strong what is above
// comfort_mA, reading the level from the trial's line as a person hears it; or who says
// `script`'s answers in turn.  Everything said is kept.
class Scripted : public runs::Respondent {
 public:
  Scripted(double threshold_mA, double comfort_mA) : thr_(threshold_mA), comfort_(comfort_mA) {}
  explicit Scripted(std::vector<std::string> script) : script_(std::move(script)) {}
  void say(const std::string& text) override {
    said += text;
    if (text.rfind("trial ", 0) == 0) level_ = std::stod(text.substr(text.rfind("), ") + 3));
    if (text.rfind("too strong?", 0) == 0) comfort_question_ = true;
    if (text.rfind("felt it?", 0) == 0) comfort_question_ = false;
  }
  bool stop_key(int) override { return false; }
  bool gone() const override { return false; }
  std::string stop_key_name() const override { return ""; }
  std::optional<host::Answer> answer(const volatile std::sig_atomic_t*) override {
    std::string given;
    if (!script_.empty()) {
      given = script_.at(next_++);
    } else {
      given = level_ > (comfort_question_ ? comfort_ : thr_) ? "y" : "n";
    }
    host::Answer a;
    a.given = given;
    a.kind = given == "y" ? host::Answer::yes : given == "q" ? host::Answer::stop : host::Answer::no;
    return a;
  }
  std::string said;

 private:
  double thr_ = 0, comfort_ = 0, level_ = 0;
  bool comfort_question_ = false;
  std::vector<std::string> script_;
  std::size_t next_ = 0;
};

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

struct TempLog {
  std::string path = "test-runs-calibration-" + std::to_string(::getpid()) + ".csv";
  ~TempLog() { std::remove(path.c_str()); }
};

CalibrateRequest sai_request(const std::string& log) {
  CalibrateRequest r;
  r.log_path = log;
  r.pixel = "1,0";
  r.spec.primaries = "SAI";
  r.spec.trial_s = "0.05";
  r.spec.reversals = 4;
  r.spec.max_trials = 40;
  return r;
}

}  // namespace

TEST_CASE("calibrate's typed options are parsed with their flags' names", "[requests]") {
  CalibrationSpec s;
  const CalibrationOptions d = calibration_options(s);
  CHECK(d.staircase.ceiling_mA == 1.0);
  CHECK(d.staircase.start_mA == 0.05);
  CHECK(d.staircase.ascend_factor == 1.25);
  CHECK(d.staircase.step_factor == 1.25);
  CHECK(d.staircase.max_step_up == 1.5);
  CHECK(d.staircase.down == 2);
  CHECK(d.trial_s == 0.5);
  CHECK(d.width_us == 200.0);
  CHECK(d.balance_width_us == 200.0);
  CHECK(d.primaries.empty());
  CHECK(d.rate_hz == std::array<double, 3>{30.0, 200.0, 250.0});
  s.rates = "SAI:100";
  s.primaries = "PC,RA";
  s.width_us = "150";
  const CalibrationOptions o = calibration_options(s);
  CHECK(o.rate_hz[1] == 100.0);
  CHECK(o.primaries == std::vector<int>{2, 0});
  CHECK(o.balance_width_us == 150.0);
  // The first flag that is not a number, in the program's order.
  s.start_mA = "low";
  s.width_us = "wide";
  CHECK_THAT(message_of([&] { calibration_options(s); }), Contains("--start"));
  CalibrateRequest r;
  r.spec.ceiling_mA = "2.5";
  r.log_path = "x.csv";
  const PixelBank b = two_pads();
  CHECK(code_of([&] { make_calibration(b, r); }) == ExitCode::bad_input);
  CHECK_THAT(message_of([&] { make_calibration(b, r); }), Contains("--ceiling: 2.5 mA outside (0, 2] mA"));
  r.spec.ceiling_mA = "1";
  r.log_path = "/nonexistent/dir/x.csv";
  CHECK_THAT(message_of([&] { make_calibration(b, r); }),
             Contains("--log: cannot open '/nonexistent/dir/x.csv'"));
}

TEST_CASE("a calibration session over the emulator finds a scripted observer's range",
          "[runs]") {
  const PixelBank b = two_pads();
  TempLog log;
  const CalibrateRequest r = sai_request(log.path);
  Calibration cal = make_calibration(b, r);
  Scripted person(0.2, 0.5);
  std::vector<std::string> told;
  const volatile std::sig_atomic_t flag = 0;
  const Profile p = runs::run_calibration(r, b, cal, person, &flag,
                                          [&](const std::string& l) { told.push_back(l); });
  REQUIRE(p.primary[1].has_value());
  CHECK(!p.primary[0].has_value());
  const double step = std::log(std::sqrt(1.25)) + 1e-9;
  CHECK(std::fabs(std::log(p.primary[1]->threshold_mA / 0.2)) <= step);
  CHECK(std::fabs(std::log(p.primary[1]->comfort_mA / 0.5)) <= step);
  // Told: the length up front, each staircase as it starts, each trial and its answer.
  CHECK_THAT(person.said, StartsWith("calibrate: SAI at 1 pixel: 2 staircases, about "));
  CHECK_THAT(person.said, Contains("\ntrial 1: SAI at (1, 0), 0.05 mA ... felt it? [y/n] n\n"));
  CHECK_THAT(person.said, Contains("at pixel (1, 0), 1 of 1: the comfort limit, too strong?\n"));
  // The log: its header and a row a trial; stderr's last line the summary.
  const std::vector<std::string> rows = lines_of(log.path);
  REQUIRE(rows.size() == cal.trials().size() + 1);
  CHECK(rows[0] == calibration_log_header());
  // The first row: the trial, then the 10 pulses the device delivered and their peak,
  // 0.05 mA as the device's current steps make it.
  const std::string row = calibration_log_row(cal.trials()[0], 2, 10, 0.05);
  CHECK(row == "1,SAI,1,1,0,felt,0.05,ascending,no,0,10,0.05");
  const std::size_t peak_at = rows[1].rfind(',') + 1;
  CHECK(rows[1].substr(0, peak_at) == row.substr(0, row.rfind(',') + 1));
  CHECK(std::stod(rows[1].substr(peak_at)) == Approx(0.05).epsilon(0.01));
  REQUIRE(!told.empty());
  CHECK(told.back() == "calibrate: " + cal.summary());
}

TEST_CASE("a calibration session's refusals and stops say why", "[runs]") {
  const PixelBank b = two_pads();
  TempLog log;
  CalibrateRequest r = sai_request(log.path);
  const volatile std::sig_atomic_t no_signal = 0;
  std::vector<std::string> told;
  auto tell = [&](const std::string& l) { told.push_back(l); };
  SECTION("q after the first trial") {
    Calibration cal = make_calibration(b, r);
    Scripted person({"q"});
    CHECK(message_of([&] { runs::run_calibration(r, b, cal, person, &no_signal, tell); }) ==
          "stopped by the user (q) after trial 1; nothing running");
    CHECK(lines_of(log.path).size() == 1);  // the header, no row
  }
  SECTION("nothing felt: the notes, then no profile") {
    r.spec.ceiling_mA = "0.1";
    Calibration cal = make_calibration(b, r);
    Scripted person(5, 5);
    CHECK(message_of([&] { runs::run_calibration(r, b, cal, person, &no_signal, tell); }) ==
          "no primary found (said above): no profile; the log has every trial");
    REQUIRE(told.size() == 1);
    CHECK_THAT(told[0], StartsWith("calibrate: SAI at pixel (1, 0): not felt up to the ceiling"));
  }
  SECTION("a device of one channel: refused before anything is sent, no log") {
    r.emu_channels = 1;
    Calibration cal = make_calibration(b, r);
    Scripted person(0.2, 0.5);
    CHECK(code_of([&] { runs::run_calibration(r, b, cal, person, &no_signal, tell); }) ==
          ExitCode::bad_input);
    CHECK(person.said.empty());
    CHECK(::access(log.path.c_str(), F_OK) != 0);
  }
  SECTION("a signal: 128 + its number, before the first trial") {
    Calibration cal = make_calibration(b, r);
    Scripted person(0.2, 0.5);
    const volatile std::sig_atomic_t sigint = SIGINT;
    CHECK(message_of([&] { runs::run_calibration(r, b, cal, person, &sigint, tell); }) ==
          "stopped by SIGINT; output stopped");
    CHECK(static_cast<int>(code_of([&] {
            Calibration again = make_calibration(b, r);
            runs::run_calibration(r, b, again, person, &sigint, tell);
          })) == 128 + SIGINT);
    CHECK(cal.trials().empty());
  }
}
