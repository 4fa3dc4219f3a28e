#include "host/impedance_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/number.hpp"
#include "core/ranges.hpp"
#include "device/protocol.hpp"
#include "host/stimulator.hpp"

namespace tp::host {
namespace {

// The channels a mix drives (a current in any pattern), and each one's largest |current|
// in any phase (a shaped pulse's levels scale it).
std::vector<double> peak_currents_mA(const Mix& m) {
  std::vector<double> peak(m.patterns[0].currents_mA.size(), 0.0);
  for (const Stimulus& s : m.patterns) {
    double level = 1.0;
    for (const Phase& p : s.shape.delivered()) level = std::max(level, std::fabs(p.level));
    for (std::size_t c = 0; c < peak.size() && c < s.currents_mA.size(); ++c)
      peak[c] = std::max(peak[c], std::fabs(s.currents_mA[c]) * level);
  }
  return peak;
}

// The longest main phase of any pattern: a shaped pulse's longest run of one sign (at most
// the protocol's widest phase), so that the probe's voltage is not below any phase's.
double longest_phase_us(const Mix& m) {
  double longest = 0;
  for (const Stimulus& s : m.patterns) {
    if (!s.shape.shaped()) {
      longest = std::max(longest, s.shape.width_us);
      continue;
    }
    double run = 0;
    int sign = 0;
    for (const Phase& p : s.shape.phases) {
      if (p.level == 0) continue;
      const int sg = p.level > 0 ? 1 : -1;
      run = sg == sign ? run + p.duration_us : p.duration_us;
      sign = sg;
      longest = std::max(longest, run);
    }
  }
  return std::min(longest, double{device::hard::max_width_us});
}

double smallest_area_mm2(const Mix& m) {
  double a = m.patterns[0].electrode_area_mm2;
  for (const Stimulus& s : m.patterns) a = std::min(a, s.electrode_area_mm2);
  return a;
}

}  // namespace

Stimulus probe_stimulus(const Mix& m, double probe_mA) {
  ranges::check(probe_mA, ranges::probe_mA, "--probe-current");
  const std::vector<double> peak = peak_currents_mA(m);
  std::vector<std::size_t> used;
  for (std::size_t c = 0; c < peak.size(); ++c)
    if (peak[c] > 0) used.push_back(c);
  if (used.size() < 2)
    bad_input("--check-impedance: the stimulus drives " + std::to_string(used.size()) +
              " electrode(s); a probe needs two");
  Stimulus s;
  s.currents_mA.assign(peak.size(), 0.0);
  // Alternately cathodic and anodic; the cathodes (one more when the count is odd) share
  // the anodes' current, so that no pad carries more than the probe's.
  const auto cathodes = static_cast<double>((used.size() + 1) / 2);
  const auto anodes = static_cast<double>(used.size() / 2);
  for (std::size_t k = 0; k < used.size(); ++k)
    s.currents_mA[used[k]] = k % 2 == 0 ? probe_mA * anodes / cathodes : -probe_mA;
  const Stimulus& first = m.patterns[0];
  s.shape.width_us = s.shape.balance_width_us = std::round(longest_phase_us(m));
  s.shape.frequency_hz = 50.0;
  s.count = 5;
  s.electrode_area_mm2 = smallest_area_mm2(m);
  s.max_current_mA = first.max_current_mA;
  return s;
}

ImpedanceCheck check_impedance(Transport& transport, const Mix& m, const SessionOptions& opt,
                               double probe_mA) {
  Mix probe;
  probe.patterns.push_back(probe_stimulus(m, probe_mA));
  // Nothing is sent to a device that cannot measure: its capabilities first.
  const device::Capabilities caps = StimulatorClient(transport).identify();
  if (!caps.measures())
    bad_input("--check-impedance: " + transport.name() +
              " does not measure its pulses (protocol 7's measurements: a device with a skin, "
              "stim-emu --skin or --emu-skin)");
  SessionOptions po;
  po.limits = opt.limits;
  po.stop = opt.stop;
  po.probe = true;
  const SessionReport r = run_session(transport, probe, po);
  ImpedanceCheck out;
  out.port = r.port;
  out.compliance_V = r.caps.compliance_V;
  out.probe_mA = probe_mA;
  if (r.exit_code != 0 || !r.started) {
    out.refusal = "--check-impedance: the probe was stopped (" + r.end + ")";
    return out;
  }
  const std::vector<double> peak = peak_currents_mA(m);
  const std::vector<double>& probe_I = probe.patterns[0].currents_mA;
  for (std::size_t c = 0; c < probe_I.size() && c < r.measured.size(); ++c) {
    if (probe_I[c] == 0) continue;
    const device::ChannelMeasurement& x = r.measured[c];
    ImpedanceRow row;
    row.channel = c;
    row.probe_mA = probe_I[c];
    row.voltage_V = x.voltage_mV * 1e-3;
    row.contact = x.carried && x.impedance_ohm != device::kOpenOhm;
    row.impedance_kohm = x.impedance_ohm == device::kOpenOhm
                             ? std::numeric_limits<double>::infinity()
                             : x.impedance_ohm * 1e-3;
    row.peak_mA = peak[c];
    row.needed_V = std::fabs(row.voltage_V) * peak[c] / std::fabs(probe_I[c]);
    out.rows.push_back(row);
    if (out.refusal.empty() && !row.contact)
      out.refusal = "--check-impedance: channel " + std::to_string(c) +
                    " has no contact (no current flowed at the probe): the stimulus was not "
                    "started";
    else if (out.refusal.empty() && x.at_rail)
      out.refusal = "--check-impedance: channel " + std::to_string(c) +
                    " needs more than the device's " + number_text(out.compliance_V) +
                    " V compliance already at the probe: the stimulus was not started";
  }
  if (!out.refusal.empty()) return out;
  if (out.compliance_V <= 0) return out;  // not known: no verdict (the table says so)
  for (const ImpedanceRow& row : out.rows)
    if (row.needed_V > out.compliance_V) {
      out.refusal = "--check-impedance: channel " + std::to_string(row.channel) +
                    " would need " + number_text(std::round(row.needed_V * 10) / 10) +
                    " V at the stimulus's " + number_text(row.peak_mA) + " mA (" +
                    number_text(row.impedance_kohm) + " kOhm at the probe), above the device's " +
                    number_text(out.compliance_V) + " V compliance: the stimulus was not started";
      break;
    }
  return out;
}

std::string impedance_table(const ImpedanceCheck& c) {
  std::string t = "impedance check on " + c.port + " (probe " + number_text(c.probe_mA) +
                  " mA; compliance " +
                  (c.compliance_V > 0 ? number_text(c.compliance_V) + " V"
                                      : std::string("not known: the voltages needed are not judged")) +
                  "):\n" +
                  "  channel  impedance_kohm  voltage_V  contact  peak_mA  needed_V\n";
  char line[160];
  for (const ImpedanceRow& r : c.rows) {
    char needed[32] = "-";
    if (r.contact) std::snprintf(needed, sizeof needed, "%.1f", r.needed_V);
    std::snprintf(line, sizeof line, "  %7zu  %14s  %9.3f  %7s  %7.3f  %8s\n", r.channel,
                  std::isinf(r.impedance_kohm) ? "open" : number_text(r.impedance_kohm).c_str(),
                  r.voltage_V, r.contact ? "yes" : "no", r.peak_mA, needed);
    t += line;
  }
  return t;
}

}  // namespace tp::host
