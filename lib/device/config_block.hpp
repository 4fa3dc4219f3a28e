#pragma once
// The device configuration block: what a stimulator's firmware reads at start-up from its
// own flash (the STM32F4 firmware: sector 11, 0x080E0000), 16 bytes, little-endian:
//
//   magic u32 "TPCF" | version u16 (1) | size u16 (16) | channels u8 | dac_bits u8 |
//   max_current_uA u16 | watchdog_ms u16 | crc16 u16 (CRC-16/CCITT-FALSE of bytes 0-13)
//
// scripts/firmware-config writes one.  Erased flash (all 0xFF) means the board's defaults.
// A block that is neither erased nor valid (a bad CRC, an unknown version, a value out of
// range) leaves the device unable to deliver anything: its current limit becomes 0, so it
// refuses every stimulus with a non-zero code, and identify says so.

#include <cstddef>
#include <cstdint>

namespace tp::device {

inline constexpr std::size_t kConfigBlockSize = 16;
inline constexpr std::uint32_t kConfigMagic = 0x46435054;  // "TPCF"

struct DeviceConfig {
  enum class Source : std::uint8_t { defaults, block, invalid };
  std::uint8_t channels = 8;            // 1 to max_channels
  std::uint8_t dac_bits = 12;           // one of the DAC's resolutions
  std::uint16_t max_current_uA = 2000;  // 1 to 2000
  std::uint16_t watchdog_ms = 300;      // 10 to 1000
  Source source = Source::defaults;
};

// Reads a block; max_channels and the allowed DAC resolutions are the hardware's
// (allowed_bits: bit b set when a b-bit DAC is fitted, e.g. 12, 14 and 16).
DeviceConfig parse_config_block(const std::uint8_t* block, std::uint8_t max_channels,
                                std::uint32_t allowed_bits);

}  // namespace tp::device
