#pragma once
// The few STM32F405/407 and Cortex-M4 registers the firmware uses, by address.  Sources:
//   RM0090 rev 19 "STM32F405/415, STM32F407/417, ... reference manual" (ST):
//     2.3 memory map (peripheral base addresses, table 1);
//     3.9.1 FLASH_ACR (wait states, table 10 for 168 MHz at 2.7-3.6 V: 5);
//     7.3 RCC registers (CR 7.3.1, PLLCFGR 7.3.2, CFGR 7.3.3, AHB1ENR 7.3.10,
//         APB1ENR 7.3.13, APB2ENR 7.3.14);
//     8.4 GPIO registers (MODER, OSPEEDR, PUPDR, BSRR, AFRL/AFRH);
//     18.4 TIM2-TIM5 registers (CR1, DIER, SR, EGR, CNT, PSC, ARR);
//     21.4 IWDG registers (KR, PR, RLR);
//     28.5 SPI registers (CR1, SR, DR);
//     30.6 USART registers (SR, DR, BRR, CR1);
//     38.6.1 DBGMCU_IDCODE.
//   PM0214 rev 10 "STM32 Cortex-M4 programming manual" (ST): 4.3 NVIC (ISER, IPR),
//     4.4 SCB (VTOR, ICSR, SHPR3), 4.5 SysTick (CTRL, LOAD, VAL), 4.6.1 CPACR.
//   DS8626 (STM32F405xx/407xx datasheet) table 9 "alternate function mapping" for the AF
//     numbers in the board files; RM0090 table 61 for the interrupt positions.

#include <cstdint>

