#pragma once
// stimctl's request, for the program and the Python module's Stimulator alike
// (docs/programs.md, stimctl): where a stimulus goes (a port or the emulator), how long,
// live or not, and what is logged; the combinations checked with the program's messages;
// the session's options, the transport, and the lines the program says at the end.

#include <memory>
#include <optional>
#include <string>

#include "host/session.hpp"
#include "host/transport.hpp"
#include "pulse/mix.hpp"

namespace tp::host {

struct DeliveryRequest {
  std::string port = "emu";  // a serial port's path, or emu (the in-process emulator)
  int baud = 115200;
  std::string backend = "auto";  // auto, libserialport or posix
  std::string stimulus_path = "-";  // the stimulus document, - for stdin
  bool live = false;                // frames on stdin after starting (needs a stimulus file)
  std::optional<double> duration_s;  // (0, the host's longest]; the text typed in duration_given
  std::string duration_given;       // empty: the number (told apart from the bounds) instead
  std::string record_path;           // emulator only: a JSON line per delivered pulse
  std::optional<int> emu_channels;   // emulator only [8]
  std::string emu_skin_path;         // emulator only: the electrodes' skin (docs/skin.md)
  std::optional<double> emu_compliance_V;  // with emu_skin_path: 1 to 1000 V [100]
  std::string latency_log;           // live only: "n t_ns" per frame sent
  bool check_impedance = false;      // probe every used pad first (host/impedance_check.hpp)
  std::optional<double> probe_mA;    // with check_impedance or suspension: 0.01 to 0.5 mA [0.05]
  std::string contact_loss = "stop";  // stop, or suspend (SessionOptions::suspend_on_contact_loss)
  bool hold_sensation = false;       // SessionOptions::hold_sensation
};

// The options' combinations, before anything is read: bad input naming the flag
// (--live, --record, --emu-channels, --emu-skin, --emu-compliance-v, --latency-log,
// --probe-current), in that order.
void check_delivery(const DeliveryRequest& r);

// The session's options (live, the latency log, the duration checked against the host's
// limits: "--duration: T s outside (0, 3600] s"); no stop, frames or progress yet.
SessionOptions delivery_session(const DeliveryRequest& r);

// The port, or the emulator with its channels [8], record and skin (bad input naming
// --emu-skin for a skin file that does not read).
std::unique_ptr<Transport> open_delivery(const DeliveryRequest& r);

// --list's output: CSV port,description, one row a serial port.
std::string serial_ports_csv();

// The amplitude of each pattern against the thresholds its document carries
// (fiber-threshold's, through make-pulse), said before anything is sent; nothing when no
// pattern carries any ("pattern P: " before each of a mix's).
std::optional<std::string> thresholds_note(const Mix& mix);

// The progress line's text while the output runs: "T of E s, N of M pulses" (live: and
// ", F live frames"); a live session without a duration runs until its input ends, so
// "T s, N pulses, F live frames"; a device that measures adds the pad of the highest
// impedance, ", worst pad C: Z kOhm" (or "open").
std::string progress_text(const SessionProgress& p, const DeliveryRequest& req);

// What a session's end says, after the program's name: the device was running another
// session's output (or nothing), the output never started (or nothing), and the summary
// of a started one (pulses, channels, rate, peak, time, live frames, retransmissions, the
// receiver's losses, why it ended).  A live session without a duration ran until its input
// ended: its count is the pulses delivered alone ("N pulses", not "N of" the budget's).
std::optional<std::string> preempted_note(const SessionReport& r);
std::optional<std::string> not_started_note(const SessionReport& r);
std::string session_summary(const SessionReport& r, const Mix& mix, const DeliveryRequest& req);

}  // namespace tp::host
