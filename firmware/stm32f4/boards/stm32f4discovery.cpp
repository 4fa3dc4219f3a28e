// STM32F4-Discovery (STM32F407VGT6; 8 MHz HSE: a crystal, or on some revisions the
// ST-LINK's clock output, which needs HSE bypass: clock_init tries both).  Pins are MCU pins;
// firmware/README.md has the wiring.
#include "board.hpp"

namespace tp::fw {
namespace {
constexpr Board make() {
  Board b{};
  b.name = "stm32f4discovery";
  b.hse_hz = 8000000;  // 8 MHz / 8 * 336 / 2 = 168 MHz; / 7 = 48 MHz
  b.pll_m = 8;
  b.pll_n = 336;
  b.pll_p = 2;
  b.pll_q = 7;
  b.host_tx = {1, 6};  // USART1: PB6, PB7 (PB6 is also the audio codec's I2C clock)
  b.host_rx = {1, 7};
  b.monitor_tx = {0, 2};  // USART2: PA2, PA3
  b.monitor_rx = {0, 3};
  b.host_baud = 115200;
  b.monitor_baud = 921600;
  b.spi_sck = {1, 13};  // SPI2: PB13, PB15, PB14
  b.spi_mosi = {1, 15};
  b.spi_miso = {1, 14};
  b.dac_sync = {1, 12};      // PB12
  b.dac_ldac = {3, 0};       // PD0
  b.output_enable = {3, 1};  // PD1
  b.hold_low = {3, 4};       // PD4: the CS43L22 codec's reset, so that it leaves PB6 alone
  const std::uint8_t sense[8] = {1, 8, 9, 11, 12, 14, 15, 4};  // PA1, PB0-1, PC1-2, PC4-5, PA4
  for (int c = 0; c < 8; ++c) b.sense_adc[c] = sense[c];
  b.sense_zero_code = 2048;  // +-60 V -> 0-3.3 V (firmware/README.md)
  b.sense_uV_per_code = 29297;
  b.compliance_V = 60;
  b.stop_input = {0, 0};  // PA0: the B1 button (pressed: high; the board's pull-down)
  b.stop_active_high = true;
  b.min_phase_us = 20;
  return b;
}
}  // namespace

const Board kBoard = make();

}  // namespace tp::fw
