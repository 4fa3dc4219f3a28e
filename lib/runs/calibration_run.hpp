#pragma once
// calibrate's session (docs/calibration.md): the stimulator opened, every trial at the
// ceiling checked against the device before the first is sent, each trial delivered while
// the person's keys are watched for a stop, then asked; the log written a trial at a time;
// the notes, the summary and the profile at the end.  Above both the host (transports,
// sessions, the terminal) and the model (psych::Calibration): tp_runs, which links both.

#include <csignal>
#include <functional>
#include <optional>
#include <string>

#include "host/answers.hpp"
#include "io/bank.hpp"
#include "psych/calibration.hpp"
#include "psych/profile.hpp"
#include "requests/calibrate.hpp"

namespace tp::runs {

// The person at the device as the session asks: host::Answers (AnswersRespondent), or a
// test's script.
class Respondent {
 public:
  virtual ~Respondent() = default;
  virtual void say(const std::string& text) = 0;  // a prompt, a trial, a stage
  // During a trial: whether a stop key was pressed within timeout_ms (or the terminal went).
  virtual bool stop_key(int timeout_ms) = 0;
  virtual bool gone() const = 0;
  virtual std::string stop_key_name() const = 0;
  // The next answer; empty when *flag was set (a signal) while waiting.
  virtual std::optional<host::Answer> answer(const volatile std::sig_atomic_t* flag) = 0;
};

// host::Answers as a Respondent.
class AnswersRespondent : public Respondent {
 public:
  explicit AnswersRespondent(host::Answers& a) : a_(a) {}
  void say(const std::string& text) override { a_.say(text); }
  bool stop_key(int timeout_ms) override { return a_.stop_key(timeout_ms); }
  bool gone() const override { return a_.gone(); }
  std::string stop_key_name() const override { return a_.stop_key_name(); }
  std::optional<host::Answer> answer(const volatile std::sig_atomic_t* flag) override {
    return a_.answer(flag);
  }

 private:
  host::Answers& a_;
};

// The session of `cal` (make_calibration's, over `bank`) through r's port (the in-process
// emulator with r.emu_channels, else the bank's pads, for emu), asking `person`; *flag is
// host::install_stop_handlers()'s.  `tell` gets the lines for stderr at the end (the
// notes, then the summary: "calibrate: ..." without a newline).  Returns the profile.
// Bad input when a trial at the ceiling is more than the device can deliver (nothing
// sent, no log); a runtime failure when the person stops it ("stopped by the user (q)
// ..."), the terminal goes, or no primary is found (after the notes); exit 128 + signal
// when a signal stops it.
Profile run_calibration(const CalibrateRequest& r, const PixelBank& bank, Calibration& cal,
                        Respondent& person, const volatile std::sig_atomic_t* flag,
                        const std::function<void(const std::string&)>& tell);

}  // namespace tp::runs
