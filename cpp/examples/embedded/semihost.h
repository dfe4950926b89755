// Minimal ARM semihosting (bkpt 0xAB on M-profile): write a string to the host, exit with a code.
// QEMU implements it with -semihosting-config enable=on,target=native.
#pragma once

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

static inline int semihost_call(int op, const void* arg) {
  register int r0 __asm__("r0") = op;
  register const void* r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

/// SYS_WRITE0: write a NUL-terminated string to the host console.
static inline void semihost_write0(const char* s) { semihost_call(0x04, s); }

/// SYS_EXIT_EXTENDED with ADP_Stopped_ApplicationExit: QEMU exits with `code`.
static inline void semihost_exit(int code) {
  const uint32_t block[2] = {0x20026u, (uint32_t)code};
  semihost_call(0x20, block);
  for (;;) {
  }
}

#ifdef __cplusplus
}
#endif
