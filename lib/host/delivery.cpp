#include "host/delivery.hpp"

#include "core/ranges.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/number.hpp"
#include "host/skin_file.hpp"
#include "pulse/thresholds.hpp"

namespace tp::host {

void check_delivery(const DeliveryRequest& r) {
  if (r.live && r.stimulus_path == "-")
    bad_input("--live: give the stimulus with --stimulus FILE (stdin carries the frames)");
  if (r.port != "emu" && !r.record_path.empty())
    bad_input("--record: only with --port emu (stim-emu has its own)");
  if (r.port != "emu" && r.emu_channels)
    bad_input("--emu-channels: only with --port emu (a device reports its own channels)");
  if (r.port != "emu" && !r.emu_skin_path.empty())
    bad_input("--emu-skin: only with --port emu (a device's electrodes touch real skin)");
  if (r.emu_compliance_V && r.emu_skin_path.empty())
    bad_input("--emu-compliance-v: applies with --emu-skin (an ideal load needs no voltage)");
  if (!r.latency_log.empty() && !r.live)
    bad_input("--latency-log: only with --live (it logs live frames)");
  if (r.contact_loss != "stop" && r.contact_loss != "suspend")
    bad_input("--contact-loss: " + r.contact_loss + " is not stop or suspend");
  if (r.probe_mA && !r.check_impedance && r.contact_loss != "suspend")
    bad_input("--probe-current: applies with --check-impedance or --contact-loss suspend");
  if (r.probe_mA) ranges::check(*r.probe_mA, ranges::probe_mA, "--probe-current");
}

SessionOptions delivery_session(const DeliveryRequest& r) {
  SessionOptions opt;
  opt.live = r.live;
  opt.suspend_on_contact_loss = r.contact_loss == "suspend";
  opt.hold_sensation = r.hold_sensation;
  if (r.probe_mA) opt.probe_mA = *r.probe_mA;
  opt.latency_log = r.latency_log;
  if (r.duration_s) {
    opt.duration_s = *r.duration_s;
    if (!(opt.duration_s > 0 && opt.duration_s <= opt.limits.max_duration_s))
      bad_input("--duration: " +
                (r.duration_given.empty()
                     ? number_beside(opt.duration_s, 0.0, opt.limits.max_duration_s)
                     : r.duration_given) +
                " s outside (0, " + number_text(opt.limits.max_duration_s) + "] s");
  }
  return opt;
}

std::unique_ptr<Transport> open_delivery(const DeliveryRequest& r) {
  EmulatorOptions emu;
  emu.caps.channels = static_cast<std::uint8_t>(r.emu_channels.value_or(8));
  emu.record_path = r.record_path;
  if (r.port == "emu")
    emu.skin = emulator_skin(r.emu_skin_path, r.emu_compliance_V, emu.caps.channels,
                             "--emu-skin", "--emu-compliance-v");
  return open_transport(r.port, r.baud, emu, r.backend);
}

std::string serial_ports_csv() {
  std::string out = "port,description\n";
  for (const std::string& p : list_serial_ports()) {
    const auto tab = p.find('\t');
    out += p.substr(0, tab) + "," + p.substr(tab + 1) + "\n";
  }
  return out;
}

std::optional<std::string> thresholds_note(const Mix& mix) {
  std::optional<std::string> against;
  for (std::size_t p = 0; p < mix.patterns.size(); ++p) {
    const auto one = stimulus_against_thresholds(mix.patterns[p]);
    if (one)
      against = (against ? *against + "; " : std::string()) +
                (mix.single() ? "" : "pattern " + std::to_string(p) + ": ") + *one;
  }
  return against;
}

std::string progress_text(const SessionProgress& p, const DeliveryRequest& req) {
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f", p.seconds);
  char expected[32];
  std::snprintf(expected, sizeof expected, "%.1f", p.expected_s);
  const bool open_ended = req.live && !req.duration_s;
  std::string text = seconds + (open_ended ? std::string() : std::string(" of ") + expected) +
                     " s, " + std::to_string(p.pulses) +
                     (open_ended ? std::string() : " of " + number_text(p.scheduled)) + " pulses";
  if (req.live) text += ", " + std::to_string(p.frames) + " live frames";
  // A device that measures: the pad of the highest impedance (open: no current flowed).
  std::size_t worst = p.measured.size();
  for (std::size_t c = 0; c < p.measured.size(); ++c)
    if (p.measured[c].carried &&
        (worst == p.measured.size() || p.measured[c].impedance_ohm > p.measured[worst].impedance_ohm))
      worst = c;
  if (worst < p.measured.size()) {
    const std::uint32_t z = p.measured[worst].impedance_ohm;
    text += ", worst pad " + std::to_string(worst) + ": " +
            (z == device::kOpenOhm ? std::string("open") : number_text(z * 1e-3) + " kOhm");
  }
  return text;
}

std::optional<std::string> preempted_note(const SessionReport& r) {
  if (!r.preempted) return std::nullopt;
  return r.port + " was running another session's output (its host is gone): stopped it first";
}

std::optional<std::string> not_started_note(const SessionReport& r) {
  if (r.started) return std::nullopt;
  return r.port + ": " + r.end + " before the output started; nothing delivered";
}

namespace {
// --contact-loss suspend: the pulses that went out at the probe, not as asked.
std::string suspended_text(const SessionReport& r) {
  if (r.suspended_pulses == 0) return "";
  return ", " + std::to_string(r.suspended_pulses) +
         " of them at the probe while a pad had no contact (--contact-loss suspend)";
}
}  // namespace

std::string session_summary(const SessionReport& r, const Mix& mix, const DeliveryRequest& req) {
  const bool live = req.live;
  const Stimulus& s = mix.patterns[0];
  // What the device's receiver has lost since it started, when it lost anything
  // (docs/protocol.md, status).
  std::string lost;
  if (r.rx_errors || r.line_errors || r.overruns)
    lost = " (the device's receiver so far: " + std::to_string(r.rx_errors) +
           " damaged frames, " + std::to_string(r.line_errors) + " bytes with line errors, " +
           std::to_string(r.overruns) + " overruns)";
  const std::string rate = mix.single() ? "at " + number_text(s.shape.frequency_hz) + " Hz"
                                        : "of " + std::to_string(mix.patterns.size()) + " patterns";
  const std::string of =
      live && !req.duration_s ? std::string() : " of " + number_text(r.scheduled);
  return r.port + ": " + std::to_string(r.pulses) + of + " pulses on " + std::to_string(s.currents_mA.size()) + " channels " + rate + ", peak " +
         number_text(r.peak_mA) + " mA, " + number_text(std::round(r.seconds * 100) / 100) +
         " s" + (live ? ", " + std::to_string(r.weight_frames) + " live frames" : "") + ", " +
         std::to_string(r.retransmissions) + " retransmissions" + lost + suspended_text(r) +
         (r.hold_headroom > 0 ? ", sensation held (up to " + number_text(std::round(r.hold_headroom * 1000) / 1000) +
                                    " x each amplitude)"
                              : std::string()) +
         "; " + r.end + "; output stopped";
}

}  // namespace tp::host
