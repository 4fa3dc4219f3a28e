#include "dac_ad56x8.hpp"

#include "hw.hpp"

namespace tp::fw {
namespace {

using reg::at;
// Commands (data sheet table 8).
constexpr std::uint32_t kWriteInput = 0x0, kWriteUpdate = 0x3, kClearCode = 0x5, kLdacReg = 0x6,
                        kReset = 0x7, kReference = 0x8;
constexpr std::uint32_t kAllChannels = 0xF;

std::uint32_t word(std::uint32_t command, std::uint32_t address, std::uint32_t data20) {
  return (command << 24) | (address << 20) | (data20 & 0xFFFFFu);
}

bool wait_spi(std::uint32_t mask, std::uint32_t value) {
  for (int i = 0; i < 10000; ++i)
    if ((at(reg::SPI2 + reg::spi::SR) & mask) == value) return true;
  return false;
}

}  // namespace

void DacAd56x8::init(const Board& board, int bits) {
  board_ = &board;
  bits_ = bits;
  gpio_output(board.output_enable, false);
  gpio_output(board.dac_sync, true);
  gpio_output(board.dac_ldac, true);
  gpio_alternate(board.spi_sck, 5);
  gpio_alternate(board.spi_mosi, 5);
  gpio_alternate(board.spi_miso, 5);
  namespace s = reg::spi;
  // Master, f_PCLK1 / 2 (21 MHz of the AD5628's 50 MHz), CPOL = 1, CPHA = 0, 16-bit,
  // software chip select (SYNC is a GPIO).
  at(reg::SPI2 + s::CR1) = s::CR1_MSTR | (1u << 1) | s::CR1_SSM | s::CR1_SSI | s::CR1_DFF16;
  at(reg::SPI2 + s::CR1) |= s::CR1_SPE;
  write_word(word(kReset, 0, 0));
  write_word(word(kReference, 0, 1));  // internal reference on
  write_word(word(kClearCode, 0, 1));  // CLR goes to mid-scale: 0 mA
  write_word(word(kLdacReg, 0, 0));    // every channel follows the LDAC pin
  const std::uint32_t mid = value_of(0);
  const bool ok = write_word(word(kWriteUpdate, kAllChannels, mid << (20 - bits_)));
  for (std::size_t i = 0; i < kChannels; ++i) input_[i] = dac_[i] = ok ? mid : kUnknown;
}

std::uint32_t DacAd56x8::value_of(std::int16_t code) const {
  return static_cast<std::uint32_t>((1 << (bits_ - 1)) + code);
}

bool DacAd56x8::write_word(std::uint32_t w) {
  namespace s = reg::spi;
  gpio_set(board_->dac_sync, false);
  bool ok = wait_spi(s::SR_TXE, s::SR_TXE);
  at(reg::SPI2 + s::DR) = w >> 16;
  ok = ok && wait_spi(s::SR_TXE, s::SR_TXE);
  at(reg::SPI2 + s::DR) = w & 0xFFFFu;
  ok = ok && wait_spi(s::SR_TXE, s::SR_TXE) && wait_spi(s::SR_BSY, 0);
  // Reading DR then SR clears RXNE and a possible overrun (RM0090 28.3, error flags).
  const std::uint32_t dr = at(reg::SPI2 + s::DR);
  const std::uint32_t sr = at(reg::SPI2 + s::SR);
  static_cast<void>(dr + sr);
  gpio_set(board_->dac_sync, true);
  if (!ok) ++faults_;
  return ok;
}

void DacAd56x8::load(const std::int16_t* codes, std::size_t n) {
  for (std::size_t i = 0; i < kChannels; ++i) {
    const std::uint32_t v = value_of(i < n ? codes[i] : 0);
    if (v == input_[i]) continue;  // only what changes: the SPI time bounds the phase
    // The register is known to hold v only once the word went out; after a fault it is
    // unknown, and the next load writes it again (the firmware stops on any fault).
    if (write_word(word(kWriteInput, static_cast<std::uint32_t>(i), v << (20 - bits_))))
      input_[i] = v;
    else
      input_[i] = kUnknown;
  }
}

void DacAd56x8::latch() {
  for (std::size_t i = 0; i < kChannels; ++i) dac_[i] = input_[i];
  // LDAC low for at least 20 ns, then high: every channel updates together, on the falling
  // edge (the caller reads the clock right after this).
  gpio_set(board_->dac_ldac, false);
  __asm volatile("nop\n nop\n nop\n nop\n nop\n nop" ::: "memory");
  gpio_set(board_->dac_ldac, true);
}

void DacAd56x8::output(std::int16_t* codes, std::size_t n) const {
  const auto mid = static_cast<std::int32_t>(1u << (bits_ - 1));
  for (std::size_t i = 0; i < n && i < kChannels; ++i)
    codes[i] = static_cast<std::int16_t>(static_cast<std::int32_t>(dac_[i]) - mid);
}

void DacAd56x8::enable(bool on) {
  gpio_set(board_->output_enable, on);
  enabled_ = on;
}

}  // namespace tp::fw
