#include "hw.hpp"

namespace tp::fw {
namespace {

using reg::at;

// Bounded waits: a flag that never comes (a dead crystal, an unimplemented peripheral)
// must not hang the firmware.
bool wait_set(std::uint32_t address, std::uint32_t mask, std::uint32_t value) {
  for (std::uint32_t i = 0; i < 2000000; ++i)
    if ((at(address) & mask) == value) return true;
  return false;
}

std::uint32_t gpio_base(Pin p) {
  return reg::GPIOA + 0x400u * p.port;
}

void set_field(std::uint32_t address, unsigned shift, std::uint32_t mask, std::uint32_t value) {
  at(address) = (at(address) & ~(mask << shift)) | (value << shift);
}

}  // namespace

void enable_peripheral_clocks() {
  namespace rcc = reg::rcc;
  // GPIOA-D, and the peripherals: TIM2, SPI2, USART2 (APB1), USART1 (APB2).
  at(rcc::AHB1ENR) |= 0xFu;
  at(rcc::APB1ENR) |= rcc::APB1_TIM2 | rcc::APB1_SPI2 | rcc::APB1_USART2;
  at(rcc::APB2ENR) |= rcc::APB2_USART1;
  __asm volatile("dsb" ::: "memory");  // the clocks are on before the first access
}

Clocks clock_init(const Board& b) {
  namespace rcc = reg::rcc;
  if (!(at(rcc::CR) & rcc::CR_HSIRDY)) {
    // QEMU's netduinoplus2: SYSCLK fixed at 168 MHz (hw/arm/netduinoplus2.c) and TIM2-5
    // at the clock-frequency of 1 GHz that the SoC gives them (hw/arm/stm32f405_soc.c).
    // Baud rates are not modelled.
    return Clocks{168000000, 42000000, 84000000, 1000000000, true, true};
  }
  // The crystal oscillator first; then bypass mode, for a clock signal on OSC_IN (some
  // STM32F4-Discovery revisions take the ST-LINK's 8 MHz clock output, UM1472).
  at(rcc::CR) |= rcc::CR_HSEON;
  if (!wait_set(rcc::CR, rcc::CR_HSERDY, rcc::CR_HSERDY)) {
    at(rcc::CR) &= ~rcc::CR_HSEON;
    wait_set(rcc::CR, rcc::CR_HSERDY, 0);
    at(rcc::CR) |= rcc::CR_HSEBYP;  // writable only while HSE is off
    at(rcc::CR) |= rcc::CR_HSEON;
    if (!wait_set(rcc::CR, rcc::CR_HSERDY, rcc::CR_HSERDY)) {
      at(rcc::CR) &= ~(rcc::CR_HSEON | rcc::CR_HSEBYP);
      return Clocks{16000000, 16000000, 16000000, 16000000, false, false};  // HSI, no prescalers
    }
  }
  // 168 MHz needs 5 wait states at 2.7-3.6 V (RM0090 table 10), with prefetch and caches.
  at(reg::flash::ACR) =
      reg::flash::ACR_5WS | reg::flash::ACR_PRFTEN | reg::flash::ACR_ICEN | reg::flash::ACR_DCEN;
  // M [5:0], N [14:6], P [17:16] as P/2 - 1, source [22], Q [27:24]; reserved bits kept.
  at(rcc::PLLCFGR) = (at(rcc::PLLCFGR) & ~0x0F437FFFu) | b.pll_m | (b.pll_n << 6) |
                     (((b.pll_p / 2) - 1) << 16) | rcc::PLLCFGR_SRC_HSE | (b.pll_q << 24);
  at(rcc::CR) |= rcc::CR_PLLON;
  if (!wait_set(rcc::CR, rcc::CR_PLLRDY, rcc::CR_PLLRDY)) {
    at(rcc::CR) &= ~rcc::CR_PLLON;
    return Clocks{16000000, 16000000, 16000000, 16000000, false, false};
  }
  at(rcc::CFGR) = rcc::CFGR_PPRE1_DIV4 | rcc::CFGR_PPRE2_DIV2 | rcc::CFGR_SW_PLL;
  if (!wait_set(rcc::CFGR, rcc::CFGR_SWS_MASK, rcc::CFGR_SWS_PLL)) {
    at(rcc::CFGR) = 0;  // back to HSI
    return Clocks{16000000, 16000000, 16000000, 16000000, false, false};
  }
  const std::uint32_t sys = b.hse_hz / b.pll_m * b.pll_n / b.pll_p;
  // APB1 timers run at twice APB1 when its prescaler is not 1 (RM0090 7.2).
  return Clocks{sys, sys / 4, sys / 2, sys / 2, false, true};
}

void gpio_output(Pin p, bool high) {
  gpio_set(p, high);  // the level first, then the pin becomes an output
  set_field(gpio_base(p) + reg::gpio::MODER, 2u * p.pin, 3u, 1u);
  set_field(gpio_base(p) + reg::gpio::OSPEEDR, 2u * p.pin, 3u, 2u);
}

void gpio_alternate(Pin p, std::uint8_t af) {
  const std::uint32_t afr = p.pin < 8 ? reg::gpio::AFRL : reg::gpio::AFRH;
  set_field(gpio_base(p) + afr, 4u * (p.pin % 8), 0xFu, af);
  set_field(gpio_base(p) + reg::gpio::OSPEEDR, 2u * p.pin, 3u, 2u);
  set_field(gpio_base(p) + reg::gpio::MODER, 2u * p.pin, 3u, 2u);
}

void gpio_analog(Pin p) {
  set_field(gpio_base(p) + reg::gpio::PUPDR, 2u * p.pin, 3u, 0u);
  set_field(gpio_base(p) + reg::gpio::MODER, 2u * p.pin, 3u, 3u);
}

namespace {
// EXTI and SYSCFG (RM0090 12.3, 9.2.3-6); the lines' interrupts (RM0090 table 61).
constexpr std::uint32_t EXTI = 0x40013C00, SYSCFG = 0x40013800;
constexpr std::uint32_t EXTI_IMR = EXTI + 0x00, EXTI_RTSR = EXTI + 0x08, EXTI_FTSR = EXTI + 0x0C,
                        EXTI_PR = EXTI + 0x14, SYSCFG_EXTICR1 = SYSCFG + 0x08;
constexpr std::uint32_t APB2_SYSCFG = 1u << 14, NVIC_ISPR0 = 0xE000E200;
int exti_irq(std::uint8_t line) {
  return line <= 4 ? 6 + line : line <= 9 ? 23 : 40;
}
}  // namespace

int stop_input_init(const Board& b) {
  const Pin p = b.stop_input;
  if (p.port == 0xFF || p.pin > 15) return -1;
  at(reg::rcc::APB2ENR) |= APB2_SYSCFG;
  __asm volatile("dsb" ::: "memory");
  set_field(gpio_base(p) + reg::gpio::MODER, 2u * p.pin, 3u, 0u);  // input
  set_field(gpio_base(p) + reg::gpio::PUPDR, 2u * p.pin, 3u, b.stop_active_high ? 0u : 1u);
  set_field(SYSCFG_EXTICR1 + 4u * (p.pin / 4u), 4u * (p.pin % 4u), 0xFu, p.port);
  const std::uint32_t bit = 1u << p.pin;
  at(b.stop_active_high ? EXTI_RTSR : EXTI_FTSR) |= bit;
  at(EXTI_PR) = bit;  // nothing pending from before
  at(EXTI_IMR) |= bit;
  const int irq = exti_irq(p.pin);
  reg::nvic_enable(irq, 0);  // above the engine's SysTick and the UARTs
  return irq;
}

void stop_input_acknowledge(const Board& b) {
  if (b.stop_input.port != 0xFF) at(EXTI_PR) = 1u << b.stop_input.pin;
}

bool stop_input_held(const Board& b) {
  const Pin p = b.stop_input;
  if (p.port == 0xFF || p.pin > 15) return false;
  const bool high = (at(gpio_base(p) + reg::gpio::IDR) >> p.pin) & 1u;
  return high == b.stop_active_high;
}

void stop_input_pend(int irq) {
  if (irq >= 0) at(NVIC_ISPR0 + 4u * static_cast<std::uint32_t>(irq / 32)) = 1u << (irq % 32);
}

void Clock::init(std::uint32_t timer_hz) {
  namespace tim = reg::tim;
  at(reg::TIM2 + tim::CR1) = 0;
  at(reg::TIM2 + tim::PSC) = timer_hz / 1000000u - 1;
  at(reg::TIM2 + tim::ARR) = 0xFFFFFFFFu;
  at(reg::TIM2 + tim::EGR) = tim::EGR_UG;  // load the prescaler now
  at(reg::TIM2 + tim::SR) = 0;
  at(reg::TIM2 + tim::CNT) = 0;
  at(reg::TIM2 + tim::CR1) = tim::CR1_CEN;
  last_ = 0;
  high_ = 0;
}

std::uint64_t Clock::now_us() {
  reg::CriticalSection cs;
  const std::uint32_t c = at(reg::TIM2 + reg::tim::CNT);
  if (c < last_) high_ += std::uint64_t{1} << 32;
  last_ = c;
  return high_ | c;
}

void Alarm::init(std::uint32_t core_hz) {
  cycles_per_us_ = core_hz / 1000000u;
  // SysTick's priority (SHPR3, PM0214 4.4.8): 1, above the UARTs' (2, 3) so that edges are
  // on time; only the stop input (0) comes before it.
  at(0xE000ED20) = (at(0xE000ED20) & 0x00FFFFFFu) | (1u << 28);
}

void Alarm::set(std::uint64_t target_us, std::uint64_t now_us) {
  namespace st = reg::systick;
  if (target_us <= now_us) {
    at(0xE000ED04) = 1u << 26;  // ICSR.PENDSTSET: the SysTick interrupt now
    return;
  }
  std::uint64_t cycles = (target_us - now_us) * cycles_per_us_;
  if (cycles > 0xFFFFFFu) cycles = 0xFFFFFFu;
  at(st::CTRL) = 0;
  at(st::LOAD) = static_cast<std::uint32_t>(cycles - 1);
  at(st::VAL) = 0;
  at(st::CTRL) = st::CTRL_ENABLE | st::CTRL_TICKINT | st::CTRL_CLKSOURCE_CPU;
}

void Uart::init(std::uint32_t base, std::uint32_t clock_hz, std::uint32_t baud, bool receive,
                bool synchronous) {
  namespace u = reg::usart;
  base_ = base;
  synchronous_ = synchronous;
  at(base + u::CR1) = 0;
  at(base + u::BRR) = (clock_hz + baud / 2) / baud;  // 16x oversampling: USARTDIV x 16
  at(base + u::CR1) = u::CR1_UE | u::CR1_TE | (receive ? u::CR1_RE | u::CR1_RXNEIE : 0u);
}

void Uart::on_interrupt() {
  namespace u = reg::usart;
  const std::uint32_t sr = at(base_ + u::SR);
  if (sr & (u::SR_RXNE | u::SR_ORE)) {
    // Reading SR then DR clears RXNE and the error flags (RM0090 30.6.1).
    const auto byte = static_cast<std::uint8_t>(at(base_ + u::DR) & 0xFF);
    if (sr & u::SR_ORE) ++overruns_;
    if (sr & (u::SR_FE | u::SR_NF | u::SR_PE))
      ++line_errors_;  // a damaged byte is dropped: its frame then fails its CRC
    else if ((sr & u::SR_RXNE) && !rx_.push(byte))
      ++overruns_;
  }
  constexpr std::uint32_t kTxeie = 1u << 7;
  if ((at(base_ + u::CR1) & kTxeie) && (sr & u::SR_TXE)) {
    std::uint8_t b;
    if (tx_.pop(b))
      at(base_ + u::DR) = b;
    else
      at(base_ + u::CR1) &= ~kTxeie;
  }
}

bool Uart::write(const std::uint8_t* p, std::size_t n) {
  if (tx_.free_space() < n) return false;
  for (std::size_t i = 0; i < n; ++i) tx_.push(p[i]);
  return true;
}

void Uart::kick() {
  namespace u = reg::usart;
  constexpr std::uint32_t kTxeie = 1u << 7;
  // The UARTs' interrupts (priority 2 and 3) are masked, not the pulse edges' SysTick (1)
  // nor the stop input (0): a long line must not delay an edge.
  reg::MaskFrom no_uart(2);
  std::uint8_t b;
  if (synchronous_) {
    // TXE is always set: no read of SR before each byte (see hw.hpp).  One read a call
    // all the same: it is what lets QEMU's main loop deliver the host's next bytes while
    // the firmware spins (without it, keep-alives arrived late enough to trip a 100 ms
    // watchdog: firmware.pty-device-bounds).
    const std::uint32_t sr = at(base_ + u::SR);
    (void)sr;
    while (tx_.pop(b)) at(base_ + u::DR) = b;
    return;
  }
  // The ring first: a main loop with nothing to send reads no register.
  while (!tx_.empty() && (at(base_ + u::SR) & u::SR_TXE) && tx_.pop(b)) at(base_ + u::DR) = b;
  if (!tx_.empty()) at(base_ + u::CR1) |= kTxeie;
}

void iwdg_start() {
  namespace w = reg::iwdg;
  at(w::KR) = w::KEY_UNLOCK;
  at(w::PR) = 3;     // LSI / 32: ~1 kHz
  at(w::RLR) = 150;  // ~150 ms
  at(w::KR) = w::KEY_RELOAD;
  at(w::KR) = w::KEY_START;
}

}  // namespace tp::fw
