// quatnav_bench_filters: the cases of NavFilter13, unscented time update (bench_cases.hpp).
#include "bench_cases.hpp"

namespace qb {
void run_nav13_ukf_cases(const Options& opt) {
  run_case<Nav13UkfCase>(opt);
}
}  // namespace qb
