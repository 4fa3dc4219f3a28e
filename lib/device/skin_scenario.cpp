// A skin scenario's interfaces over time (skin_scenario.hpp).

#include "device/skin_scenario.hpp"

#include <cmath>

#include "device/pulse_record.hpp"

namespace tp::device {

double skin_field(const SkinInterface& s, SkinField f) {
  switch (f) {
    case SkinField::rs_kohm: return s.rs_kohm;
    case SkinField::rp_kohm: return s.rp_kohm;
    case SkinField::cp_nf: return s.cp_nf;
    case SkinField::j_half_mA_mm2: return s.j_half_mA_mm2;
    case SkinField::contact: return s.contact;
  }
  return 0;
}

void set_skin_field(SkinInterface& s, SkinField f, double value) {
  switch (f) {
    case SkinField::rs_kohm: s.rs_kohm = value; break;
    case SkinField::rp_kohm: s.rp_kohm = value; break;
    case SkinField::cp_nf: s.cp_nf = value; break;
    case SkinField::j_half_mA_mm2: s.j_half_mA_mm2 = value; break;
    case SkinField::contact: s.contact = value; break;
  }
}

void SkinScenario::reset(const SkinInterface& base) {
  area_mm2_ = base.area_mm2;
  for (auto& channel : start_)
    for (std::size_t f = 0; f < kSkinFields; ++f)
      channel[f] = skin_field(base, static_cast<SkinField>(f));
  n_ = 0;
  stops_ = 0;
}

void SkinScenario::set_override(std::size_t channel, SkinField field, double value) {
  if (channel < kMaxChannels) start_[channel][static_cast<std::size_t>(field)] = value;
}

bool SkinScenario::add_event(const SkinEvent& e) {
  if (n_ == kMaxEvents) return false;
  // After every event at or before its time: the order added, at one time.
  std::size_t k = n_;
  while (k > 0 && event_[k - 1].t_us > e.t_us) {
    event_[k] = event_[k - 1];
    --k;
  }
  event_[k] = e;
  ++n_;
  return true;
}

bool SkinScenario::add_stop_input(std::uint64_t t_us) {
  if (stops_ == kMaxStopInputs) return false;
  stop_us_[stops_++] = t_us;
  return true;
}

bool SkinScenario::first_stop_input(std::uint64_t& t_us) const {
  if (stops_ == 0) return false;
  t_us = stop_us_[0];
  for (std::size_t k = 1; k < stops_; ++k)
    if (stop_us_[k] < t_us) t_us = stop_us_[k];
  return true;
}

namespace {
// A field's course from one event on: linear from `from` to `target` over the ramp.
struct Segment {
  std::uint64_t t_us = 0, ramp_us = 0;
  double from = 0, target = 0;
  double at(std::uint64_t t) const {
    if (ramp_us == 0 || t >= t_us + ramp_us) return target;
    if (t <= t_us) return from;
    const double s = static_cast<double>(t - t_us) / static_cast<double>(ramp_us);
    return from + (target - from) * s;
  }
};
}  // namespace

double SkinScenario::field_at(std::size_t channel, SkinField f, std::uint64_t t_us) const {
  const double start = start_[channel][static_cast<std::size_t>(f)];
  Segment now{0, 0, start, start};
  for (std::size_t k = 0; k < n_ && event_[k].t_us <= t_us; ++k) {
    const SkinEvent& e = event_[k];
    if (e.field != f || !(e.channels >> channel & 1u)) continue;
    now = Segment{e.t_us, e.ramp_us, now.at(e.t_us), e.target};
  }
  return now.at(t_us);
}

SkinInterface SkinScenario::at(std::size_t channel, std::uint64_t t_us) const {
  SkinInterface s;
  s.area_mm2 = area_mm2_;
  if (channel >= kMaxChannels) return s;
  for (std::size_t f = 0; f < kSkinFields; ++f)
    set_skin_field(s, static_cast<SkinField>(f), field_at(channel, static_cast<SkinField>(f), t_us));
  return s;
}

namespace {
// A channel's phases of a pulse (mA, us), and which of them is the main phase.
struct Phases {
  double current_mA[kMaxPhases + 2] = {};
  double duration_us[kMaxPhases + 2] = {};
  std::size_t n = 0, main = 0;
};

Phases phases_of(const PulseRecord& r, std::size_t channel) {
  Phases ph;
  const double step_mA = r.step_nA * 1e-6;
  const double code = r.main[channel];
  if (r.shape.n != 0) {
    const Shape& s = r.shape;
    for (std::size_t k = 0; k < s.n && k < kMaxPhases; ++k) {
      ph.current_mA[k] = code * s.units[k] * step_mA;
      ph.duration_us[k] = r.measured ? r.measured_duration_us[k] : s.duration_us[k];
      ph.n = k + 1;
    }
    ph.main = s.strongest();
    return ph;
  }
  ph.current_mA[0] = code * step_mA;
  ph.duration_us[0] = r.measured ? r.measured_width_us : r.width_us;
  ph.current_mA[1] = 0;
  ph.duration_us[1] = r.measured ? r.measured_interphase_us : r.interphase_us;
  ph.current_mA[2] = r.balance[channel] * step_mA;
  ph.duration_us[2] = r.measured ? r.measured_balance_us : r.balance_width_us;
  ph.n = 3;
  return ph;
}
}  // namespace

void SimulatedSkin::measure(const DeliveredPulse& p, ElectricalRecord& m) {
  measure(record_of(p), p.start_us, m);
}

void SimulatedSkin::measure(const PulseRecord& r, std::uint64_t start_us, ElectricalRecord& m) {
  m = ElectricalRecord{};
  if (start_us != output_start_us_) {  // a new output: every channel discharged
    output_start_us_ = start_us;
    for (std::size_t c = 0; c < kMaxChannels; ++c) {
      state_[c] = SkinState{};
      last_us_[c] = start_us;
    }
  }
  const std::uint64_t t_us = r.t_us;  // from the output's start
  const std::uint64_t t_abs = start_us + t_us;
  for (std::size_t c = 0; c < r.channels && c < kMaxChannels; ++c) {
    const SkinInterface s = scenario_.at(c, t_us);
    if (t_abs > last_us_[c])  // discharged since its last pulse
      phase_voltage_V(s, state_[c], 0.0, static_cast<double>(t_abs - last_us_[c]));
    const Phases ph = phases_of(r, c);
    double end_V[kMaxPhases + 2] = {};
    const double peak_V =
        pulse_peak_voltage_V(s, state_[c], ph.current_mA, ph.duration_us, ph.n, end_V);
    double length_us = 0;
    for (std::size_t k = 0; k < ph.n; ++k) length_us += ph.duration_us[k];
    last_us_[c] = t_abs + static_cast<std::uint64_t>(length_us);
    const double i = ph.current_mA[ph.main];
    if (i == 0) continue;
    m.carried[c] = true;
    const double v = rail_voltage_V(end_V[ph.main], i, compliance_V_);
    m.voltage_mV[c] = static_cast<std::int32_t>(std::lround(v * 1000));
    // Past the compliance anywhere in the pulse the source is at its rail: it delivers what
    // the rail pushes through the load, i x compliance / needed (a linear load's; nothing
    // into a lifted pad).
    m.at_rail[c] = !(std::fabs(peak_V) <= compliance_V_);
    const double delivered_mA =
        m.at_rail[c] ? (std::isfinite(peak_V) ? i * compliance_V_ / std::fabs(peak_V) : 0.0) : i;
    m.current_nA[c] = static_cast<std::int32_t>(std::lround(delivered_mA * 1e6));
    const double ohm = measured_impedance_kohm(v, delivered_mA) * 1000;
    m.impedance_ohm[c] = delivered_mA == 0 || !(ohm < 4e9) ? kOpenOhm
                                                           : static_cast<std::uint32_t>(std::lround(ohm));
  }
}

}  // namespace tp::device
