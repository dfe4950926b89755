// quatnav_bench_filters: the cases of NavFilter13, EKF and second-order time updates (bench_cases.hpp).
#include "bench_cases.hpp"

namespace qb {
void run_nav13_cases(const Options& opt) {
  run_case<Nav13EkfCase>(opt);
  run_case<Nav13SecondOrderCase>(opt);
}
}  // namespace qb
