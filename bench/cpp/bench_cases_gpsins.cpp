// quatnav_bench_filters: the cases of GpsInsFilter (bench_cases.hpp).
#include "bench_cases.hpp"

namespace qb {
void run_gpsins_cases(const Options& opt) {
  run_case<GpsInsCase>(opt);
  run_case<GpsInsGnssCase>(opt);
  run_case<GpsInsScaleCase>(opt);
  run_case<GpsInsScaleGnssCase>(opt);
}
}  // namespace qb
