// quatnav_bench_filters: the cases of QuaternionEKFPaper (7 states, paper 000) (bench_cases.hpp).
#include "bench_cases.hpp"

namespace qb {
void run_qekf_cases(const Options& opt) {
  run_case<QEKFCase>(opt);
  run_case<QEKFJointCase>(opt);
  run_case<QEKFPredictCase>(opt);
  run_case<QEKFPredictAccCase>(opt);
  run_case<QEKFNoFloorCase>(opt);
  run_case<QEKFPaperCase>(opt);
}
}  // namespace qb
