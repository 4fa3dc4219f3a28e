// The firmware's configuration block: defaults, a valid block, refusals
// (lib/device/config_block).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>

#include <nlohmann/json.hpp>
#include "core/error.hpp"
#include "device/config_block.hpp"
#include "device/device_core.hpp"
#include "device/pulse_record.hpp"
#include "device_support.hpp"
#include "host/session.hpp"
#include "host/stimulator.hpp"
#include "pulse/stimulus.hpp"

using namespace tp;
using namespace tp::device;


TEST_CASE("the firmware's configuration block: defaults, a valid block, and refusals",
          "[device][config]") {
  constexpr std::uint32_t bits = (1u << 12) | (1u << 14) | (1u << 16);
  std::uint8_t erased[kConfigBlockSize];
  std::fill(std::begin(erased), std::end(erased), std::uint8_t{0xFF});
  const DeviceConfig d = parse_config_block(erased, 8, bits);
  CHECK(d.source == DeviceConfig::Source::defaults);
  CHECK(d.channels == 8);
  CHECK(d.max_current_uA == 2000);
  // What `scripts/firmware-config --max-current 1` writes (tests/cli: the same bytes).
  std::uint8_t block[kConfigBlockSize] = {0x54, 0x50, 0x43, 0x46, 0x01, 0x00, 0x10, 0x00,
                                          0x08, 0x0c, 0xe8, 0x03, 0x2c, 0x01, 0x56, 0x47};
  const DeviceConfig c = parse_config_block(block, 8, bits);
  CHECK(c.source == DeviceConfig::Source::block);
  CHECK(c.channels == 8);
  CHECK(c.dac_bits == 12);
  CHECK(c.max_current_uA == 1000);
  CHECK(c.watchdog_ms == 300);
  // Every single-bit error is caught, and leaves a device that delivers nothing.
  for (std::size_t byte = 0; byte < kConfigBlockSize; ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::uint8_t bad[kConfigBlockSize];
      std::copy(std::begin(block), std::end(block), bad);
      bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1u << bit));
      const DeviceConfig b = parse_config_block(bad, 8, bits);
      REQUIRE(b.source == DeviceConfig::Source::invalid);
      REQUIRE(b.max_current_uA == 0);
    }
  // A valid CRC over values the hardware cannot honour: refused the same way.
  auto with = [&](std::size_t at, std::uint8_t v) {
    std::uint8_t b[kConfigBlockSize];
    std::copy(std::begin(block), std::end(block), b);
    b[at] = v;
    const std::uint16_t crc = crc16(b, 14);
    b[14] = static_cast<std::uint8_t>(crc & 0xFF);
    b[15] = static_cast<std::uint8_t>(crc >> 8);
    return parse_config_block(b, 8, bits);
  };
  CHECK(with(8, 9).source == DeviceConfig::Source::invalid);   // 9 channels on an 8-channel DAC
  CHECK(with(8, 0).source == DeviceConfig::Source::invalid);   // none
  CHECK(with(9, 13).source == DeviceConfig::Source::invalid);  // a 13-bit DAC is not fitted
  CHECK(with(9, 16).source == DeviceConfig::Source::block);
  CHECK(with(11, 0x08).source == DeviceConfig::Source::invalid);  // 2.28 mA: over the bound
  CHECK(with(13, 0x04).source == DeviceConfig::Source::invalid);  // watchdog 1068 ms
  // A 4-channel board: its defaults have 4 channels.
  CHECK(parse_config_block(erased, 4, bits).channels == 4);
}
