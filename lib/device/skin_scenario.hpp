#pragma once
// A skin scenario (issue 41, item 2; docs/skin.md, "Skin scenarios"): every channel's
// electrode-skin interface (skin_circuit.hpp) at any time of a session, from a base
// interface, per-channel overrides and a script of timed events (a pad lifted, part of a
// pad touching, sweat lowering Rp along a ramp).  What an emulator's skin is made of; the
// host reads it from a skin file (host/skin_file.hpp).  Portable: fixed capacity, no heap.

#include <cstddef>
#include <cstdint>

#include "device/device_core.hpp"
#include "device/protocol.hpp"
#include "device/pulse_record.hpp"
#include "device/skin_circuit.hpp"

namespace tp::device {

// The interface's values an override or an event may set.
enum class SkinField : std::uint8_t { rs_kohm, rp_kohm, cp_nf, j_half_mA_mm2, contact };
inline constexpr std::size_t kSkinFields = 5;

// One event: from t_us on, on its channels, `field` moves linearly from its value at t_us to
// `target` over ramp_us (0: at once).  A later event on the same field and channel starts
// from where the earlier one has brought it, and takes over.
struct SkinEvent {
  std::uint64_t t_us = 0;
  std::uint64_t ramp_us = 0;
  std::uint64_t channels = 0;  // bit c: channel c
  SkinField field = SkinField::contact;
  double target = 0;
};

class SkinScenario {
 public:
  static constexpr std::size_t kMaxEvents = 512;  // field changes, all events together

  // Every channel starts from `base` (its area too).
  explicit SkinScenario(const SkinInterface& base = SkinInterface{}) { reset(base); }
  // As constructed from base: no overrides, events or stop inputs (in place: a firmware
  // has no room for a second scenario on its stack).
  void reset(const SkinInterface& base);

  // Channel c starts with `field` at `value` instead of the base's.
  void set_override(std::size_t channel, SkinField field, double value);
  // Adds an event; false when kMaxEvents are held (nothing is added).  Events may be added
  // in any order: evaluation takes them by time, and in the order added at one time.
  bool add_event(const SkinEvent& e);

  // The board's stop input pressed at t_us from the start of every output (an emulator's
  // equivalent of the firmware's GPIO stop input); false when kMaxStopInputs are held.
  static constexpr std::size_t kMaxStopInputs = 16;
  bool add_stop_input(std::uint64_t t_us);
  // The earliest stop input in an output, into t_us; false when there is none.
  bool first_stop_input(std::uint64_t& t_us) const;

  // Channel c's interface at t_us from the start of the output.
  SkinInterface at(std::size_t channel, std::uint64_t t_us) const;

  // What the scenario holds (skin_block.hpp writes it so): each channel's starting value of
  // each field, the pads' area, the events in time order, the stop inputs.
  double start_value(std::size_t channel, SkinField f) const {
    return start_[channel][static_cast<std::size_t>(f)];
  }
  double area_mm2() const { return area_mm2_; }
  std::size_t events() const { return n_; }
  const SkinEvent& event(std::size_t k) const { return event_[k]; }
  std::size_t stop_inputs() const { return stops_; }
  std::uint64_t stop_input(std::size_t k) const { return stop_us_[k]; }

 private:
  double field_at(std::size_t channel, SkinField f, std::uint64_t t_us) const;

  double start_[kMaxChannels][kSkinFields] = {};
  double area_mm2_ = 1.0;
  SkinEvent event_[kMaxEvents];
  std::size_t n_ = 0;
  std::uint64_t stop_us_[kMaxStopInputs] = {};
  std::size_t stops_ = 0;
};

// What an emulator's (or a simulated board's) electrodes touch: each channel's interface
// from a scenario, its charge carried from pulse to pulse (discharging in between), and the
// output stage's compliance voltage.  It gives what a device measures at the end of a
// pulse's main phase (a shaped pulse's strongest phase, the first of them): each channel's
// voltage, held at the compliance rail where the pulse would need more anywhere (a lifted
// pad always does: at_rail), the current delivered (as asked, or at the rail i x
// compliance / the voltage needed, a linear load's; none into a lifted pad), and the
// impedance |V / I delivered| (kOpenOhm when none flowed).  The interface's charge follows
// the asked current even at the rail (the emulation's simplification: docs/skin.md).
class SimulatedSkin {
 public:
  SimulatedSkin(const SkinScenario& scenario, double compliance_V)
      : scenario_(scenario), compliance_V_(compliance_V) {}

  // The pulse delivered at p.t_us (its output started at p.start_us; the scenario's time is
  // from there, and a new output starts every channel discharged), measured into m.
  void measure(const DeliveredPulse& p, ElectricalRecord& m);
  // The same from a pulse's record (a firmware's simulated board: the codes it latched and,
  // when r.measured, the phases' durations as its clock measured them), of the output whose
  // start command came at start_us.
  void measure(const PulseRecord& r, std::uint64_t start_us, ElectricalRecord& m);

  double compliance_V() const { return compliance_V_; }
  void set_compliance_V(double v) { compliance_V_ = v; }

 private:
  const SkinScenario& scenario_;
  double compliance_V_;
  SkinState state_[kMaxChannels];
  std::uint64_t last_us_[kMaxChannels] = {};  // each channel's state is at this time
  std::uint64_t output_start_us_ = UINT64_MAX;
};

// The value of a field of an interface, and the interface with it set.
double skin_field(const SkinInterface& s, SkinField f);
void set_skin_field(SkinInterface& s, SkinField f, double value);

}  // namespace tp::device
