// libFuzzer target: every filter's step functions under arbitrary input (see filter_fuzz.hpp).
// The first byte picks the family and the next the filter and precision; each family is a unit
// of its own (fuzz_attitude.cpp, fuzz_marg_gpsins.cpp, fuzz_nav13.cpp).
// Build and run: bash tests/fuzz/run.sh [seconds]
#include <cstdio>
#include <cstdlib>

#include "filter_fuzz.hpp"

namespace {
void fail(const std::string& msg) {
  std::fprintf(stderr, "quatnav contract violated: %s\n", msg.c_str());
  std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  quatnav_fuzz::Reader r(data, size);
  const int family = r.byte() % 3;
  const int which = r.byte() % 6;
  switch (family) {
    case 0: quatnav_fuzz::fuzz_attitude(r, which, fail); break;
    case 1: quatnav_fuzz::fuzz_marg_gpsins(r, which, fail); break;
    default: quatnav_fuzz::fuzz_nav13(r, which, fail); break;
  }
  return 0;
}
