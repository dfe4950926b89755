// quatnav_bench_filters: the cases of EulerEKF and MargFilter (bench_cases.hpp).
#include "bench_cases.hpp"

namespace qb {
void run_euler_marg_cases(const Options& opt) {
  run_case<EulerEKFCase>(opt);
  run_case<MargCase>(opt);
}
}  // namespace qb
