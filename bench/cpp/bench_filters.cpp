// Cost of one filter step (predict + every update that applies) for each filter and time-update
// policy, float and double: ns per step (median of repeats after a warm-up), the number of
// floating-point operations of one step (counted by running the same code on a counting
// scalar, flop_counter.hpp), the resulting GFLOP/s, and the heap allocations seen during the
// timed steps (must be 0).
//
//   cmake -S . -B build/bench -DQUATNAV_BUILD_BENCH=ON && cmake --build build/bench -j2
//   build/bench/bench/cpp/quatnav_bench_filters [--reps R] [--steps N] [--filter SUBSTR] [--csv]
//
// Instruction counts that do not depend on the machine's load: bench/cpp/callgrind.sh.
//
// Adding a filter: write a case struct like QEKFCase in bench_cases.hpp (name, policy, init, step)
// and add one line `run_case<XCase>(opt);` to a bench_cases_*.cpp unit (or a new unit).
#include <cstdlib>
#include <new>

#include "bench_cases.hpp"

// ------------------------------------------------------------------------------------------
// Heap allocations during the timed loop (global operator new counter).
// ------------------------------------------------------------------------------------------
std::atomic<std::uint64_t> g_allocs{0};
void* operator new(std::size_t n) {
  ++g_allocs;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

int main(int argc, char** argv) {
  qb::Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc) opt.reps = std::max(1, std::atoi(argv[++i]));
    else if (a == "--steps" && i + 1 < argc) opt.steps = std::max(1, std::atoi(argv[++i]));
    else if (a == "--filter" && i + 1 < argc) opt.filter = argv[++i];
    else if (a == "--csv") opt.csv = true;
    else if (a == "--no-flops") opt.flops = false;
    else if (a == "--list") opt.list = true;
    else if (a == "--iterations") opt.iterations = true;
    else if (a == "--scalar" && i + 1 < argc) opt.scalar = argv[++i];
    else {
      std::printf("usage: %s [--reps R] [--steps N] [--filter SUBSTR] [--csv] [--no-flops] [--scalar float|double] [--iterations]\n", argv[0]);
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (opt.list) {
  } else if (opt.csv) {
    std::printf("filter,policy,step,flops_per_step,ns_double,ns_float,heap_allocs\n");
  } else {
    std::printf("ns per step: median of %d repeats of %zu steps after a warm-up; flops counted on a "
                "counting scalar\n", opt.reps, opt.steps);
    std::printf("%-42s %-18s %8s %9s %7s %9s %7s %6s\n", "filter [policy]", "step", "flops", "ns f64",
                "GF/s", "ns f32", "GF/s", "allocs");
  }
  qb::run_qekf_cases(opt);
  qb::run_eskf_cases(opt);
  qb::run_euler_marg_cases(opt);
  qb::run_gpsins_cases(opt);
  qb::run_nav13_cases(opt);
  qb::run_nav13_ukf_cases(opt);
  return 0;
}
