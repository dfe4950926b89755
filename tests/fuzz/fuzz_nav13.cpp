// The fuzz target's NavFilter13 with each of its three time updates, float and double
// (fuzz_filters.cpp picks one).
#include "filter_fuzz.hpp"

namespace quatnav_fuzz {
bool fuzz_nav13(Reader& r, int which, FailFn fail) {
  switch (which) {
    case 0: return run_one<NavFilter13<double, TimeUpdate::Ekf>>(r, fail);
    case 1: return run_one<NavFilter13<float, TimeUpdate::Ekf>>(r, fail);
    case 2: return run_one<NavFilter13<double, TimeUpdate::SecondOrder>>(r, fail);
    case 3: return run_one<NavFilter13<float, TimeUpdate::SecondOrder>>(r, fail);
    case 4: return run_one<NavFilter13<double, TimeUpdate::Ukf>>(r, fail);
    default: return run_one<NavFilter13<float, TimeUpdate::Ukf>>(r, fail);
  }
}
}  // namespace quatnav_fuzz
