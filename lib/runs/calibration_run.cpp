#include "runs/calibration_run.hpp"

#include <cmath>
#include <cstdint>
#include <memory>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/number.hpp"
#include "host/session.hpp"
#include "host/skin_file.hpp"
#include "host/signals.hpp"
#include "host/stimulator.hpp"
#include "host/terminal.hpp"
#include "host/transport.hpp"
#include "model/primaries.hpp"
#include "render/model_profile.hpp"
#include "render/recruitment.hpp"

namespace tp::runs {
namespace {

[[noreturn]] void stopped_by_signal(int sig) {
  throw Error(static_cast<ExitCode>(128 + sig),
              "stopped by " + host::signal_name(sig) + "; output stopped");
}

// "trial 3: SAI at (4, 4), 0.0781 mA ... "
std::string trial_text(const Calibration& cal, int n, int columns) {
  return "trial " + std::to_string(n) + ": " + kPrimaries[static_cast<std::size_t>(cal.primary())] +
         " at (" + std::to_string(cal.pad() % columns) + ", " + std::to_string(cal.pad() / columns) +
         "), " + number_text(std::round(cal.level_mA() * 1e4) / 1e4) + " mA ... ";
}

// The trial's stimulus delivered while the keys are watched for a stop: its report, or
// the failure that a signal, a stop key or a terminal gone makes.
host::SessionReport deliver(const Calibration& cal, host::Transport& transport, Respondent& person,
                            const volatile std::sig_atomic_t* flag, int n) {
  bool by_key = false;
  const host::SessionReport r = host::run_watched(
      transport, cal.stimulus(), host::SessionOptions{}, flag,
      [&](int ms) { return person.stop_key(ms); }, by_key);
  if (*flag) stopped_by_signal(*flag);
  if (by_key && person.gone())
    failure("the terminal is gone during trial " + std::to_string(n) + "; output stopped");
  if (by_key) {
    person.say("stopped\n");
    failure("stopped by the user (" + person.stop_key_name() + ") during trial " +
            std::to_string(n) + "; output stopped");
  }
  if (r.exit_code != 0) stopped_by_signal(r.exit_code - 128);
  return r;
}

// Each channel's impedance (kOhm; 0 where it carried no current or none flowed).
std::vector<double> impedances_kohm(const std::vector<device::ChannelMeasurement>& m) {
  std::vector<double> z;
  for (const auto& c : m)
    z.push_back(c.carried && c.impedance_ohm != device::kOpenOhm ? c.impedance_ohm * 1e-3 : 0.0);
  return z;
}

// One trial: its stimulus delivered, then the question; the answer goes to the
// calibration and the log.
void run_trial(Calibration& cal, host::Transport& transport, Respondent& person, LineFile& log,
               const volatile std::sig_atomic_t* flag, int columns) {
  if (*flag) stopped_by_signal(*flag);
  const std::string stage = cal.stage_text();
  if (!stage.empty()) person.say("calibrate: " + stage + "\n");
  const int n = static_cast<int>(cal.trials().size()) + 1;
  person.say(trial_text(cal, n, columns));
  const host::SessionReport r = deliver(cal, transport, person, flag, n);
  person.say(cal.comfort() ? "too strong? [y/n] " : "felt it? [y/n] ");
  const auto a = person.answer(flag);
  if (!a) stopped_by_signal(*flag);
  person.say(a->given + "\n");
  if (a->kind == host::Answer::stop)
    failure("stopped by the user (" + a->given + ") after trial " + std::to_string(n) +
            "; nothing running");
  // A device that measures: the impedances at this trial's end, for the profile.
  if (!r.measured.empty()) cal.measured(impedances_kohm(r.measured));
  cal.respond(a->kind == host::Answer::yes);
  log.line(calibration_log_row(cal.trials().back(), columns, r.pulses, r.peak_mA));
}

// The port (the emulator with the bank's pads unless told).
std::unique_ptr<host::Transport> open_port(const CalibrateRequest& r, const PixelBank& bank) {
  host::EmulatorOptions emu;
  emu.caps.channels = static_cast<std::uint8_t>(r.emu_channels > 0 ? r.emu_channels
                                                                    : static_cast<int>(bank.pads()));
  emu.record_path = r.record_path;
  if (!r.emu_skin_path.empty())
    emu.skin = host::emulator_skin(r.emu_skin_path, r.emu_compliance_V, emu.caps.channels,
                                   "--emu-skin", "--emu-compliance-v");
  return host::open_transport(r.port, r.baud, emu);
}

// What was found, for stderr: the notes, then the summary; a runtime failure (after the
// notes) when no primary was.  The profile gains the model's thresholds beside the
// person's (a note for each primary the model gives none).
Profile finish(const Calibration& cal, const PixelBank& bank, const CalibrateRequest& r,
               const std::function<void(const std::string&)>& tell) {
  for (const std::string& note : cal.notes()) tell("calibrate: " + note);
  Profile p = cal.profile();
  bool any = false;
  for (const auto& range : p.primary) any = any || range.has_value();
  if (!any) failure("no primary found (said above): no profile; the log has every trial");
  // The model's prediction beside each measured threshold (docs/calibration.md).
  const CalibrationOptions o = calibration_options(r.spec);
  PulseSpec pulse;
  pulse.width_us = o.width_us;
  pulse.balance_width_us = o.balance_width_us;
  for (const std::string& note :
       add_model_thresholds(p, bank, "mrg", pulse, bank.doc.max_current_mA))
    tell("calibrate: note: " + note);
  if (bank.recruitment) add_colours(p, *bank.recruitment);  // the modes' colours for this person
  tell("calibrate: " + cal.summary());
  return p;
}

}  // namespace

Profile run_calibration(const CalibrateRequest& r, const PixelBank& bank, Calibration& cal,
                        Respondent& person, const volatile std::sig_atomic_t* flag,
                        const std::function<void(const std::string&)>& tell) {
  const auto transport = open_port(r, bank);
  const host::EmergencyStopArmed armed(transport->native_handle());  // until the port closes
  // Every trial at the ceiling against the device's capabilities, as each trial's session
  // will check it (run_watched's count is the stimulus's own), before the first is sent.
  const device::Capabilities caps = host::StimulatorClient(*transport).identify();
  cal.check_trials([&](const Mix& m) { host::plan_session(caps, m, host::SessionOptions{}); });
  LineFile log(r.log_path, "--log");
  log.line(calibration_log_header());
  person.say("calibrate: " + cal.length_text() + "\n");
  while (!cal.done()) run_trial(cal, *transport, person, log, flag, bank.columns);
  log.close();
  return finish(cal, bank, r, tell);
}

}  // namespace tp::runs
