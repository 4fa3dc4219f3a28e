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

// Channel c's charge per phase, pC (nA x us / 1000), in single precision: the MCU's FPU
// multiplies floats in hardware, doubles in a library (issue 41's budget of 500
// instructions a pulse for the measurement and the guards).  A biphasic pulse's charge is
// exact in integers first (|code| x width x step < 2^47).
float phase_charge_pC(const PulseRecord& r, std::size_t c) {
  if (r.shape.n != 0)
    return static_cast<float>(magnitude(r.main[c])) * static_cast<float>(r.step_nA) *
           static_cast<float>(largest_run_unit_us(r.shape)) * 1e-3f;
  const std::uint32_t main = magnitude(r.main[c]) * std::uint32_t{r.width_us};  // < 2^31
  const std::uint32_t balance = magnitude(r.balance[c]) * std::uint32_t{r.balance_width_us};
  return static_cast<float>(main > balance ? main : balance) * static_cast<float>(r.step_nA) *
         1e-3f;
}

// The measured phase's units (a shaped pulse's strongest; 1 for a biphasic pulse).
std::uint32_t measured_units(const PulseRecord& r) {
  return r.shape.n == 0 ? 1u : magnitude(r.shape.units[r.shape.strongest()]);
}

// |V / I|, ohm: mV / nA = 10^6 ohm; kOpenOhm when no current flowed (below 1 nA).
// The quotient floor(|mV| x 10^6 / i), exact: estimated in single precision (a hardware
// division on the MCU; the 64-bit integer one is a library call of ~100 instructions),
// then corrected by the remainder, whose division fits 32 bits (the estimate is within a
// few parts in 10^7, so the remainder is within ~400 x i < 2^31 for i <= 2 mA); a
// remainder that does not fit takes the 64-bit division.
std::uint64_t ohm_quotient(std::uint32_t mV, std::uint32_t i) {
  const std::uint64_t num = std::uint64_t{mV} * 1000000u;
  const float est = static_cast<float>(mV) * 1e6f / static_cast<float>(i);
  if (!(est < 4.0e9f)) return num / i;
  std::uint64_t q = static_cast<std::uint32_t>(est);
  const std::uint64_t qi = q * i;
  constexpr std::uint64_t kFits = 0x7FFFFFFFu;
  if (qi <= num) {
    const std::uint64_t rem = num - qi;
    return rem <= kFits ? q + static_cast<std::uint32_t>(rem) / i : num / i;
  }
  const std::uint64_t over = qi - num;
  return over <= kFits ? q - (static_cast<std::uint32_t>(over) + i - 1) / i : num / i;
}

std::uint32_t impedance_ohm(std::int32_t voltage_mV, std::int32_t current_nA) {
  const std::uint32_t i = magnitude(current_nA);
  if (i == 0) return kOpenOhm;
  const std::uint64_t ohm = ohm_quotient(magnitude(voltage_mV), i);
  // At least 1 ohm: 0 marks a channel without a baseline (a shorted pad reads 1).
  return ohm >= kOpenOhm ? kOpenOhm - 1 : ohm == 0 ? 1u : static_cast<std::uint32_t>(ohm);
}

}  // namespace

Fault DeviceCore::check_channel(const PulseRecord& r, const PulseTerms& t, ElectricalRecord& m,
                                std::size_t c) {
  ChannelMeasurement& reading = reading_[c];
  reading.carried = true;
  reading.at_rail = m.at_rail[c];
  reading.voltage_mV = m.voltage_mV[c];
  const std::uint32_t z = impedance_ohm(m.voltage_mV[c], m.current_nA[c]);
  reading.impedance_ohm = m.impedance_ohm[c] = z;
  const std::uint64_t lost = guards_.lost_contact_milli;
  // At the rail the source could not push what was asked: through a pad without contact
  // (almost nothing flowed), or through one that needs more than the compliance.
  if (m.at_rail[c]) {
    const std::uint64_t delivered = magnitude(m.current_nA[c]);
    const std::uint64_t asked_nA = std::uint64_t{magnitude(r.main[c])} * r.step_nA * t.units;
    return delivered * 1000u < asked_nA * lost ? Fault::contact : Fault::compliance;
  }
  if (z == kOpenOhm) return Fault::contact;  // no current flowed, whatever the rail said
  if (reading.baseline_ohm == 0 || z < reading.baseline_ohm) reading.baseline_ohm = z;
  const std::uint32_t base = reading.baseline_ohm;
  // The contact estimated from the impedance against the baseline (the interface's
  // resistance scales as 1 / contact): base / z.
  if (std::uint64_t{z} * lost > std::uint64_t{base} * 1000u) return Fault::contact;
  if (density_limit_uC2_ <= 0) return Fault::none;
  // The charge per phase (phase_charge_pC's, from the pulse's terms), then Shannon's k on
  // the estimated contact area (density_fault).
  float q_uC;
  if (r.shape.n != 0) {
    q_uC = static_cast<float>(magnitude(r.main[c])) * t.shaped_uC_per_code;
  } else {
    const std::uint32_t main = magnitude(r.main[c]) * std::uint32_t{r.width_us};  // < 2^31
    const std::uint32_t balance = magnitude(r.balance[c]) * std::uint32_t{r.balance_width_us};
    q_uC = static_cast<float>(main > balance ? main : balance) * t.uC_per_code_us;
  }
  return q_uC * q_uC * static_cast<float>(z) > density_limit_uC2_ * static_cast<float>(base)
             ? Fault::density
             : Fault::none;
}

