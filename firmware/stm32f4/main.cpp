// The stimulator firmware: the portable device core (lib/device) on an STM32F405/407.
//
//   USART1  the host link (docs/protocol.md), received by interrupt into a ring
//   SysTick the alarm that paces every pulse edge (pulse_engine.hpp)
//   TIM2    the microsecond clock every time comes from
//   SPI2    the 8-channel DAC (dac_ad56x8.hpp); a GPIO enables the electrode switches
//   USART2  the monitor: one JSON line per delivered pulse, as stim-emu --record writes
//   ADC1    each electrode's voltage at each pulse's main phase's end (sense.hpp); under
//           QEMU, the skin model on the skin block beside the configuration block
//   EXTI    the stop input: its edge opens the electrode switches and latches them open
//   IWDG    resets the MCU if this loop ever stops
//
// The main loop feeds received bytes to the core, lets it emit the pulses due within
// kLeadUs to the engine, follows its state (output-enable high only while it runs, and
// every way of stopping stops the engine first), and writes the monitor's lines.

#include <cstdint>

#include "board.hpp"
#include "dac_ad56x8.hpp"
#include "device/config_block.hpp"
#include "device/device_core.hpp"
#include "device/pulse_record.hpp"
#include "device/skin_block.hpp"
#include "hw.hpp"
#include "pulse_engine.hpp"
#include "sense.hpp"

extern "C" const std::uint8_t _config_block[];
extern "C" const std::uint8_t _skin_block[];

