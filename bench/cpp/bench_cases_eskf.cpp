// quatnav_bench_filters: the cases of QuaternionEKF (the default) (bench_cases.hpp).
#include "bench_cases.hpp"

namespace qb {
void run_eskf_cases(const Options& opt) {
  run_case<ESKFCase>(opt);
  run_case<ESKFPredictCase>(opt);
  run_case<ESKFPredictAccCase>(opt);
  run_case<ESKFPaperCase>(opt);
}
}  // namespace qb
