#include "device/config_block.hpp"

#include "device/frame.hpp"
#include "device/protocol.hpp"

namespace tp::device {

DeviceConfig parse_config_block(const std::uint8_t* b, std::uint8_t max_channels,
                                std::uint32_t allowed_bits) {
  DeviceConfig defaults;
  defaults.channels = max_channels < defaults.channels ? max_channels : defaults.channels;
  bool erased = true;
  for (std::size_t i = 0; i < kConfigBlockSize; ++i) erased = erased && b[i] == 0xFF;
  if (erased) return defaults;
  DeviceConfig invalid = defaults;
  invalid.source = DeviceConfig::Source::invalid;
  invalid.max_current_uA = 0;
  if (get_u32(b) != kConfigMagic || get_u16(b + 4) != 1 || get_u16(b + 6) != kConfigBlockSize ||
      crc16(b, 14) != get_u16(b + 14))
    return invalid;
  DeviceConfig c;
  c.source = DeviceConfig::Source::block;
  c.channels = b[8];
  c.dac_bits = b[9];
  c.max_current_uA = get_u16(b + 10);
  c.watchdog_ms = get_u16(b + 12);
  const bool ok =
      c.channels >= 1 && c.channels <= max_channels && c.dac_bits < 32 &&
      (allowed_bits >> c.dac_bits & 1u) && c.max_current_uA >= 1 &&
      c.max_current_uA <= hard::max_current_uA && c.watchdog_ms >= hard::min_watchdog_ms &&
      c.watchdog_ms <= hard::max_watchdog_ms && dac_step_nA(c.max_current_uA, c.dac_bits) != 0;
  return ok ? c : invalid;
}

}  // namespace tp::device
