#include "host/emulator_request.hpp"

#include "core/files.hpp"
#include "device/skin_block.hpp"
#include "host/skin_file.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/number.hpp"

namespace tp::host {

namespace {

std::string text(const std::string& given, double v) { return given.empty() ? number_text(v) : given; }

double fraction(double v, const char* what) {
  if (v < 0 || v > 1) bad_input(std::string(what) + ": " + number_beside(v, 0, 1) + " outside [0, 1]");
  return v;
}

double seconds(double v, const std::string& given, const char* what) {
  if (v < 0 || v > 1e6) bad_input(std::string(what) + ": " + text(given, v) + " outside [0, 1e6]");
  return v;
}

FaultInjection faults(const EmulatorRequest& r) {
  FaultInjection f;
  f.drop = fraction(r.drop, "--drop");
  f.corrupt = fraction(r.corrupt, "--corrupt");
  if (r.stall_after_s) f.stall_after_s = seconds(*r.stall_after_s, r.given.stall_after, "--stall-after");
  f.stall_s = seconds(r.stall_ms, r.given.stall_ms, "--stall-ms") * 1e-3;
  if (r.disconnect_after_s)
    f.disconnect_after_s = seconds(*r.disconnect_after_s, r.given.disconnect_after, "--disconnect-after");
  f.reply_delay_s = r.reply_delay_ms * 1e-3;
  if (!(f.reply_delay_s >= 0 && f.reply_delay_s <= 1))
    bad_input("--reply-delay-ms: " + text(r.given.reply_delay_ms, r.reply_delay_ms) +
              " outside [0, 1000] ms");
  f.seed = r.seed;
  return f;
}

}  // namespace

PtyEmulatorOptions pty_emulator_options(const EmulatorRequest& r) {
  namespace hard = device::hard;
  const double hard_mA = hard::max_current_uA * 1e-3;
  const std::string max_current = text(r.given.max_current, r.max_current_mA);
  if (!(r.max_current_mA >= 0.001 && r.max_current_mA <= hard_mA))
    bad_input("--max-current: " + max_current + " mA outside [0.001, " + number_text(hard_mA) +
              "] mA (the device's compile-time bound)");
  PtyEmulatorOptions o;
  o.faults = faults(r);
  o.caps.channels = static_cast<std::uint8_t>(r.channels);
  // Whole microamperes, rounded down: the limit is never raised by rounding.
  o.caps.max_current_uA = static_cast<std::uint16_t>(std::floor(r.max_current_mA * 1000 + 1e-9));
  // One code of a signed DAC of dac_bits spanning +-max_current (the device core's rule,
  // which the firmware applies to its own DAC).
  const std::uint32_t step = device::dac_step_nA(o.caps.max_current_uA, r.dac_bits);
  if (step == 0)  // the protocol's dac_step_nA is 16 bits
    bad_input("--dac-bits " + std::to_string(r.dac_bits) + " at " + max_current +
              " mA needs a DAC step over 65535 nA, more than the protocol carries "
              "(use more bits)");
  o.caps.dac_step_nA = static_cast<std::uint16_t>(step);
  o.caps.watchdog_ms = static_cast<std::uint16_t>(r.watchdog_ms);
  o.caps.max_pulse_rate_hz = static_cast<std::uint16_t>(r.max_pulse_rate_hz);
  o.record_path = r.record_path;
  o.skin = emulator_skin(r.skin_path, r.compliance_V, static_cast<std::size_t>(r.channels),
                         "--skin", "--compliance-v");
  o.apply_log_path = r.apply_log_path;
  o.event_log_path = r.event_log_path;
  o.forward_socket = r.forward_socket;
  return o;
}

std::size_t write_skin_block(const EmulatorRequest& r, const std::string& path) {
  if (r.skin_path.empty())
    bad_input("--skin-block: needs --skin (the skin the firmware's simulated board runs)");
  const PtyEmulatorOptions o = pty_emulator_options(r);
  std::string block(device::kSkinBlockMaxSize, '\0');
  const std::size_t n = device::encode_skin_block(
      *o.skin.scenario, static_cast<std::size_t>(r.channels), o.skin.compliance_V,
      reinterpret_cast<std::uint8_t*>(block.data()));
  if (n == 0) bad_input("--skin-block: the skin cannot be written as a block");
  block.resize(n);
  write_file_atomically(path, block, "--skin-block");
  return n;
}

}  // namespace tp::host
