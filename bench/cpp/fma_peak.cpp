// This machine's scalar floating-point rate: chains of scalar fused multiply-adds, float and
// double, one dependent chain (latency bound) and K independent chains (throughput bound), and the
// cost of the libm calls the filters make (sin, cos, atan2, asin, exp, sqrt, a division), each in
// a dependent chain (latency) and independent (throughput). Compiled -O3 without -ffast-math;
// std::fma is a single instruction only when the target has FMA (-mfma or -march=native; the
// portable x86-64 build would call libm's software fma), so this program is built with -mfma and
// says so. Scalar code: -fno-tree-vectorize keeps the K chains in scalar registers.
//
//   g++ -O3 -mfma -fno-tree-vectorize -std=c++17 bench/cpp/fma_peak.cpp -o /tmp/fma_peak
//   /tmp/fma_peak [--reps R]
//
// Reported: ns per FMA, FMA/ns and flops/ns (2 flops per FMA), the median and the best of R
// repeats (default 51); the libm calls in ns per call, including the chain's FMA when dependent.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

// Median and minimum over the repeats of ns per iteration. Short repeats (a fraction of a
// millisecond) so that on a shared machine most of them run without being descheduled.
struct Timing {
  double median, best;
};

template <class F> Timing time_ns(int reps, long n, F&& body) {
  std::vector<double> t;
  body(n / 10);  // warm-up
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    body(n);
    const auto t1 = std::chrono::steady_clock::now();
    t.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(n));
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

// K independent chains x_i = fma(x_i, a, b); n iterations of all K -> n * K FMAs.
template <class S, int K> __attribute__((noinline)) S chains(long n, S a, S b) {
  S x[K];
  for (int i = 0; i < K; ++i) x[i] = S(i + 1) * S(1e-3);
  for (long k = 0; k < n; ++k) {
#pragma GCC unroll 16
    for (int i = 0; i < K; ++i) x[i] = std::fma(x[i], a, b);
  }
  S s = 0;
  for (int i = 0; i < K; ++i) s += x[i];
  return s;
}

volatile double g_sink;

template <class S, int K> void report_fma(int reps, const char* tname) {
  const long n = 250000 / K;  // 250,000 FMAs per repeat: 0.05-0.4 ms
  const S a = S(0.999999), b = S(1e-7);
  const Timing t = time_ns(reps, n, [&](long m) { g_sink = double(chains<S, K>(m, a, b)); });
  const double med = t.median / K, best = t.best / K;
  std::printf("%-8s fma, %2d independent chain%s  median %7.4f ns/FMA %6.3f FMA/ns %6.3f flops/ns   best %7.4f ns/FMA "
              "%6.3f flops/ns\n", tname, K, K == 1 ? " " : "s", med, 1.0 / med, 2.0 / med, best, 2.0 / best);
}

// libm and division: dependent chain y = f(y * c + d) (latency, includes the fma) and an
// independent loop over an array (throughput).
template <class S, class F> void report_call(int reps, const char* tname, const char* fname, F f) {
  const long n = 20000;
  const Timing lat = time_ns(reps, n, [&](long m) {
    S y = S(0.3);
    for (long k = 0; k < m; ++k) y = f(std::fma(y, S(0.5), S(0.1)));
    g_sink = double(y);
  });
  std::vector<S> in(1024), out(1024);
  for (int i = 0; i < 1024; ++i) in[i] = S(0.1) + S(0.8) * S(i) / S(1024);
  const Timing thr = time_ns(reps, n, [&](long m) {
    for (long k = 0; k < m; k += 1024) {
      for (int i = 0; i < 1024; ++i) out[i] = f(in[i]);
      g_sink = double(out[k % 1024]);
    }
  });
  std::printf("%-8s %-10s dependent median %7.2f best %7.2f ns/call   independent median %7.2f best %7.2f ns/call\n",
              tname, fname, lat.median, lat.best, thr.median, thr.best);
}

int main(int argc, char** argv) {
  int reps = 51;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--reps") == 0 && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
    else {
      std::printf("usage: %s [--reps R]\n", argv[0]);
      return 2;
    }
  }
#ifndef __FMA__
  std::printf("warning: built without -mfma: std::fma is a libm call, not one instruction\n");
#endif
  report_fma<double, 1>(reps, "double");
  report_fma<double, 4>(reps, "double");
  report_fma<double, 8>(reps, "double");
  report_fma<double, 12>(reps, "double");
  report_fma<float, 1>(reps, "float");
  report_fma<float, 4>(reps, "float");
  report_fma<float, 8>(reps, "float");
  report_fma<float, 12>(reps, "float");
  report_call<double>(reps, "double", "sin", [](double x) { return std::sin(x); });
  report_call<double>(reps, "double", "cos", [](double x) { return std::cos(x); });
  report_call<double>(reps, "double", "atan2", [](double x) { return std::atan2(x, 0.7); });
  report_call<double>(reps, "double", "asin", [](double x) { return std::asin(x); });
  report_call<double>(reps, "double", "exp", [](double x) { return std::exp(-x); });
  report_call<double>(reps, "double", "sqrt", [](double x) { return std::sqrt(x); });
  report_call<double>(reps, "double", "divide", [](double x) { return 0.7 / (x + 1.0); });
  report_call<float>(reps, "float", "sin", [](float x) { return std::sin(x); });
  report_call<float>(reps, "float", "cos", [](float x) { return std::cos(x); });
  report_call<float>(reps, "float", "atan2", [](float x) { return std::atan2(x, 0.7f); });
  report_call<float>(reps, "float", "asin", [](float x) { return std::asin(x); });
  report_call<float>(reps, "float", "exp", [](float x) { return std::exp(-x); });
  report_call<float>(reps, "float", "sqrt", [](float x) { return std::sqrt(x); });
  report_call<float>(reps, "float", "divide", [](float x) { return 0.7f / (x + 1.0f); });
  return 0;
}
