// The device's measured guards (protocol version 7, issue 41; docs/safety.md, "Measured
// guards"): each pulse's readings, the impedance derived from them, the baselines, and the
// three guards (lost contact, compliance, charge density on the estimated contact area).
// Part of DeviceCore: portable, no allocation.

#include "device/device_core.hpp"
#include "device/pulse_record.hpp"

namespace tp::device {
namespace {

std::uint32_t magnitude(std::int32_t v) {
  return v < 0 ? static_cast<std::uint32_t>(-static_cast<std::int64_t>(v))
               : static_cast<std::uint32_t>(v);
}

// The largest charge of one phase, in units x us per code: a biphasic pulse's main phase or
// its balance (each channel's balance code x balance width is within a code of the main
// phase's charge, so the larger of the two is taken by the caller); a shaped pulse's largest
// run of phases of one sign (a zero-level phase inside a run does not end it), as the host
// counts charge per phase (pulse/stimulus.hpp).
std::uint64_t largest_run_unit_us(const Shape& s) {
  std::uint64_t best = 0, run = 0;
  int sign = 0;
  for (std::size_t k = 0; k < s.n && k < kMaxPhases; ++k) {
    const int u = s.units[k];
    if (u == 0) continue;
    const int sg = u > 0 ? 1 : -1;
    if (sg != sign) run = 0;
    sign = sg;
    run += static_cast<std::uint64_t>(u > 0 ? u : -u) * s.duration_us[k];
    if (run > best) best = run;
  }
  return best;
}

// Channel c's charge per phase, fC (nA x us).
double phase_charge_fC(const PulseRecord& r, std::size_t c) {
  const double step = r.step_nA;
  if (r.shape.n != 0)
    return magnitude(r.main[c]) * step * static_cast<double>(largest_run_unit_us(r.shape));
  const double main = static_cast<double>(magnitude(r.main[c])) * r.width_us;
  const double balance = static_cast<double>(magnitude(r.balance[c])) * r.balance_width_us;
  return (main > balance ? main : balance) * step;
}

// The current asked of channel c in the phase measured (a shaped pulse's strongest), nA.
std::uint64_t asked_nA(const PulseRecord& r, std::size_t c) {
  std::uint32_t units = r.shape.n == 0 ? 1 : 0;
  for (std::size_t k = 0; k < r.shape.n && k < kMaxPhases; ++k) {
    const std::uint32_t u = magnitude(r.shape.units[k]);
    if (u > units) units = u;
  }
  return std::uint64_t{magnitude(r.main[c])} * r.step_nA * units;
}

// |V / I|, ohm: mV / nA = 10^6 ohm; kOpenOhm when no current flowed (below 1 nA).
std::uint32_t impedance_ohm(std::int32_t voltage_mV, std::int32_t current_nA) {
  const std::uint64_t i = magnitude(current_nA);
  if (i == 0) return kOpenOhm;
  const std::uint64_t ohm = std::uint64_t{magnitude(voltage_mV)} * 1000000u / i;
  return ohm >= kOpenOhm ? kOpenOhm - 1 : static_cast<std::uint32_t>(ohm);
}

}  // namespace

Fault DeviceCore::check_channel(const PulseRecord& r, ElectricalRecord& m, std::size_t c) {
  ChannelMeasurement& reading = reading_[c];
  reading.carried = m.carried[c];
  reading.at_rail = m.at_rail[c];
  reading.voltage_mV = m.voltage_mV[c];
  if (!m.carried[c]) {
    reading.impedance_ohm = m.impedance_ohm[c] = 0;
    return Fault::none;
  }
  const std::uint32_t z = impedance_ohm(m.voltage_mV[c], m.current_nA[c]);
  reading.impedance_ohm = m.impedance_ohm[c] = z;
  const std::uint64_t lost = guards_.lost_contact_milli;
  // At the rail the source could not push what was asked: through a pad without contact
  // (almost nothing flowed), or through one that needs more than the compliance.
  if (m.at_rail[c]) {
    const std::uint64_t delivered = magnitude(m.current_nA[c]);
    return delivered * 1000u < asked_nA(r, c) * lost ? Fault::contact : Fault::compliance;
  }
  if (reading.baseline_ohm == 0 || z < reading.baseline_ohm) reading.baseline_ohm = z;
  // The contact estimated from the impedance against the baseline (the interface's
  // resistance scales as 1 / contact): baseline / z.
  const std::uint64_t base = reading.baseline_ohm;
  if (std::uint64_t{z} * lost > base * 1000u) return Fault::contact;
  if (density_limit_uC2_ <= 0) return Fault::none;
  // Shannon's k on the estimated contact area A c: log10(Q / (A c)) + log10(Q) <= k, Q in
  // uC and A in cm^2, that is Q^2 <= 10^k A c.  With c = base / z: Q^2 z <= 10^k A base.
  const double q_uC = phase_charge_fC(r, c) * 1e-9;
  return q_uC * q_uC * z > density_limit_uC2_ * static_cast<double>(base) ? Fault::density
                                                                          : Fault::none;
}

void DeviceCore::measured(std::uint64_t start_us, const PulseRecord& r, ElectricalRecord& m) {
  if (start_us != start_us_) return;  // an earlier output's
  ++readings_.measured;
  const bool suspend = (guards_.flags & kGuardSuspend) != 0;
  for (std::size_t c = 0; c < r.channels && c < kMaxChannels; ++c) {
    const Fault f = check_channel(r, m, c);
    const std::uint64_t bit = std::uint64_t{1} << c;
    // Suspending: a pad without contact pauses the patterns that drive it (pulse_codes
    // delivers only their probe); a probe that finds it again resumes them.
    if (suspend && f == Fault::contact) {
      suspended_ |= bit;
    } else if (f != Fault::none) {
      if (readings_.trip == Fault::none) trip(f, c, r.t_us);
    } else if (m.carried[c]) {
      suspended_ &= ~bit;
    }
    reading_[c].suspended = (suspended_ & bit) != 0;
  }
}

void DeviceCore::trip(Fault cause, std::size_t channel, std::uint64_t t_us) {
  readings_.trip = cause;
  readings_.trip_channel = static_cast<std::uint8_t>(channel);
  readings_.trip_t_us = t_us > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<std::uint32_t>(t_us);
  readings_.trip_ohm = reading_[channel].impedance_ohm;
  pending_trip_ = cause;
  if (!in_advance_) apply_trip();
}

void DeviceCore::apply_trip() {
  if (pending_trip_ == Fault::none) return;
  const Fault cause = pending_trip_;
  pending_trip_ = Fault::none;
  if (status_.state == State::running) {
    end_session();
    status_.fault = cause;
  } else if (status_.fault == Fault::completed) {
    status_.fault = cause;  // its last pulses were not delivered as asked
  }
}

Result DeviceCore::set_guards(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  if (!caps_.measures()) return Result::not_supported;
  if (status_.state == State::running) return Result::bad_state;
  Guards g;
  if (!decode_guards(payload.data() + 4, payload.size() - 4, g)) return Result::bad_length;
  if (!guards_in_range(g)) return Result::out_of_range;
  guards_ = g;
  // 10^k x A (cm^2), k in thousandths: 10^(1/1000) multiplied in k times (no libm on the
  // firmware; at most 2500 products, a relative error below 1e-12).
  double ten_k = 1.0;
  for (std::uint16_t i = 0; i < g.shannon_k_milli; ++i) ten_k *= 1.0023052380778996;
  density_limit_uC2_ = g.area_um2 * 1e-8 * ten_k;
  return Result::ok;
}

Result DeviceCore::measurements(const FixedBytes<kMaxPayload>& payload,
                                FixedBytes<kMaxPayload>& body) const {
  if (payload.size() != 2) return Result::bad_length;
  const std::uint8_t first = payload[0], n = payload[1];
  if (n > kMeasurementsPerReply || std::size_t{first} + n > caps_.channels)
    return Result::out_of_range;
  MeasurementsHead h = readings_;
  h.first = first;
  h.n = n;
  put_measurements_head(body, h);
  for (std::size_t k = 0; k < n; ++k) put_channel_measurement(body, reading_[first + k]);
  return Result::ok;
}

}  // namespace tp::device
