// sched-bench.elf: what the device core's scheduling costs on the MCU (issue 22), built
// with the firmware's own flags and sources (lib/device/), run under QEMU by
// `scripts/bench firmware` (or flashed to a board; its line comes out on the monitor
// UART, USART2).
//
//  1. Per pulse: 16 patterns of 8 channels each (every code non-zero, at half amplitude so
//     that every pulse is scaled), at the highest rates such a table allows (utilisation 1:
//     50 + 50 us pulses and the 100 us gap, every 3.2 ms each), taken from the core as the
//     firmware's main loop takes them: DeviceCore::advance (the scheduler's heap, the
//     codes' expansion and scaling) and the balancing codes, each call timed.
//  1b. The guards' cost per pulse (protocol 7, issue 41): the same table again with the
//     density guard on, each pulse measured as a board that measures reports it (every
//     channel carrying current through 10 kOhm), DeviceCore::measured timed alone: the
//     impedance, the baseline and the three guards on 8 channels; then on 2 (a pattern of
//     2 pads).
//  2. The longest check at start: 256 patterns whose closed slip bound is too loose, so
//     the core simulates the exact schedule (about 12800 pulses of a budget of 16384),
//     timed against the IWDG's timeout (~150 ms, 100 ms at the shortest: hw.hpp).
//
// Timed on the microsecond timer.  Under QEMU's -icount shift=5 a microsecond is exactly
// 31.25 instructions, so the figures are instructions; on a board, 168 cycles.
#include <cstdint>

#include "board.hpp"
#include "device/device_core.hpp"
#include "device/frame.hpp"
#include "device/pulse_record.hpp"
#include "hw.hpp"

namespace tp::fw {
namespace {

Clock g_clock;
Uart g_monitor;
constexpr std::uint32_t kToken = 0xBE7C4001u;
std::uint8_t g_seq = 0;

class Bytes {
 public:
  void u8(std::uint32_t v) { b_[n_++] = static_cast<std::uint8_t>(v); }
  void u16(std::uint32_t v) {
    u8(v & 0xFF);
    u8(v >> 8);
  }
  void u32(std::uint32_t v) {
    u16(v & 0xFFFF);
    u16(v >> 16);
  }
  const std::uint8_t* data() const { return b_; }
  std::size_t size() const { return n_; }

