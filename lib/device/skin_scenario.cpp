// A skin scenario's interfaces over time (skin_scenario.hpp).

#include "device/skin_scenario.hpp"

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

SkinScenario::SkinScenario(const SkinInterface& base) : area_mm2_(base.area_mm2) {
  for (auto& channel : start_)
    for (std::size_t f = 0; f < kSkinFields; ++f)
      channel[f] = skin_field(base, static_cast<SkinField>(f));
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

}  // namespace tp::device
