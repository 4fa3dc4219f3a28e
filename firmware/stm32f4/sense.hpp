#pragma once
// What the board measures of each pulse (issue 41; docs/skin.md): each electrode's voltage
// at the end of the pulse's main phase.  The pulse engine samples in its interrupt, just
// before the main phase's last edge (sample()); the main loop turns the samples into the
// core's readings (reading(), then DeviceCore::measured applies the guards).
//
//  - AdcSense: a real board's ADC1, one conversion per channel on the board's sense
//    inputs (board.hpp: sense_adc, the divider's scale and zero, the compliance rail).
//  - SkinSense: the board under QEMU, whose ADC has no analogue inputs: the same skin model
//    the host's emulators run (device/skin_scenario.hpp), from the skin block that
//    scripts/firmware-emu --skin writes beside the configuration block, on the pulse as
//    delivered (the codes latched, the phases as the clock measured them).

#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "device/pulse_record.hpp"
#include "device/skin_scenario.hpp"

namespace tp::fw {

inline constexpr std::size_t kSenseChannels = 8;

class Sense {
 public:
  // In the engine's interrupt, before the main phase's end: raw samples of n channels.
  virtual void sample(std::uint16_t* raw, std::size_t n) = 0;
  // In the main loop: the pulse r of the output started at start_us (device time), sampled
  // as raw, as the core's readings (carried, at_rail, voltage_mV, current_nA).
  virtual void reading(const device::PulseRecord& r, std::uint64_t start_us,
                       const std::uint16_t* raw, device::ElectricalRecord& m) = 0;
  virtual std::uint16_t compliance_V() const = 0;

 protected:
  ~Sense() = default;
};

class AdcSense final : public Sense {
 public:
  // Configures ADC1 and the board's sense pins (analogue); false when the board has none.
  bool init(const Board& b);
  void sample(std::uint16_t* raw, std::size_t n) override;
  void reading(const device::PulseRecord& r, std::uint64_t start_us, const std::uint16_t* raw,
               device::ElectricalRecord& m) override;
  std::uint16_t compliance_V() const override { return board_->compliance_V; }
  // Conversions that never completed (a bounded wait ran out): a reading fault.
  std::uint32_t timeouts() const { return timeouts_; }

 private:
  const Board* board_ = nullptr;
  volatile std::uint32_t timeouts_ = 0;
};

class SkinSense final : public Sense {
 public:
  // Reads the skin block at `block` (max_size bytes); false when there is none or it is not
  // valid (device/skin_block.hpp): the board then does not measure.
  bool init(const std::uint8_t* block, std::size_t max_size);
  void sample(std::uint16_t*, std::size_t) override {}  // the model needs no samples
  void reading(const device::PulseRecord& r, std::uint64_t start_us, const std::uint16_t* raw,
               device::ElectricalRecord& m) override;
  std::uint16_t compliance_V() const override { return compliance_V_; }
  // The skin's first stop input in an output (its stop_input events), from the output's start.
  bool first_stop_input(std::uint64_t& t_us) const { return scenario_.first_stop_input(t_us); }

 private:
  device::SkinScenario scenario_;
  device::SimulatedSkin skin_{scenario_, 100.0};
  std::uint16_t compliance_V_ = 0;
};

}  // namespace tp::fw
