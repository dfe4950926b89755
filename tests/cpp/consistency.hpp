// What the C++ consistency tests share with the Python ones (tests/python/_consistency.py): the
// factor c on every variance a filter is told (process noise Q, measurement noise R, initial
// covariance P0), read from QUATNAV_TEST_VARIANCE_SCALE (default 1), and the two-sided
// chi-square interval of a mean NEES per degree of freedom with its power against a covariance
// off by a factor. c = 1/1.5: a filter 1.5x over-confident; c = 1.5: 1.5x under-confident; every
// consistency test must fail at both (python3 tools/mutate.py --consistency runs them so).
#pragma once

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace quatnav_test {

/// The factor c on every variance (QUATNAV_TEST_VARIANCE_SCALE, default 1).
inline double variance_scale() {
  const char* s = std::getenv("QUATNAV_TEST_VARIANCE_SCALE");
  if (!s || !*s) return 1.0;
  const double c = std::strtod(s, nullptr);
  if (!(c > 0.0) || !std::isfinite(c)) throw std::invalid_argument(std::string("QUATNAV_TEST_VARIANCE_SCALE=") + s);
  return c;
}

/// A one-sigma value (or noise density) times sqrt(c).
inline double scaled_sigma(double sigma) { return sigma * std::sqrt(variance_scale()); }

/// Quantile of chi-square(n) / n at the standard normal quantile z, by the Wilson-Hilferty
/// cube (relative error below 1e-3 for n >= 30, the sizes used here).
inline double chi2_mean_quantile(double n, double z) {
  const double a = 2.0 / (9.0 * n);
  const double c = 1.0 - a + z * std::sqrt(a);
  return c * c * c;
}

/// Standard normal quantiles of the two-sided 99 % interval and of the 1 % tail.
constexpr double kZ995 = 2.5758293035489;
constexpr double kZ99 = 2.3263478740408;

/// The two-sided 99 % interval of a mean NEES per degree of freedom over n independent degrees of
/// freedom, and whether it rejects a covariance off by 1.5 (either way) with probability >= 99 %:
/// the over-confident filter's mean is 1.5 X, so its 1 % quantile must lie above hi, the
/// under-confident one's 99 % quantile below lo (n >= 296).
struct Chi2Interval {
  double lo, hi;
  bool powerful;
};
inline Chi2Interval chi2_interval_99(double n, double factor = 1.5) {
  const double lo = chi2_mean_quantile(n, -kZ995), hi = chi2_mean_quantile(n, kZ995);
  const bool p = factor * chi2_mean_quantile(n, -kZ99) > hi && chi2_mean_quantile(n, kZ99) / factor < lo;
  return {lo, hi, p};
}

}  // namespace quatnav_test