namespace tp::fw::reg {

inline volatile std::uint32_t& at(std::uint32_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// Peripheral base addresses (RM0090 table 1).
inline constexpr std::uint32_t TIM2 = 0x40000000, TIM5 = 0x40000C00;
inline constexpr std::uint32_t SPI2 = 0x40003800;
inline constexpr std::uint32_t IWDG = 0x40003000;
inline constexpr std::uint32_t USART2 = 0x40004400, USART1 = 0x40011000;
inline constexpr std::uint32_t GPIOA = 0x40020000;  // GPIOx = GPIOA + 0x400 * x
inline constexpr std::uint32_t RCC = 0x40023800;
inline constexpr std::uint32_t FLASH_IF = 0x40023C00;
inline constexpr std::uint32_t DBGMCU_IDCODE = 0xE0042000;

namespace rcc {
inline constexpr std::uint32_t CR = RCC + 0x00, PLLCFGR = RCC + 0x04, CFGR = RCC + 0x08;
inline constexpr std::uint32_t AHB1ENR = RCC + 0x30, APB1ENR = RCC + 0x40, APB2ENR = RCC + 0x44;
inline constexpr std::uint32_t CR_HSION = 1u << 0, CR_HSIRDY = 1u << 1, CR_HSEON = 1u << 16,
                               CR_HSERDY = 1u << 17, CR_HSEBYP = 1u << 18, CR_PLLON = 1u << 24,
                               CR_PLLRDY = 1u << 25;
inline constexpr std::uint32_t PLLCFGR_SRC_HSE = 1u << 22;
inline constexpr std::uint32_t CFGR_SW_PLL = 2u, CFGR_SWS_MASK = 3u << 2, CFGR_SWS_PLL = 2u << 2;
inline constexpr std::uint32_t CFGR_PPRE1_DIV4 = 5u << 10, CFGR_PPRE2_DIV2 = 4u << 13;
inline constexpr std::uint32_t APB1_TIM2 = 1u << 0, APB1_TIM5 = 1u << 3, APB1_SPI2 = 1u << 14,
                               APB1_USART2 = 1u << 17, APB2_USART1 = 1u << 4;
}  // namespace rcc

namespace flash {
inline constexpr std::uint32_t ACR = FLASH_IF + 0x00;
inline constexpr std::uint32_t ACR_5WS = 5u, ACR_PRFTEN = 1u << 8, ACR_ICEN = 1u << 9,
                               ACR_DCEN = 1u << 10;
}  // namespace flash

namespace gpio {
inline constexpr std::uint32_t MODER = 0x00, OSPEEDR = 0x08, PUPDR = 0x0C, IDR = 0x10, BSRR = 0x18,
                               AFRL = 0x20, AFRH = 0x24;
}

namespace tim {  // offsets
inline constexpr std::uint32_t CR1 = 0x00, DIER = 0x0C, SR = 0x10, EGR = 0x14, CNT = 0x24,
                               PSC = 0x28, ARR = 0x2C;
inline constexpr std::uint32_t CR1_CEN = 1u << 0, CR1_OPM = 1u << 3, DIER_UIE = 1u << 0,
                               SR_UIF = 1u << 0, EGR_UG = 1u << 0;
}  // namespace tim

namespace usart {  // offsets
inline constexpr std::uint32_t SR = 0x00, DR = 0x04, BRR = 0x08, CR1 = 0x0C;
inline constexpr std::uint32_t SR_PE = 1u << 0, SR_FE = 1u << 1, SR_NF = 1u << 2, SR_ORE = 1u << 3,
                               SR_RXNE = 1u << 5, SR_TXE = 1u << 7;
inline constexpr std::uint32_t CR1_RE = 1u << 2, CR1_TE = 1u << 3, CR1_RXNEIE = 1u << 5,
                               CR1_UE = 1u << 13;
}  // namespace usart

namespace spi {  // offsets
inline constexpr std::uint32_t CR1 = 0x00, SR = 0x08, DR = 0x0C;
inline constexpr std::uint32_t CR1_CPHA = 1u << 0, CR1_MSTR = 1u << 2, CR1_SPE = 1u << 6,
                               CR1_SSI = 1u << 8, CR1_SSM = 1u << 9, CR1_DFF16 = 1u << 11;
inline constexpr std::uint32_t SR_RXNE = 1u << 0, SR_TXE = 1u << 1, SR_BSY = 1u << 7;
}  // namespace spi

namespace iwdg {
inline constexpr std::uint32_t KR = IWDG + 0x00, PR = IWDG + 0x04, RLR = IWDG + 0x08;
inline constexpr std::uint32_t KEY_START = 0xCCCC, KEY_RELOAD = 0xAAAA, KEY_UNLOCK = 0x5555;
}  // namespace iwdg

namespace scb {
inline constexpr std::uint32_t VTOR = 0xE000ED08, CPACR = 0xE000ED88;
}
namespace systick {
inline constexpr std::uint32_t CTRL = 0xE000E010, LOAD = 0xE000E014, VAL = 0xE000E018;
inline constexpr std::uint32_t CTRL_ENABLE = 1u << 0, CTRL_TICKINT = 1u << 1,
                               CTRL_CLKSOURCE_CPU = 1u << 2;
}  // namespace systick
namespace nvic {
inline constexpr std::uint32_t ISER0 = 0xE000E100, IPR0 = 0xE000E400;
}

// Interrupt positions (RM0090 table 61).
inline constexpr int IRQ_TIM2 = 28, IRQ_USART1 = 37, IRQ_USART2 = 38, IRQ_TIM5 = 50;

inline void nvic_enable(int irq, std::uint8_t priority) {
  volatile std::uint8_t* ipr = reinterpret_cast<volatile std::uint8_t*>(nvic::IPR0);
  ipr[irq] = static_cast<std::uint8_t>(priority << 4);  // 4 priority bits, upper nibble
  at(nvic::ISER0 + 4u * static_cast<std::uint32_t>(irq / 32)) = 1u << (irq % 32);
}

inline void disable_irq() {
  __asm volatile("cpsid i" ::: "memory");
}
inline void enable_irq() {
  __asm volatile("cpsie i" ::: "memory");
}
inline void wait_for_interrupt() {
  __asm volatile("wfi");
}
inline std::uint32_t primask() {
  std::uint32_t r;
  __asm volatile("mrs %0, primask" : "=r"(r));
  return r;
}

// Interrupts of priority `level` and below (numerically >= level) masked for the lifetime
// of the object (BASEPRI, PM0214 2.1.3); more urgent ones, such as the stop input at
// priority 0 and the pulse edges' SysTick at 1, still come.
class MaskFrom {
 public:
  explicit MaskFrom(std::uint8_t level) {
    __asm volatile("mrs %0, basepri" : "=r"(was_));
    const std::uint32_t v = static_cast<std::uint32_t>(level) << 4;
    __asm volatile("msr basepri, %0" ::"r"(v) : "memory");
  }
  ~MaskFrom() { __asm volatile("msr basepri, %0" ::"r"(was_) : "memory"); }
  MaskFrom(const MaskFrom&) = delete;
  MaskFrom& operator=(const MaskFrom&) = delete;

 private:
  std::uint32_t was_;
};

// Interrupts off for the lifetime of the object, restored as they were.
class CriticalSection {
 public:
  CriticalSection() : was_(primask()) { disable_irq(); }
  ~CriticalSection() {
    if (!(was_ & 1u)) enable_irq();
  }
  CriticalSection(const CriticalSection&) = delete;
  CriticalSection& operator=(const CriticalSection&) = delete;

 private:
  std::uint32_t was_;
};

}  // namespace tp::fw::reg
