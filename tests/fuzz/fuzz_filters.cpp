// libFuzzer target: every filter's step functions under arbitrary input (see filter_fuzz.hpp).
// Build and run: bash tests/fuzz/run.sh [seconds]
#include <cstdio>
#include <cstdlib>

#include "filter_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  quatnav_fuzz::fuzz_all(data, size, [](const std::string& msg) {
    std::fprintf(stderr, "quatnav contract violated: %s\n", msg.c_str());
    std::abort();
  });
  return 0;
}
