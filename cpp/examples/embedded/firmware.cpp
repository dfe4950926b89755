// Replays a recorded input through one quatnav filter and prints the attitude after every
// sample. Built for a Cortex-M4F (QEMU mps2-an386, output through semihosting) and for the
// host (stdout), from the same source; run.py builds, runs and compares them.
//
// Compile-time settings (run.py passes them):
//   QN_SCALAR    float or double
//   QN_ADAPTER   the adapter type, e.g. qn_fw::AttitudeAdapter<quatnav::QuaternionEKF<QN_SCALAR>>
//   QN_INPUT     the generated recording header, e.g. "input_marg.h"
//   QN_NAME      the filter's name for the output
//
// Output lines (numbers are hexadecimal bit patterns, so nothing is lost in printing and no
// printf is needed on the target):
//   BEGIN <name> <n samples> <sizeof(Scalar)> <sizeof(State)> <sizeof(adapter)>
//   Q <k> <flags> <w> <x> <y> <z>         attitude q_nb after sample k
//   N <k> <lat> <lon> <h> <vN> <vE> <vD>  navigation filters only: position (double, rad, m)
//                                         and NED velocity (Scalar, m/s) after sample k
//   STACK <bytes>                         stack high-water of the step (target only)
//   TICKS <sum> <min> <max> <overhead>    SysTick ticks per step (target only)
//   CAL <ticks> <instructions>            a loop of known length (target only)
//   END
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#include QN_INPUT
#include "adapters.hpp"

#ifdef __arm__
#include "semihost.h"
extern "C" uintptr_t stack_low_water(void);
static void out(const char* s) { semihost_write0(s); }
#else
#include <cstdio>
static void out(const char* s) { std::fputs(s, stdout); }
#endif

namespace {

using Adapter = QN_ADAPTER;
using S = QN_SCALAR;
Adapter g_adapter;
// Every image holds the whole recording, used by its filter or not, so that image sizes differ
// by the filter alone: main reads one sample at an index the compiler cannot know.
volatile std::uint32_t g_touch_index = 0;
volatile float g_touch_sink = 0.0f;

struct Line {
  char buf[160];
  std::size_t n = 0;
  void put(const char* s) {
    while (*s && n + 1 < sizeof buf) buf[n++] = *s++;
  }
  void hex(std::uint64_t v, int digits) {
    static const char d[] = "0123456789abcdef";
    if (n + digits + 2 >= sizeof buf) return;
    buf[n++] = ' ';
    for (int i = digits - 1; i >= 0; --i) buf[n++] = d[(v >> (4 * i)) & 0xF];
  }
  void hexs(S x) {
    if (sizeof(S) == 4) {
      std::uint32_t u;
      std::memcpy(&u, &x, 4);
      hex(u, 8);
    } else {
      std::uint64_t u;
      std::memcpy(&u, &x, 8);
      hex(u, 16);
    }
  }
  void hexd(double x) {
    std::uint64_t u;
    std::memcpy(&u, &x, 8);
    hex(u, 16);
  }
  void flush() {
    buf[n++] = '\n';
    buf[n] = 0;
    out(buf);
    n = 0;
  }
};

// Navigation adapters also give position and velocity: nav(double llh[3], S v[3]).
template <class A, class = void> struct HasNav : std::false_type {};
template <class A>
struct HasNav<A, std::void_t<decltype(std::declval<const A&>().nav(static_cast<double*>(nullptr),
                                                                   static_cast<S*>(nullptr)))>> : std::true_type {};

template <class A> void put_nav(const A& a, std::uint32_t k, Line& l) {
  if constexpr (HasNav<A>::value) {
    double llh[3];
    S v[3];
    a.nav(llh, v);
    l.put("N");
    l.hex(k, 8);
    for (int i = 0; i < 3; ++i) l.hexd(llh[i]);
    for (int i = 0; i < 3; ++i) l.hexs(v[i]);
    l.flush();
  }
}

#ifdef __arm__
// SysTick, clocked by the core clock. Under QEMU -icount the virtual clock advances a fixed time
// per instruction, so ticks count executed instructions (run.py converts).
volatile std::uint32_t* const kSystCsr = reinterpret_cast<volatile std::uint32_t*>(0xE000E010u);
volatile std::uint32_t* const kSystRvr = reinterpret_cast<volatile std::uint32_t*>(0xE000E014u);
volatile std::uint32_t* const kSystCvr = reinterpret_cast<volatile std::uint32_t*>(0xE000E018u);
inline std::uint32_t ticks() { return *kSystCvr; }
inline std::uintptr_t stack_pointer() {
  std::uintptr_t sp;
  __asm__ volatile("mov %0, sp" : "=r"(sp));
  return sp;
}
#endif

}  // namespace

// One step of the filter: the root of the stack analysis (run.py reads its call graph).
extern "C" __attribute__((noinline)) std::uint32_t qn_step(std::uint32_t k) { return g_adapter.step(k); }

int main() {
  g_touch_sink = qn_input::touch(g_touch_index);
  Line l;
  l.put("BEGIN " QN_NAME);
  l.hex(qn_input::kN, 8);
  l.hex(sizeof(S), 8);
  l.hex(sizeof(typename Adapter::State), 8);
  l.hex(sizeof(Adapter), 8);
  l.flush();
#ifdef __arm__
  *kSystRvr = 0xFFFFFFu;
  *kSystCvr = 0;
  *kSystCsr = 0x5u;  // enable, core clock, no interrupt
  const std::uint32_t o0 = ticks();
  const std::uint32_t o1 = ticks();
  const std::uint32_t overhead = (o0 - o1) & 0xFFFFFFu;
  // Calibration: a loop of 1 + 2 * 1000 instructions between two reads.
  const std::uint32_t c0 = ticks();
  __asm__ volatile(
      "movw r0, #1000\n"
      "1: subs r0, r0, #1\n"
      "bne 1b\n" ::: "r0", "cc");
  const std::uint32_t c1 = ticks();
  std::uint64_t sum = 0;
  std::uint32_t tmin = 0xFFFFFFFFu, tmax = 0;
  const std::uintptr_t sp_call = stack_pointer();
#endif
  for (std::uint32_t k = 0; k < qn_input::kN; ++k) {
#ifdef __arm__
    const std::uint32_t t0 = ticks();
#endif
    const std::uint32_t fl = qn_step(k);
#ifdef __arm__
    const std::uint32_t t1 = ticks();
    const std::uint32_t dt = (t0 - t1) & 0xFFFFFFu;
    if (k > 0) {  // sample 0 initializes
      sum += dt;
      tmin = dt < tmin ? dt : tmin;
      tmax = dt > tmax ? dt : tmax;
    }
#endif
    const quatnav::Quat<S> q = g_adapter.attitude();
    l.put("Q");
    l.hex(k, 8);
    l.hex(fl, 8);
    for (int i = 0; i < 4; ++i) l.hexs(q[i]);
    l.flush();
    put_nav(g_adapter, k, l);
  }
#ifdef __arm__
  l.put("STACK");
  l.hex(sp_call - stack_low_water(), 8);
  l.flush();
  l.put("TICKS");
  l.hex(sum, 16);
  l.hex(tmin, 8);
  l.hex(tmax, 8);
  l.hex(overhead, 8);
  l.flush();
  l.put("CAL");
  l.hex((c0 - c1) & 0xFFFFFFu, 8);
  l.hex(2001, 8);
  l.flush();
#endif
  l.put("END");
  l.flush();
  return 0;
}
