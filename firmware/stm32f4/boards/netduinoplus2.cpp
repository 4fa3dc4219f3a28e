// Netduino Plus 2 (STM32F405RGT6, 25 MHz crystal): the board QEMU's netduinoplus2 machine
// models.  Pins are MCU pins; firmware/README.md has the wiring.
#include "board.hpp"

namespace tp::fw {
namespace {
constexpr Board make() {
  Board b{};
  b.name = "netduinoplus2";
  b.hse_hz = 25000000;  // 25 MHz / 25 * 336 / 2 = 168 MHz; / 7 = 48 MHz
  b.pll_m = 25;
  b.pll_n = 336;
  b.pll_p = 2;
  b.pll_q = 7;
  b.host_tx = {1, 6};  // USART1: PB6, PB7
  b.host_rx = {1, 7};
  b.monitor_tx = {0, 2};  // USART2: PA2, PA3
  b.monitor_rx = {0, 3};
  b.host_baud = 115200;
  b.monitor_baud = 921600;
  b.spi_sck = {1, 13};  // SPI2: PB13, PB15, PB14
  b.spi_mosi = {1, 15};
  b.spi_miso = {1, 14};
  b.dac_sync = {1, 12};      // PB12
  b.dac_ldac = {1, 8};       // PB8
  b.output_enable = {1, 9};  // PB9
  b.hold_low = {0xFF, 0};    // none
  const std::uint8_t sense[8] = {10, 11, 12, 13, 14, 15, 8, 9};  // PC0-PC5 (A0-A5), PB0-1
  for (int c = 0; c < 8; ++c) b.sense_adc[c] = sense[c];
  b.sense_zero_code = 2048;       // +-60 V -> 0-3.3 V (firmware/README.md)
  b.sense_uV_per_code = 29297;
  b.compliance_V = 60;
  b.stop_input = {2, 13};         // PC13, to ground through a normally-open switch (pull-up)
  b.stop_active_high = false;
  b.min_phase_us = 20;
  return b;
}
}  // namespace

const Board kBoard = make();

}  // namespace tp::fw