 private:
  std::uint8_t b_[device::kMaxPayload] = {};
  std::size_t n_ = 0;
};

// Sends one frame to the core (its reply is dropped: what it did shows in the status).
void send(device::DeviceCore& core, device::Msg type, const Bytes& payload, std::uint64_t now) {
  std::uint8_t frame[device::kMaxEncodedFrame];
  std::size_t n = 0;
  device::encode_frame_to(++g_seq, static_cast<std::uint8_t>(type), payload.data(), payload.size(),
                          [&](std::uint8_t b) { frame[n++] = b; });
  core.receive(frame, n, now, [](const std::uint8_t*, std::size_t) {});
}

Bytes table(std::uint16_t n, std::uint8_t channels, std::uint16_t gap) {
  Bytes b;
  b.u32(kToken);
  b.u16(n);
  b.u8(channels);
  b.u16(gap);
  return b;
}
Bytes pattern(std::uint16_t i, std::uint32_t period, std::uint32_t phase, std::uint16_t width) {
  Bytes b;
  b.u32(kToken);
  b.u16(i);
  b.u32(period);
  b.u32(phase);
  b.u16(width);
  b.u16(0);
  b.u16(width);
  b.u32(0);  // no count: runs until stopped
  return b;
}
// Eight non-zero codes summing to zero (in pairs), different for each pattern.
Bytes codes(std::uint16_t i) {
  Bytes b;
  b.u32(kToken);
  b.u16(i);
  b.u8(8);
  for (std::uint32_t c = 0; c < 8; ++c) {
    const auto m = static_cast<std::int32_t>(100 + 3 * i + c / 2);
    b.u8(c);
    b.u16(static_cast<std::uint16_t>(static_cast<std::int16_t>(c % 2 == 0 ? m : -m)));
  }
  return b;
}
Bytes token() {
  Bytes b;
  b.u32(kToken);
  return b;
}

void text(const char* s) {
  std::size_t n = 0;
  while (s[n]) ++n;
  while (!g_monitor.write(reinterpret_cast<const std::uint8_t*>(s), n)) g_monitor.kick();
}
void number(std::uint64_t v) {
  char d[24];
  int k = 0;
  do {
    d[k++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v != 0);
  char out[24];
  int n = 0;
  while (k > 0) out[n++] = d[--k];
  out[n] = 0;
  text(out);
}
// x us as instructions (QEMU) or cycles (a board), in tenths: "1234.5".
void work(std::uint64_t us_x10, std::uint32_t per_us_x100) {
  const std::uint64_t v = us_x10 * per_us_x100 / 100;  // tenths
  number(v / 10);
  text(".");
  number(v % 10);
}

}  // namespace
}  // namespace tp::fw

using namespace tp;
using namespace tp::fw;

extern "C" void USART2_IRQHandler() {
  g_monitor.on_interrupt();
}
extern "C" void tp_fault_stop() {
  gpio_set(kBoard.output_enable, false);
}
extern "C" void abort() {
  for (;;) {
  }
}
extern "C" void __cxa_pure_virtual() {
  abort();
}

extern "C" void firmware_main() {
  enable_peripheral_clocks();
  gpio_output(kBoard.output_enable, false);  // nothing is driven: no DAC, output disabled
  const Clocks clocks = clock_init(kBoard);
  g_clock.init(clocks.timer_hz);
  gpio_alternate(kBoard.monitor_tx, 7);
  g_monitor.init(reg::USART2, clocks.apb1_hz, kBoard.monitor_baud, false, clocks.emulated);
  reg::nvic_enable(reg::IRQ_USART2, 3);
  reg::enable_irq();
  // Instructions (QEMU: 31.25 a us) or cycles (the core clock) per microsecond, x 100.
  const std::uint32_t per_us_x100 = clocks.emulated ? 3125u : clocks.sysclk_hz / 10000u;

  device::Capabilities caps;
  caps.channels = 8;
  caps.min_width_us = 50;
  caps.watchdog_ms = 1000;
  caps.features = device::kFeatureMeasures;  // changes nothing in part 1: no guards, no hold
  caps.compliance_V = 100;
  static device::DeviceCore core(caps);

  // 1. 16 patterns, every 3200 us, staggered 200 us apart: utilisation 1, no slip.
  send(core, device::Msg::configure_table, table(16, 8, 100), 0);
  for (std::uint16_t i = 0; i < 16; ++i) {
    send(core, device::Msg::set_pattern, pattern(i, 3200, 200u * i, 50), 0);
    send(core, device::Msg::set_codes, codes(i), 0);
  }
  send(core, device::Msg::start, token(), 0);
  Bytes half;
  half.u32(kToken);
  half.u16(0);
  half.u8(16);
  for (int i = 0; i < 16; ++i) half.u16(device::kFullScale / 2);
  const std::uint32_t updates = core.status().weight_updates;
  send(core, device::Msg::set_amplitudes, half, 0);
  const bool running =
      core.status().state == device::State::running && core.status().weight_updates == updates + 1;
  constexpr std::uint32_t kPulses = 16000;
  std::uint64_t total_us = 0, worst_us = 0, now = 0;
  std::uint32_t pulses = 0, calls = 0;
  std::int32_t checksum = 0;
  while (running && pulses < kPulses) {
    now += 200;  // one pulse due each call
    if (now % 100000 == 0) send(core, device::Msg::keepalive, token(), now);
    const std::uint64_t t0 = g_clock.now_us();
    core.advance(now, [&](const device::DeliveredPulse& p) {
      std::int16_t balance[device::kMaxChannels];
      device::balance_codes(p.codes, p.timing.width_us, p.timing.balance_width_us, balance);
      checksum += p.codes[p.pattern % 8] + balance[0];
      ++pulses;
    });
    const std::uint64_t dt = g_clock.now_us() - t0;
    total_us += dt;
    if (dt > worst_us) worst_us = dt;
    ++calls;
  }
  send(core, device::Msg::stop, token(), now);

  // 1b. The same table, the density guard on (5 mm^2, k 1.85), every pulse measured.
  send(core, device::Msg::configure_table, table(16, 8, 100), now);
  for (std::uint16_t i = 0; i < 16; ++i) {
    send(core, device::Msg::set_pattern, pattern(i, 3200, 200u * i, 50), now);
    send(core, device::Msg::set_codes, codes(i), now);
  }
  Bytes guards;
  guards.u32(kToken);
  guards.u32(5000000);  // area_um2
  guards.u16(1850);     // Shannon's k
  guards.u16(100);      // lost contact
  guards.u16(50);       // probe
  guards.u8(0);
  send(core, device::Msg::set_guards, guards, now);
  send(core, device::Msg::start, token(), now);
  const bool guarded = core.status().state == device::State::running;
  static device::ElectricalRecord reading;
  constexpr std::uint32_t kMeasured = 1600;
  std::uint64_t guard_us = 0, clock_us = 0, guard2_us = 0, clock2_us = 0;
  std::uint32_t measured = 0;
  const std::uint64_t out_us = core.output_start_us();
  // kMeasured pulses with all 8 channels carrying current, then kMeasured with 2 (the others
  // reported as carrying none, as a pattern of 2 pads is).
  for (std::uint32_t k = 0; guarded && measured < 2 * kMeasured && k < 4 * kMeasured; ++k) {
    now += 200;
    if (now % 100000 == 0) send(core, device::Msg::keepalive, token(), now);
    core.advance(now, [&](const device::DeliveredPulse& p) {
      const device::PulseRecord r = device::record_of(p);
      for (std::size_t c = 0; c < 8; ++c) {
        const std::int32_t asked = r.main[c] * static_cast<std::int32_t>(r.step_nA);
        reading.carried[c] = r.main[c] != 0 && (measured < kMeasured || c < 2);
        reading.current_nA[c] = asked;
        reading.voltage_mV[c] = asked / 100;  // 10 kOhm: nA x 1e4 ohm / 1e6 = mV
        reading.at_rail[c] = false;
      }
      const std::uint64_t t0 = g_clock.now_us();
      core.measured(out_us, r, reading);
      const std::uint64_t t1 = g_clock.now_us();
      (measured < kMeasured ? guard_us : guard2_us) += t1 - t0;
      // The two readings' own cost, subtracted below.
      (measured < kMeasured ? clock_us : clock2_us) += g_clock.now_us() - t1;
      ++measured;
    });
  }
  const bool guards_ok = guarded && core.status().state == device::State::running;
  send(core, device::Msg::stop, token(), now);

  // 2. 256 patterns: four at 1000 Hz, 252 at 1 Hz staggered over the second.
  send(core, device::Msg::configure_table, table(256, 8, 100), now);
  for (std::uint16_t i = 0; i < 256; ++i) {
    const bool fast = i < 4;
    send(core, device::Msg::set_pattern,
         pattern(i, fast ? 1000u : 1000000u, fast ? 250u * i : 250u + 3900u * (i - 4u), 50), now);
    send(core, device::Msg::set_codes, codes(i), now);
  }
  const std::uint64_t s0 = g_clock.now_us();
  send(core, device::Msg::start, token(), now);
  const std::uint64_t start_us = g_clock.now_us() - s0;
  const bool started = core.status().state == device::State::running;
  send(core, device::Msg::stop, token(), now);

  text("sched-bench: ");
  text(clocks.emulated ? "QEMU (instructions)" : "board (cycles)");
  text(": 16 patterns x 8 channels at utilisation 1: ");
  number(pulses);
  text(" pulses in ");
  number(calls);
  text(" calls, ");
  work(total_us * 10 / (pulses ? pulses : 1), per_us_x100);
  text(" a pulse (mean), ");
  work(worst_us * 10, per_us_x100);
  text(" at most (a call); guards ");
  work((guard_us > clock_us ? guard_us - clock_us : 0) * 10 / kMeasured, per_us_x100);
  text(" a pulse of 8 channels, ");
  work((guard2_us > clock2_us ? guard2_us - clock2_us : 0) * 10 / kMeasured, per_us_x100);
  text(" of 2 (mean, ");
  number(measured);
  text(guards_ok ? " measured, none tripped)" : " measured, FAILED)");
  text("; start of 256 patterns with the exact slip check: ");
  number(start_us);
  text(" us (");
  text(started ? "accepted" : "refused");
  text("); setup ");
  text(running && pulses == kPulses ? "ok" : "FAILED");
  text("; checksum ");
  number(static_cast<std::uint32_t>(checksum));
  text("\n");
  for (;;) g_monitor.kick();
}
