#pragma once
// The MCU's peripherals as the firmware uses them: clocks, pins, the microsecond clock,
// the alarm, the UARTs and the independent watchdog.  Register-level, no vendor library.

#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "regs.hpp"

namespace tp::fw {

struct Clocks {
  std::uint32_t sysclk_hz;  // the core, and SysTick
  std::uint32_t apb1_hz, apb2_hz;
  std::uint32_t timer_hz;  // TIM2's input clock
  bool emulated;           // QEMU: its RCC is a stub that reads 0
  bool pll;                // false: the crystal did not start; running on HSI
};

// Turns on the clocks of the GPIO ports and the peripherals the firmware uses.
void enable_peripheral_clocks();

// Sets SYSCLK to 168 MHz from the board's crystal, with bounded waits: a crystal that does
// not start leaves the core on its 16 MHz HSI (every derived clock follows), and an RCC
// that reads 0 (QEMU's unimplemented-device stub; a real RCC reads HSIRDY = 1 out of
// reset) selects QEMU's fixed clocks.
Clocks clock_init(const Board& board);

void gpio_output(Pin p, bool high);
void gpio_alternate(Pin p, std::uint8_t af);
void gpio_analog(Pin p);  // an ADC input

// The board's stop input (board.hpp): the pin an input (pulled up when active low), its
// EXTI line interrupting on the edge to its active level, above every other interrupt.
// Returns the line's IRQ number; -1 when the board has none.
int stop_input_init(const Board& b);
void stop_input_acknowledge(const Board& b);  // in its handler: clears the line's pending bit
bool stop_input_held(const Board& b);         // the pin at its active level now
// What the pin's edge does, without the pin (the simulated board under QEMU, whose GPIOs
// are not modelled): the interrupt made pending, as the EXTI makes it.
void stop_input_pend(int irq);
inline void gpio_set(Pin p, bool high) {
  reg::at(reg::GPIOA + 0x400u * p.port + reg::gpio::BSRR) =
      high ? (1u << p.pin) : (1u << (p.pin + 16));
}

// A 64-bit microsecond clock from TIM2's 32-bit counter (prescaled to 1 MHz); wraps are
// counted, so it must be read at least once every 71 minutes (the main loop reads it
// every millisecond).  Safe from interrupts and the main loop.
class Clock {
 public:
  void init(std::uint32_t timer_hz);
  std::uint64_t now_us();
  // The counter's microseconds alone (the low 32 bits of now_us()), one register read: for
  // a wait's last microseconds, whose readings must come faster than the counter ticks.
  // now_us() must still be called at least every 71 minutes (the firmware's loop does).
  static std::uint32_t counter() { return reg::at(reg::TIM2 + reg::tim::CNT); }

 private:
  std::uint32_t last_ = 0;
  std::uint64_t high_ = 0;
};

// The one interrupt that wakes the firmware on time: SysTick, counting core cycles,
// programmed for the next moment something must happen.  (QEMU 7.2's TIM2-5 update
// interrupt comes at now + the absolute target time, so the firmware does not pace with
// it; see firmware/README.md.)
class Alarm {
 public:
  void init(std::uint32_t core_hz);
  // The SysTick interrupt at target_us (now_us: the clock's reading), at once when it is
  // due; never later than max_wait_us from now.
  void set(std::uint64_t target_us, std::uint64_t now_us);

 private:
  std::uint32_t cycles_per_us_ = 168;
};

// A single-producer, single-consumer ring of N bytes (N a power of two): one side in an
// interrupt, the other in the main loop.
template <std::size_t N>
class ByteRing {
  static_assert((N & (N - 1)) == 0, "N must be a power of two");

 public:
  bool push(std::uint8_t b) {
    const std::uint32_t h = head_;
    if (h - tail_ == N) return false;
    __asm volatile("" ::: "memory");  // the index is read before the slot is written
    buf_[h % N] = b;
    __asm volatile("dmb" ::: "memory");
    head_ = h + 1;
    return true;
  }
  bool pop(std::uint8_t& b) {
    const std::uint32_t t = tail_;
    if (head_ == t) return false;
    __asm volatile("" ::: "memory");  // the index is read before the slot is
    b = buf_[t % N];
    __asm volatile("dmb" ::: "memory");
    tail_ = t + 1;
    return true;
  }
  std::size_t free_space() const { return N - (head_ - tail_); }
  bool empty() const { return head_ == tail_; }

 private:
  std::uint8_t buf_[N] = {};
  volatile std::uint32_t head_ = 0, tail_ = 0;
};

// A USART: receive by interrupt into a ring; transmit from a ring, by the TXE interrupt
// where the USART raises it (a real one) and by the main loop's kick() (QEMU's, which
// transmits at once and raises no TXE interrupt).
//
// synchronous: the USART sends each byte the moment DR is written and its TXE is always
// set (QEMU's, hw/char/stm32f2xx_usart.c), so kick() writes DR without reading SR first.
// Under QEMU every read of SR also wakes the emulator's main loop
// (qemu_chr_fe_accept_input -> qemu_notify_event): polling TXE before each byte of the
// monitor's lines cost ~3 ms of real time per line while the emulated clock stood still,
// so at 1000 pulses/s the emulated board fell behind real time by 3 to 7 times and missed
// the host's acknowledgement deadlines (firmware/README.md, "The board and QEMU").  One
// read per kick() stays: it lets QEMU's main loop deliver the host's bytes.
class Uart {
 public:
  void init(std::uint32_t base, std::uint32_t clock_hz, std::uint32_t baud, bool receive,
            bool synchronous = false);
  void on_interrupt();  // the USART's interrupt handler
  bool read(std::uint8_t& b) { return rx_.pop(b); }
  // Queues n bytes whole, or none (false) when they do not fit.
  bool write(const std::uint8_t* p, std::size_t n);
  void kick();  // main loop: send what the transmitter takes now
  bool tx_empty() const { return tx_.empty(); }
  std::uint32_t line_errors() const { return line_errors_; }  // framing, noise, parity
  std::uint32_t overruns() const { return overruns_; }        // hardware or ring full

 private:
  std::uint32_t base_ = 0;
  bool synchronous_ = false;
  ByteRing<512> rx_;
  ByteRing<4096> tx_;
  volatile std::uint32_t line_errors_ = 0, overruns_ = 0;
};

// The independent watchdog (IWDG, clocked by the ~32 kHz LSI): a main loop that stops
// feeding it for ~150 ms (about 100 to 285 ms over the LSI's 17 to 47 kHz, DS8626) resets the
// MCU, and a reset leaves output-enable low.  QEMU does not model it.
void iwdg_start();
inline void iwdg_feed() {
  reg::at(reg::iwdg::KR) = reg::iwdg::KEY_RELOAD;
}

}  // namespace tp::fw