namespace tp::fw {
namespace {

// Pulses are handed to the engine this long before their slot (plus its delay): the loop
// runs at least every millisecond.  The core's watchdog therefore acts up to this much
// early, never late.
constexpr std::uint64_t kLeadUs = 2000;

Clock g_clock;
Alarm g_alarm;
Uart g_host, g_monitor;
DacAd56x8 g_dac;
PulseEngine g_engine;
AdcSense g_adc_sense;
SkinSense g_skin_sense;  // the emulated board's (23 KB: its scenario's events)
Sense* g_sense = nullptr;  // the board measures: one of the two
int g_stop_irq = -1;
// A monitor line and a pulse's readings: the main loop's, and the start-up probes'.
char g_line[device::kMaxElectricalRecordLine];
device::ElectricalRecord g_electrical;

// The DAC resolutions this board's parts offer: AD5628, AD5648, AD5668.
constexpr std::uint32_t kDacBits = (1u << 12) | (1u << 14) | (1u << 16);

// The pulses a second this board delivers on time, from its own clock at start-up (the
// output off): a pulse's work in the main loop and the engine, measured, in at most three
// quarters of the time (the rest for the host's frames, the watchdog and the loop's turns;
// under QEMU, 1000 pulses a second keep 62 % of the time busy and come on time:
// stimctl.pty-rates).
//  - measured over kProbes pulses: formatting the monitor's record of 8 channels at their
//    widest, and loading the DAC with the pulse's three phases (main, balancing, zeros);
//  - plus the engine's four edges, each woken early_us ahead and waited out, and the
//    core's scheduling of a pulse: at most 6000 instructions (firmware.sched-bench's bound
//    on one call of advance), at an instruction a cycle, or QEMU's 32 ns an instruction.
std::uint16_t measure_pulse_rate(std::uint32_t early_us, std::uint32_t core_hz, bool emulated) {
  constexpr std::uint32_t kProbes = 16;
  device::PulseRecord r;
  r.channels = 8;
  r.pattern = 255;
  r.t_us = 3599999999u;
  r.slip_us = 1000;
  r.step_nA = 977;
  r.width_us = r.interphase_us = r.balance_width_us = 1000;
  r.measured = true;
  r.start_us = 3599999999u;
  r.measured_width_us = r.measured_interphase_us = r.measured_balance_us = 1000;
  for (std::size_t i = 0; i < 8; ++i) {
    r.main[i] = static_cast<std::int16_t>(i % 2 ? -2047 : 2047);
    r.balance[i] = static_cast<std::int16_t>(-r.main[i]);
  }
  static const std::int16_t kZeros[8] = {};
  // A board that measures also turns each pulse's samples into readings (under QEMU, the
  // skin model: the costliest part) and writes them in the record.
  static const std::uint16_t kRaw[8] = {};
  if (g_sense) r.electrical = &g_electrical;
  const std::uint64_t t0 = g_clock.now_us();
  for (std::uint32_t k = 0; k < kProbes; ++k) {
    if (g_sense) g_sense->reading(r, k, kRaw, g_electrical);
    (void)device::format_record(r, g_line);
    g_dac.load(r.main, 8);
    g_dac.load(r.balance, 8);
    g_dac.load(kZeros, 8);
  }
  const std::uint64_t probed_us = (g_clock.now_us() - t0 + kProbes - 1) / kProbes;
  const std::uint64_t sched_us = emulated ? 6000u * 32u / 1000u : 6000ull * 1000000u / core_hz + 1;
  const std::uint64_t pulse_us = probed_us + 4 * (early_us + 2) + sched_us;
  const std::uint64_t rate = 3000000u / (4 * pulse_us);
  return static_cast<std::uint16_t>(rate < 1 ? 1 : rate > 65535 ? 65535 : rate);
}

// The edges a second this board delivers on time in shaped pulses, measured as above on a
// pulse of 16 phases (the costliest: 17 edges, 17 loads of the DAC, the longest record),
// in three quarters of the time: 17 x its pulses a second.
std::uint32_t measure_edge_rate(std::uint32_t early_us, std::uint32_t core_hz, bool emulated) {
  constexpr std::uint32_t kProbes = 8;
  static device::PulseRecord r;  // static: the measurement's stack stays small
  r = device::PulseRecord{};
  r.channels = 8;
  r.pattern = 255;
  r.t_us = 3599999999u;
  r.slip_us = 1000;
  r.step_nA = 977;
  r.measured = true;
  r.start_us = 3599999999u;
  r.shape.n = static_cast<std::uint8_t>(device::kMaxPhases);
  for (std::size_t k = 0; k < device::kMaxPhases; ++k) {
    r.shape.duration_us[k] = 1000;
    r.shape.units[k] = static_cast<std::int16_t>(k % 2 ? -1024 : 1024);
    r.measured_duration_us[k] = 1000;
  }
  for (std::size_t i = 0; i < 8; ++i) r.main[i] = static_cast<std::int16_t>(i % 2 ? -63 : 63);
  std::int16_t codes[8];
  const std::uint64_t t0 = g_clock.now_us();
  for (std::uint32_t p = 0; p < kProbes; ++p) {
    (void)device::format_record(r, g_line);
    for (std::size_t k = 0; k <= device::kMaxPhases; ++k) {
      device::shape_codes(r.main, 8, r.shape, k, codes);
      g_dac.load(codes, 8);
      g_dac.output(codes, 8);
    }
  }
  const std::uint64_t probed_us = (g_clock.now_us() - t0 + kProbes - 1) / kProbes;
  const std::uint64_t sched_us = emulated ? 6000u * 32u / 1000u : 6000ull * 1000000u / core_hz + 1;
  const std::uint64_t edges = device::kMaxPhases + 1;
  const std::uint64_t pulse_us = probed_us + edges * (early_us + 2) + sched_us;
  const std::uint64_t rate = edges * 3000000u / (4 * pulse_us);
  return static_cast<std::uint32_t>(rate < 1 ? 1 : rate > device::hard::max_edge_rate_hz
                                                      ? device::hard::max_edge_rate_hz
                                                      : rate);
}

device::Capabilities capabilities(const device::DeviceConfig& c, const Board& board, bool emulated,
                                  std::uint16_t max_pulse_rate_hz, std::uint32_t max_edge_rate_hz,
                                  const Sense* sense) {
  device::Capabilities caps;
  caps.channels = c.channels;
  caps.max_current_uA = c.max_current_uA;
  const std::uint32_t step =
      device::dac_step_nA(c.max_current_uA > 0 ? c.max_current_uA : 1, c.dac_bits);
  caps.dac_step_nA = static_cast<std::uint16_t>(step);
  caps.min_width_us =
      board.min_phase_us > caps.min_width_us ? board.min_phase_us : caps.min_width_us;
  // QEMU's core is slower (32 ns an instruction: scripts/firmware-emu): loading the DAC
  // between two edges takes it about 23 us, so the emulated board's shortest phase is 50.
  if (emulated && caps.min_width_us < 50) caps.min_width_us = 50;
  caps.watchdog_ms = c.watchdog_ms;
  caps.max_pulse_rate_hz = max_pulse_rate_hz;
  // The pulse engine delivers shaped pulses phase by phase (up to 16), at the edge rate
  // measured on 16-phase pulses.
  caps.features = device::kFeatureShapedPulses;
  caps.max_phases = static_cast<std::uint8_t>(device::kMaxPhases);
  caps.max_edge_rate_hz = max_edge_rate_hz;
  if (sense) {  // every pulse measured, and the guards (docs/safety.md)
    caps.features |= device::kFeatureMeasures;
    caps.compliance_V = sense->compliance_V();
  }
  return caps;
}

// The sense this board measures with: under QEMU, the skin block's model (none without a
// block); on a real board, its ADC (none when the board file gives no sense inputs).
Sense* choose_sense(bool emulated) {
  if (emulated) return g_skin_sense.init(_skin_block, device::kSkinBlockMaxSize) ? &g_skin_sense : nullptr;
  return g_adc_sense.init(kBoard) ? &g_adc_sense : nullptr;
}

// Idle under QEMU.  With -icount, an idle CPU's virtual time jumps ahead by the host's real
// sleeping time, which overshoots deadlines by the host's wake-up delay: interrupts would
// come late by that much.  A CPU that never idles has a virtual time that is its
// instruction count, exactly, and QEMU's -icount align=on keeps that in step with real
// time (it sleeps while the guest is ahead).  So the emulated board idles in a loop that
// touches no peripheral (peripheral accesses are slow under -icount); interrupts end it.
void spin_idle() {
  std::uint32_t k = 2000;
  __asm volatile("1: subs %0, %0, #1\n bne 1b" : "+r"(k)::"cc");
}

}  // namespace
}  // namespace tp::fw

