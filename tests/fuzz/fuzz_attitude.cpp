// The fuzz target's attitude EKFs, float and double (fuzz_filters.cpp picks one).
#include "filter_fuzz.hpp"

namespace quatnav_fuzz {
bool fuzz_attitude(Reader& r, int which, FailFn fail) {
  switch (which) {
    case 0: return run_one<QuaternionEKF<double>>(r, fail);
    case 1: return run_one<QuaternionEKF<float>>(r, fail);
    case 2: return run_one<QuaternionEKFPaper<double>>(r, fail);
    case 3: return run_one<QuaternionEKFPaper<float>>(r, fail);
    case 4: return run_one<EulerEKF<double>>(r, fail);
    default: return run_one<EulerEKF<float>>(r, fail);
  }
}
}  // namespace quatnav_fuzz
