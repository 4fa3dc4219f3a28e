#pragma once
// A board: its pins and clocks.  Another STM32F405/407 board is a new file in boards/
// (chosen with -DTP_BOARD=name), not a change to the firmware.

#include <cstdint>

namespace tp::fw {

struct Pin {
  std::uint8_t port;  // 0 = GPIOA, 1 = GPIOB, ...
  std::uint8_t pin;   // 0 to 15
};

struct Board {
  const char* name;
  // Clocks (RM0090 7.3.2): SYSCLK = HSE / pll_m * pll_n / pll_p = 168 MHz; USB/SDIO
  // 48 MHz = HSE / pll_m * pll_n / pll_q.  APB1 = SYSCLK / 4, APB2 = SYSCLK / 2.
  std::uint32_t hse_hz;
  std::uint32_t pll_m, pll_n, pll_p, pll_q;
  // Host link (USART1), monitor (USART2): pins and their alternate function (AF7).
  Pin host_tx, host_rx;
  Pin monitor_tx, monitor_rx;
  std::uint32_t host_baud, monitor_baud;
  // The DAC on SPI2 (AF5): clock, data out, data in (unused by the AD56x8), chip select
  // (SYNC, a GPIO), and LDAC, which updates every channel at once.
  Pin spi_sck, spi_mosi, spi_miso, dac_sync, dac_ldac;
  // Output enable: the electrode switches; high only while output runs.  The board must
  // pull it down, so that it is low in reset too.
  Pin output_enable;
  // Pins driven low at start-up to keep other parts of the board quiet (0xFF: none), such
  // as the STM32F4-Discovery's audio codec, whose I2C clock shares PB6.
  Pin hold_low;
  // The electrodes' voltage sense (issue 41; docs/skin.md): channel c's electrode, through
  // the board's divider and level shift, on ADC1 channel sense_adc[c] (0xFF: the board
  // does not measure; its capabilities then say so).  A code reads
  // (code - sense_zero_code) x sense_uV_per_code at the electrode, + = cathodic.  The output
  // stage's compliance, V: a reading within 2 % of it is at the rail.
  std::uint8_t sense_adc[8];
  std::uint16_t sense_zero_code;
  std::int32_t sense_uV_per_code;
  std::uint16_t compliance_V;
  // The stop input: a GPIO whose edge to its active level latches the output off
  // (EXTI interrupt, above every other); port 0xFF: none.
  Pin stop_input;
  bool stop_active_high;
  // The shortest phase the DAC can follow: 8 channels of 32-bit words at the SPI clock,
  // with chip-select gaps (AD5628 timing, t4 + t8).
  std::uint16_t min_phase_us;
};

extern const Board kBoard;

}  // namespace tp::fw
