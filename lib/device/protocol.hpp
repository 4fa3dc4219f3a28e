#pragma once
// Messages of the stimulator protocol (docs/protocol.md).  Portable: no OS calls.
// All multi-byte fields are little-endian.  Currents travel as signed DAC codes;
// a positive code is cathodic.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tp::device {

enum class Msg : std::uint8_t {
  identify = 0x01,     // -> ack + Capabilities
  configure = 0x02,    // PulseConfig -> ack
  set_weights = 0x03,  // count u8, count x int16 codes -> ack
  start = 0x04,        // -> ack
  stop = 0x05,         // -> ack (always honoured)
  status = 0x06,       // -> ack + Status
  keepalive = 0x07,    // -> ack
  ack = 0x80,          // device -> host: acked type u8, Result u8, body
};

enum class Result : std::uint8_t {
  ok = 0,
  unknown_type = 1,
  bad_length = 2,
  out_of_range = 3,      // a width, rate or current outside the device's limits
  not_configured = 4,    // set_weights/start before configure, start before set_weights
  sum_not_zero = 5,      // channel codes do not sum to zero
  channel_mismatch = 6,  // more channels than the device has, or not the configured count
  bad_state = 7,         // configure while running
};
const char* to_string(Result r);

enum class State : std::uint8_t { idle = 0, running = 1 };
enum class Fault : std::uint8_t { none = 0, watchdog = 1, link_lost = 2, completed = 3 };
const char* to_string(Fault f);

struct Capabilities {
  std::uint8_t channels = 8;
  std::uint16_t max_current_uA = 2000;  // per channel, either phase
  std::uint16_t dac_step_nA = 977;      // one DAC code (12-bit signed over +-2 mA)
  std::uint16_t min_width_us = 10;
  std::uint16_t max_width_us = 1000;
  std::uint16_t max_balance_width_us = 8000;
  std::uint16_t max_rate_hz = 1000;
  std::uint16_t watchdog_ms = 300;  // output stops this long after the last valid frame
  std::uint8_t fw_major = 0, fw_minor = 1, fw_patch = 0;
  std::int16_t max_code() const {
    return static_cast<std::int16_t>(std::uint32_t{max_current_uA} * 1000u / dac_step_nA);
  }
};

struct PulseConfig {
  std::uint32_t period_us = 5000;
  std::uint16_t width_us = 200;
  std::uint16_t interphase_us = 0;
  std::uint16_t balance_width_us = 200;
  std::uint8_t channels = 8;
  std::uint32_t max_pulses = 0;  // the device stops by itself after this many; 0: no limit
};

struct Status {
  State state = State::idle;
  Fault fault = Fault::none;
  std::uint32_t pulses = 0;  // delivered since the last start
  std::uint32_t weight_updates = 0;
  std::uint16_t rx_errors = 0;  // damaged frames dropped
};

void put_u16(std::vector<std::uint8_t>& b, std::uint16_t v);
void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v);
std::uint16_t get_u16(const std::uint8_t* p);
std::uint32_t get_u32(const std::uint8_t* p);

std::vector<std::uint8_t> encode(const Capabilities& c);
std::optional<Capabilities> decode_capabilities(const std::vector<std::uint8_t>& b, std::size_t at);
std::vector<std::uint8_t> encode(const PulseConfig& c);
std::optional<PulseConfig> decode_config(const std::vector<std::uint8_t>& b);
std::vector<std::uint8_t> encode(const Status& s);
std::optional<Status> decode_status(const std::vector<std::uint8_t>& b, std::size_t at);
std::vector<std::uint8_t> encode_weights(const std::vector<std::int16_t>& codes);
std::optional<std::vector<std::int16_t>> decode_weights(const std::vector<std::uint8_t>& b);

}  // namespace tp::device
