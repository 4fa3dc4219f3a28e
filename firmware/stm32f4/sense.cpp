#include "sense.hpp"

#include "device/skin_block.hpp"
#include "hw.hpp"
#include "regs.hpp"

namespace tp::fw {
namespace {

using reg::at;

// ADC1 (RM0090 13.13): its registers, and the common control register's prescaler.
constexpr std::uint32_t ADC1 = 0x40012000, ADC_CCR = 0x40012304;
constexpr std::uint32_t SR = 0x00, CR1 = 0x04, CR2 = 0x08, SMPR1 = 0x0C, SMPR2 = 0x10,
                        SQR1 = 0x2C, SQR3 = 0x34, DR = 0x4C;
constexpr std::uint32_t SR_EOC = 1u << 1, CR2_ADON = 1u << 0, CR2_SWSTART = 1u << 30;
constexpr std::uint32_t APB2_ADC1 = 1u << 8;
// A conversion takes 15 ADC clocks (3 of sampling, 12 of conversion) at 21 MHz: 0.7 us.
// The wait for it is bounded well beyond that.
constexpr std::uint32_t kMaxPolls = 400;

// The pin of ADC1's channel ch (RM0090 table 7 via the datasheet's pinout): IN0-7 PA0-7,
// IN8-9 PB0-1, IN10-15 PC0-5.
Pin adc_pin(std::uint8_t ch) {
  if (ch < 8) return Pin{0, ch};
  if (ch < 10) return Pin{1, static_cast<std::uint8_t>(ch - 8)};
  return Pin{2, static_cast<std::uint8_t>(ch - 10)};
}

// The code of a channel's measured phase (the main phase, or a shape's strongest: its base
// code x its units) and that phase's units.
std::int32_t measured_code(const device::PulseRecord& r, std::size_t c) {
  if (r.shape.n == 0) return r.main[c];
  return r.main[c] * r.shape.units[r.shape.strongest()];
}

}  // namespace

bool AdcSense::init(const Board& b) {
  for (std::size_t c = 0; c < kSenseChannels; ++c)
    if (b.sense_adc[c] > 15) return false;
  board_ = &b;
  at(reg::rcc::APB2ENR) |= APB2_ADC1;
  __asm volatile("dsb" ::: "memory");
  at(ADC_CCR) = (at(ADC_CCR) & ~(3u << 16)) | (1u << 16);  // ADCCLK = APB2 / 4: 21 MHz
  at(ADC1 + CR1) = 0;                                       // 12 bits, one channel
  at(ADC1 + SMPR1) = 0;                                     // 3 cycles' sampling
  at(ADC1 + SMPR2) = 0;
  at(ADC1 + SQR1) = 0;  // one conversion a start
  at(ADC1 + CR2) = CR2_ADON;
  for (std::size_t c = 0; c < kSenseChannels; ++c) gpio_analog(adc_pin(b.sense_adc[c]));
  return true;
}

void AdcSense::sample(std::uint16_t* raw, std::size_t n) {
  for (std::size_t c = 0; c < n && c < kSenseChannels; ++c) {
    at(ADC1 + SQR3) = board_->sense_adc[c];
    at(ADC1 + CR2) = CR2_ADON | CR2_SWSTART;
    std::uint32_t i = 0;
    while (!(at(ADC1 + SR) & SR_EOC) && i < kMaxPolls) ++i;
    if (i == kMaxPolls) timeouts_ = timeouts_ + 1;
    raw[c] = static_cast<std::uint16_t>(at(ADC1 + DR) & 0xFFFu);  // clears EOC
  }
}

void AdcSense::reading(const device::PulseRecord& r, std::uint64_t, const std::uint16_t* raw,
                       device::ElectricalRecord& m) {
  m = device::ElectricalRecord{};
  const std::int64_t rail_mV = std::int64_t{board_->compliance_V} * 980;  // 98 %
  for (std::size_t c = 0; c < r.channels && c < kSenseChannels; ++c) {
    const std::int32_t code = measured_code(r, c);
    if (code == 0) continue;
    m.carried[c] = true;
    const std::int64_t mV =
        (std::int64_t{raw[c]} - board_->sense_zero_code) * board_->sense_uV_per_code / 1000;
    m.voltage_mV[c] = static_cast<std::int32_t>(mV);
    m.at_rail[c] = (mV < 0 ? -mV : mV) >= rail_mV;
    // No current sense: the current is the one asked (at the rail the guard names the
    // compliance, docs/skin.md).
    m.current_nA[c] = static_cast<std::int32_t>(std::int64_t{code} * r.step_nA);
  }
}

bool SkinSense::init(const std::uint8_t* block, std::size_t max_size) {
  double compliance = 0;
  if (!device::decode_skin_block(block, max_size, scenario_, compliance)) return false;
  compliance_V_ = static_cast<std::uint16_t>(compliance + 0.5);
  skin_.set_compliance_V(compliance);
  return true;
}

void SkinSense::reading(const device::PulseRecord& r, std::uint64_t start_us,
                        const std::uint16_t*, device::ElectricalRecord& m) {
  skin_.measure(r, start_us, m);
}

}  // namespace tp::fw
