// The fuzz target's MargFilter and GpsInsFilter (with and without scale-factor states), float and
// double (fuzz_filters.cpp picks one).
#include "filter_fuzz.hpp"

namespace quatnav_fuzz {
bool fuzz_marg_gpsins(Reader& r, int which, FailFn fail) {
  switch (which) {
    case 0: return run_one<MargFilter<double>>(r, fail);
    case 1: return run_one<MargFilter<float>>(r, fail);
    case 2: return run_one<GpsInsFilter<double>>(r, fail);
    case 3: return run_one<GpsInsFilter<float>>(r, fail);
    case 4: return run_one<GpsInsFilter<double, true>>(r, fail);
    default: return run_one<GpsInsFilter<float, true>>(r, fail);
  }
}
}  // namespace quatnav_fuzz