using namespace tp;
using namespace tp::fw;

extern "C" void SysTick_Handler() {
  g_engine.on_alarm();
}
extern "C" void USART1_IRQHandler() {
  g_host.on_interrupt();
}
extern "C" void USART2_IRQHandler() {
  g_monitor.on_interrupt();
}

// Faults and unexpected interrupts (startup.cpp): the electrode switches open at once,
// without the SPI (which may be what failed); then the IWDG resets the MCU.
extern "C" void tp_fault_stop() {
  gpio_set(kBoard.output_enable, false);
}
// The stop input (priority 0, above the engine): the switches open at once, and stay open.
extern "C" void EXTI_IRQHandler() {
  stop_input_acknowledge(kBoard);
  tp_fault_stop();
  g_engine.stop_input();
}
extern "C" void abort() {
  reg::disable_irq();
  tp_fault_stop();
  for (;;) {
  }
}
extern "C" void __cxa_pure_virtual() {
  abort();
}

extern "C" void firmware_main() {
  // Output-enable low and the watchdog running before anything that could take time (the
  // clock set-up's bounded waits) or fail.
  enable_peripheral_clocks();
  gpio_output(kBoard.output_enable, false);
  if (kBoard.hold_low.port != 0xFF) gpio_output(kBoard.hold_low, false);
  iwdg_start();
  const Clocks clocks = clock_init(kBoard);
  iwdg_feed();

  const device::DeviceConfig config =
      device::parse_config_block(_config_block, DacAd56x8::kChannels, kDacBits);
  g_clock.init(clocks.timer_hz);
  g_dac.init(kBoard, config.dac_bits);
  // The alarm wakes the engine early enough to cover its own interrupt latency, then it
  // waits on the clock: edges fall on their microsecond.  (QEMU's slower virtual core,
  // 32 ns an instruction, needs more; a real board's ADC, 8 conversions of 0.7 us before
  // the main phase's end, 8 more.)
  g_sense = choose_sense(clocks.emulated);
  const std::uint32_t early_us = clocks.emulated ? 50u : g_sense ? 11u : 3u;
  static device::DeviceCore core(
      capabilities(config, kBoard, clocks.emulated,
                   measure_pulse_rate(early_us, clocks.sysclk_hz, clocks.emulated),
                   measure_edge_rate(early_us, clocks.sysclk_hz, clocks.emulated), g_sense));
  const std::uint32_t step_nA = core.caps().dac_step_nA;

  gpio_alternate(kBoard.host_tx, 7);
  gpio_alternate(kBoard.host_rx, 7);
  gpio_alternate(kBoard.monitor_tx, 7);
  gpio_alternate(kBoard.monitor_rx, 7);
  g_host.init(reg::USART1, clocks.apb2_hz, kBoard.host_baud, true, clocks.emulated);
  g_monitor.init(reg::USART2, clocks.apb1_hz, kBoard.monitor_baud, false, clocks.emulated);
  g_alarm.init(clocks.sysclk_hz);
  g_engine.init(g_dac, g_clock, g_alarm, early_us, clocks.sysclk_hz);
  g_engine.set_sense(g_sense);
  g_stop_irq = stop_input_init(kBoard);
  // A stop input held at the active level (a maintained e-stop) keeps every output off; a
  // board's pin only (QEMU models no GPIO levels).
  const auto stop_held = [&] { return !clocks.emulated && stop_input_held(kBoard); };
  if (stop_held()) g_engine.stop_input();
  reg::nvic_enable(reg::IRQ_USART1, 2);
  reg::nvic_enable(reg::IRQ_USART2, 3);
  reg::enable_irq();

  // The engine follows the core: it stops whenever an output ends (output_ends() counts
  // every end, so a stop and a new start within one read are both seen) and starts when
  // one runs.  Called after every frame, before its reply is queued, and after advance().
  std::uint32_t ends_seen = core.output_ends();
  bool engine_on = false;
  auto follow = [&] {
    if (core.output_ends() != ends_seen) {
      ends_seen = core.output_ends();
      const bool completed = core.status().fault == device::Fault::completed &&
                             core.status().state == device::State::idle;
      if (completed) {
        g_engine.finish_output();  // its last pulses are queued: deliver them
      } else {
        // The queued pulses are dropped: the status counts delivered pulses only.
        std::uint64_t start_us = 0;
        const std::uint32_t dropped = g_engine.stop_output(start_us);
        if (dropped != 0) core.not_delivered(start_us, dropped);
      }
      engine_on = false;
    }
    if (core.status().state == device::State::running && !engine_on) {
      if (stop_held()) {
        g_engine.stop_input();  // a maintained stop input: latched, the session ends below
      } else {
        g_engine.release_stop();  // a new session's output (the stop input ended the old)
        g_engine.start_output();
        engine_on = true;
      }
    }
  };

  std::uint8_t rx[64];
  std::uint32_t monitor_lost = 0;
  std::uint64_t pressed_output_us = UINT64_MAX;  // the simulated board's last press
  for (;;) {
    iwdg_feed();
    // 0. The stop input: the engine has latched the switches open; the core ends the
    // session.  Under QEMU the skin's stop_input events press it, through its interrupt.
    std::uint64_t pressed_at_us = 0;
    if (g_engine.take_stop(pressed_at_us)) {
      core.stop_input(pressed_at_us);
      follow();
    }
    std::uint64_t stop_t_us = 0;
    if (g_sense == &g_skin_sense && core.status().state == device::State::running &&
        core.output_start_us() != pressed_output_us &&
        g_skin_sense.first_stop_input(stop_t_us) &&
        g_clock.now_us() >= core.output_start_us() + stop_t_us) {
      pressed_output_us = core.output_start_us();
      stop_input_pend(g_stop_irq);
    }
    // 1. The host's bytes; each reply is queued once the engine has followed its frame.
    std::size_t n = 0;
    while (n < sizeof rx && g_host.read(rx[n])) ++n;
    const std::uint64_t now = g_clock.now_us();
    core.set_line_counts(g_host.line_errors(), g_host.overruns());
    if (n > 0)
      core.receive(rx, n, now, [&](const std::uint8_t* p, std::size_t k) {
        follow();
        // A reply that does not fit is lost whole, as on a saturated line; the host
        // retransmits.
        (void)g_host.write(p, k);
      });
    // 2. The pulses due soon, to the engine.  One it cannot queue is not delivered, not
    // counted, and ends the output.
    std::uint32_t not_queued = 0;
    std::uint64_t not_queued_start_us = 0;
    core.advance(now + kLeadUs, [&](const device::DeliveredPulse& p) {
      follow();
      PulseJob job;
      job.slot_us = p.t_us;
      job.start_us = p.start_us;
      const std::size_t channels = p.codes.size() < 8 ? p.codes.size() : 8;  // caps: <= 8
      job.channels = static_cast<std::uint8_t>(channels);
      if (p.timing.shaped()) {  // the base codes and the phases
        job.shape = p.timing.shape;
        for (std::size_t i = 0; i < channels; ++i) job.main[i] = p.codes[i];
      } else {
        std::int16_t balance[device::kMaxChannels];
        device::balance_codes(p.codes, p.timing.width_us, p.timing.balance_width_us, balance);
        for (std::size_t i = 0; i < channels; ++i) {
          job.main[i] = p.codes[i];
          job.balance[i] = balance[i];
        }
      }
      job.pattern = p.pattern;
      job.slip_us = p.slip_us;
      job.width_us = p.timing.width_us;
      job.interphase_us = p.timing.interphase_us;
      job.balance_width_us = p.timing.balance_width_us;
      job.period_us = p.timing.period_us;
      job.step_nA = step_nA;
      if (!g_engine.submit(job)) {
        ++not_queued;
        not_queued_start_us = p.start_us;
      }
    });
    // A pulse the engine had no room for: it is behind its schedule, and the output ends
    // (Fault::overrun) rather than deliver less than was asked.
    if (not_queued != 0) core.overrun(not_queued_start_us, not_queued);
    // 3. The DAC or the sense failed: no more output until a reset.
    // An ADC conversion that never completed (its readings are not to be trusted) is one
    // too.
    if ((g_dac.faults() != 0 || g_engine.readback_faults() != 0 || g_adc_sense.timeouts() != 0) &&
        core.status().fault != device::Fault::output_fault)
      core.output_fault();
    follow();
    // 4. Each delivered pulse's readings (a board that measures) to the core, whose guards
    // may end the output (the engine then drops what it has queued); then the monitor:
    // whole lines only; lost ones are counted in the next.
    device::PulseRecord r;
    std::uint16_t raw[kSenseChannels];
    std::uint64_t output_us = 0;
    while (g_engine.pop_record(r, output_us, raw)) {
      if (g_sense) {
        g_sense->reading(r, output_us, raw, g_electrical);
        core.measured(output_us, r, g_electrical);
        r.electrical = &g_electrical;
        follow();  // a trip drops the engine's queue first
        g_engine.readings_done();
      }
      r.dropped_before += monitor_lost;
      const std::size_t len = device::format_record(r, g_line);
      if (g_monitor.write(reinterpret_cast<const std::uint8_t*>(g_line), len))
        monitor_lost = 0;
      else
        monitor_lost = r.dropped_before + 1;
    }
    g_host.kick();
    g_monitor.kick();
    if (!g_host.tx_empty() || !g_monitor.tx_empty()) continue;
    if (clocks.emulated)
      spin_idle();  // see spin_idle()
    else
      reg::wait_for_interrupt();
  }
}
