// Reset and the vector table of the STM32F405/407 (PM0214 2.3.4 "Vector table"; RM0090
// table 61: 82 maskable interrupts).  No vendor start-up code: copy .data, clear .bss, run
// the static constructors, then firmware_main().  The FPU is enabled first (PM0214 4.6.1 CPACR),
// since the hard-float ABI may use its registers anywhere.

#include <cstdint>

#include "regs.hpp"

extern "C" {
extern std::uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
// The firmware proper (main.cpp); C++ forbids calling main().
void firmware_main();
void Reset_Handler();
void Default_Handler();
// Stops the output; the firmware's main.cpp defines it.
void tp_fault_stop();
}

// An unexpected interrupt or a fault: the output stops, then the core waits for the
// independent watchdog to reset it (a reset leaves output-enable low).
extern "C" void Default_Handler() {
  tp::fw::reg::disable_irq();
  tp_fault_stop();
  for (;;) {
  }
}

// Handlers the firmware defines (main.cpp); every other vector stops the output
// (Default_Handler, above).
#define TP_WEAK_HANDLER(name) extern "C" void name() __attribute__((weak, alias("Default_Handler")))
TP_WEAK_HANDLER(NMI_Handler);
TP_WEAK_HANDLER(HardFault_Handler);
TP_WEAK_HANDLER(MemManage_Handler);
TP_WEAK_HANDLER(BusFault_Handler);
TP_WEAK_HANDLER(UsageFault_Handler);
TP_WEAK_HANDLER(SVC_Handler);
TP_WEAK_HANDLER(DebugMon_Handler);
TP_WEAK_HANDLER(PendSV_Handler);
TP_WEAK_HANDLER(SysTick_Handler);
TP_WEAK_HANDLER(TIM2_IRQHandler);
TP_WEAK_HANDLER(USART1_IRQHandler);
TP_WEAK_HANDLER(USART2_IRQHandler);
TP_WEAK_HANDLER(TIM5_IRQHandler);
TP_WEAK_HANDLER(EXTI_IRQHandler);  // every EXTI line's vector: the board's stop input
#undef TP_WEAK_HANDLER

namespace {
using Handler = void (*)();
constexpr int kIrqs = 82;

struct VectorTable {
  std::uint32_t* stack;
  Handler core[15];
  Handler irq[kIrqs];
};

constexpr VectorTable make_table() {
  VectorTable t{&_estack, {}, {}};
  Handler core[15] = {
      Reset_Handler,      NMI_Handler,      HardFault_Handler, MemManage_Handler, BusFault_Handler,
      UsageFault_Handler, nullptr,          nullptr,           nullptr,           nullptr,
      SVC_Handler,        DebugMon_Handler, nullptr,           PendSV_Handler,    SysTick_Handler};
  for (int i = 0; i < 15; ++i) t.core[i] = core[i];
  for (int i = 0; i < kIrqs; ++i) t.irq[i] = Default_Handler;
  t.irq[tp::fw::reg::IRQ_TIM2] = TIM2_IRQHandler;
  t.irq[tp::fw::reg::IRQ_USART1] = USART1_IRQHandler;
  t.irq[tp::fw::reg::IRQ_USART2] = USART2_IRQHandler;
  t.irq[tp::fw::reg::IRQ_TIM5] = TIM5_IRQHandler;
  constexpr int kExti[] = {6, 7, 8, 9, 10, 23, 40};  // EXTI0-4, EXTI9_5, EXTI15_10
  for (int irq : kExti) t.irq[irq] = EXTI_IRQHandler;
  return t;
}
}  // namespace

__attribute__((section(".isr_vector"), used)) const VectorTable g_vectors = make_table();

extern "C" void Reset_Handler() {
  tp::fw::reg::at(tp::fw::reg::scb::CPACR) |= 0xFu << 20;  // CP10, CP11: full access
  __asm volatile("dsb\n isb" ::: "memory");
  for (std::uint32_t *src = &_sidata, *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (std::uint32_t* p = &_sbss; p < &_ebss;) *p++ = 0;
  for (auto* f = __init_array_start; f < __init_array_end; ++f) (*f)();
  firmware_main();
  for (;;) {
  }
}
