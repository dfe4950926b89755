/* Reset handler and vector table for a Cortex-M4F on QEMU mps2-an386: enable the FPU, copy
 * .data, zero .bss, paint the stack region (for the high-water measurement), run the static
 * constructors, call main and leave QEMU through semihosting with main's return value. */
#include <stdint.h>

#include "semihost.h"

extern uint32_t __data_load, __data_start, __data_end, __bss_start, __bss_end;
extern uint32_t __stack_top, __stack_limit;
extern void (*__preinit_array_start[])(void);
extern void (*__preinit_array_end[])(void);
extern void (*__init_array_start[])(void);
extern void (*__init_array_end[])(void);

int main(void);

#define STACK_PAINT 0xC5C5C5C5u

void Reset_Handler(void) {
  /* CPACR: full access to CP10 and CP11 (the FPU) before any floating-point instruction. */
  *(volatile uint32_t*)0xE000ED88u |= (0xFu << 20);
  __asm__ volatile("dsb\n\tisb" ::: "memory");
  for (uint32_t *s = &__data_load, *d = &__data_start; d < &__data_end;) *d++ = *s++;
  for (uint32_t* d = &__bss_start; d < &__bss_end;) *d++ = 0;
  /* Paint the stack region up to 256 bytes below the current stack pointer. */
  uint32_t sp;
  __asm__ volatile("mov %0, sp" : "=r"(sp));
  for (uint32_t* p = &__stack_limit; (uint32_t)p < sp - 256u; ++p) *p = STACK_PAINT;
  for (void (**f)(void) = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (void (**f)(void) = __init_array_start; f < __init_array_end; ++f) (*f)();
  semihost_exit(main());
}

/* Lowest address of the stack region that was written since reset. */
uintptr_t stack_low_water(void) {
  const uint32_t* p = &__stack_limit;
  while (p < &__stack_top && *p == STACK_PAINT) ++p;
  return (uintptr_t)p;
}

static void fault(const char* what) {
  semihost_write0(what);
  semihost_exit(3);
}
void HardFault_Handler(void) { fault("FAULT hard\n"); }
void MemManage_Handler(void) { fault("FAULT memmanage\n"); }
void BusFault_Handler(void) { fault("FAULT bus\n"); }
void UsageFault_Handler(void) { fault("FAULT usage\n"); }
void Default_Handler(void) { fault("FAULT unexpected interrupt\n"); }

typedef void (*vector_t)(void);
__attribute__((section(".isr_vector"), used)) const vector_t vector_table[16] = {
    (vector_t)&__stack_top, Reset_Handler,     Default_Handler,   HardFault_Handler,
    MemManage_Handler,      BusFault_Handler,  UsageFault_Handler, 0,
    0,                      0,                 0,                 Default_Handler,
    Default_Handler,        0,                 Default_Handler,   Default_Handler,
};