Fault DeviceCore::density_fault(float charge_pC, std::uint32_t z, std::uint32_t base) const {
  // The contact estimated from the impedance against the baseline (the interface's
  // resistance scales as 1 / contact): base / z.
  if (std::uint64_t{z} * guards_.lost_contact_milli > std::uint64_t{base} * 1000u)
    return Fault::contact;
  if (density_limit_uC2_ <= 0) return Fault::none;
  // Shannon's k on the estimated contact area A c: log10(Q / (A c)) + log10(Q) <= k, Q in
  // uC and A in cm^2, that is Q^2 <= 10^k A c.  With c = base / z: Q^2 z <= 10^k A base.
  const float q_uC = charge_pC * 1e-6f;
  return q_uC * q_uC * static_cast<float>(z) > density_limit_uC2_ * static_cast<float>(base)
             ? Fault::density
             : Fault::none;
}

float DeviceCore::full_charge_pC(std::size_t c) const {
  // The largest charge per phase any pattern of the table puts on channel c at its own
  // amplitude (not its probe): what a resumed pad is about to carry.
  float most = 0;
  for (std::uint16_t i = 0; i < patterns_; ++i) {
    const Pattern& p = pattern_[i];
    for (std::size_t k = 0; k < p.count; ++k) {
      if (pool_channel_[p.first + k] != c) continue;
      PulseRecord one;
      one.channels = 1;
      one.main[0] = pool_code_[p.first + k];
      one.balance[0] = static_cast<std::int16_t>(-one.main[0]);
      one.step_nA = caps_.dac_step_nA;
      one.width_us = timing_[i].width_us;
      one.balance_width_us = timing_[i].width_us;
      one.shape = timing_[i].shape;
      const float q = phase_charge_pC(one, 0) * static_cast<float>(p.scale) / kFullScale;
      if (q > most) most = q;
    }
  }
  return most;
}

void DeviceCore::measured(std::uint64_t start_us, const PulseRecord& r, ElectricalRecord& m) {
  if (start_us != start_us_) return;  // an earlier output's
  ++readings_.measured;
  const bool suspend = (guards_.flags & kGuardSuspend) != 0;
  PulseTerms t;
  t.uC_per_code_us = static_cast<float>(r.step_nA) * 1e-9f;
  if (r.shape.n != 0)
    t.shaped_uC_per_code =
        static_cast<float>(r.step_nA) * static_cast<float>(largest_run_unit_us(r.shape)) * 1e-9f;
  t.units = measured_units(r);
  for (std::size_t c = 0; c < r.channels && c < kMaxChannels; ++c) {
    if (!m.carried[c]) {  // its last reading stands (another pattern's pulse, say)
      m.impedance_ohm[c] = 0;
      continue;
    }
    const Fault f = check_channel(r, t, m, c);
    const std::uint64_t bit = std::uint64_t{1} << c;
    // Suspending: a pad without contact pauses the patterns that drive it (pulse_codes
    // delivers only their probe); a probe that finds it again resumes them.
    if (suspend && f == Fault::contact) {
      suspended_ |= bit;
    } else if (f != Fault::none) {
      if (readings_.trip == Fault::none) trip(f, c, r.t_us);
    } else if (m.carried[c] && (suspended_ & bit) != 0) {
      // A probe found contact: resumed only if the pad's full charge fits the contact seen
      // (else it stays suspended: its next full pulse would break the density limit).
      const ChannelMeasurement& x = reading_[c];
      if (density_fault(full_charge_pC(c), x.impedance_ohm, x.baseline_ohm) == Fault::none)
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
    // Its last pulses were not delivered as asked.  A firmware's engine may still hold some
    // of them (the core completes when it hands over the last): a new end, which the
    // firmware follows by dropping them.
    status_.fault = cause;
    ++output_ends_;
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
  density_limit_uC2_ = static_cast<float>(g.area_um2 * 1e-8 * ten_k);
  return Result::ok;
}

Result DeviceCore::set_hold(const FixedBytes<kMaxPayload>& payload) {
  if (!configured_) return Result::not_configured;
  if (!caps_.measures()) return Result::not_supported;
  if (payload.size() != 4 + kHoldSize) return Result::bad_length;
  if (status_.state == State::running) return Result::bad_state;
  const std::uint16_t i = get_u16(payload.data() + 4);
  if (i >= patterns_) return Result::no_pattern;
  if (!pattern_[i].codes_set) return Result::not_configured;
  const std::uint64_t e =
      std::uint64_t{get_u32(payload.data() + 6)} | (std::uint64_t{get_u32(payload.data() + 10)} << 32);
  hold_ref_[i] = e;
  return Result::ok;
}

namespace {
// sqrt(x) for x >= 0 by Newton's iteration from above (no libm on the firmware): to a
// relative 1e-12 within 8 steps from a start within a factor 2^32 either way.
double root(double x) {
  if (!(x > 0)) return 0;
  double r = x > 1 ? x : 1;
  for (int k = 0; k < 64; ++k) {
    const double next = 0.5 * (r + x / r);
    if (!(next < r)) break;
    r = next;
  }
  return r;
}
}  // namespace

std::uint16_t DeviceCore::hold_scale(std::uint16_t i) const {
  const Pattern& p = pattern_[i];
  std::uint64_t now = 0;
  for (std::size_t k = 0; k < p.count; ++k) {
    const std::uint32_t z = reading_[pool_channel_[p.first + k]].impedance_ohm;
    if (z == 0 || z == kOpenOhm) return p.scale;  // no reading yet, or open: as asked
    const std::uint64_t code = magnitude(pool_code_[p.first + k]);
    now += std::uint64_t{(z < kHoldMaxOhm ? z : kHoldMaxOhm) / kHoldOhmUnit} * code * code;
  }
  if (now == 0) return p.scale;
  const double s = p.scale * root(static_cast<double>(hold_ref_[i]) / static_cast<double>(now));
  return s >= kFullScale ? kFullScale : static_cast<std::uint16_t>(s);
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
