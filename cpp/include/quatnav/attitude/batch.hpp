// quatnav: batch runs of the attitude filters over arrays, in C++ (no Python needed).
//
// Inputs are row-major arrays of n samples: gyr (n x 3, rad/s), acc (n x 3), mag (n x 3 or
// null), dt (n, seconds since the previous sample). At each sample: if the filter has no
// attitude yet it is initialized from acc (and mag); otherwise predict(gyr, dt), then
// update_acc(acc), then update_mag(mag). A saturated gyro or accelerometer reading skips its
// step and sets kSaturated (with kPredictSkipped or kAccSkipped). A magnetometer row that is
// entirely NaN means "no sample" (kNoMag). Outputs (any may be null): quat (n x 4), bias (n x 3), sigma
// (n x kStates, sqrt of the covariance diagonal), att_sigma (n x 3, rad, body-frame
// rotation-vector one-sigma: the filter's attitude_variance(), the diagonal of its
// attitude_covariance() without the off-diagonal terms), flags (n, quatnav::flags bits).
// Every sample is reported to `obs` (core/checks.hpp's NoBatchObserver; the smoother's record).
// Allocates nothing.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "../core/checks.hpp"
#include "../core/types.hpp"

namespace quatnav {

template <class Filter, class S = typename Filter::Scalar, class Observer = NoBatchObserver>
void run_attitude_batch(Filter& f, const S* gyr, const S* acc, const S* mag, const S* dt, std::size_t n,
                        S* quat_out, S* bias_out, S* sigma_out, S* att_sigma_out, std::uint32_t* flags_out,
                        Observer&& obs = Observer{}) {
  constexpr int N = Filter::kStates;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Map<const Vec3<S>> g(gyr + 3 * k), a(acc + 3 * k);
    bool have_mag = mag != nullptr;
    if (have_mag) {
      const S* m = mag + 3 * k;
      have_mag = !(std::isnan(m[0]) && std::isnan(m[1]) && std::isnan(m[2]));
    }
    std::uint32_t fl = have_mag ? 0u : flags::kNoMag;
    if (!f.initialized()) {
      const Status s = have_mag ? f.initialize(Vec3<S>(a), Vec3<S>(Eigen::Map<const Vec3<S>>(mag + 3 * k)))
                                : f.initialize(Vec3<S>(a));
      fl |= (s == Status::Ok) ? flags::kInitialized : (flags::kAccSkipped | flags::kPredictSkipped);
    } else {
      const Status sp = f.predict(Vec3<S>(g), dt[k]);
      if (sp != Status::Ok) fl |= flags::kPredictSkipped | (sp == Status::Saturated ? flags::kSaturated : 0u);
      obs.after_predict(k, f);
      fl |= update_flags(f.update_acc(Vec3<S>(a)), flags::kAccSkipped, flags::kAccRejected);
      if (have_mag)
        fl |= update_flags(f.update_mag(Vec3<S>(Eigen::Map<const Vec3<S>>(mag + 3 * k))), flags::kMagSkipped,
                           flags::kMagRejected);
    }
    obs.after_sample(k, f);
    fl |= f.extra_flags();
    if (quat_out) Eigen::Map<Vec4<S>>(quat_out + 4 * k) = f.quat();
    if (bias_out) Eigen::Map<Vec3<S>>(bias_out + 3 * k) = f.bias();
    if (sigma_out)
      Eigen::Map<Vec<S, N>>(sigma_out + N * k) = f.covariance().diagonal().cwiseMax(S(0)).cwiseSqrt();
    if (att_sigma_out)
      Eigen::Map<Vec3<S>>(att_sigma_out + 3 * k) = f.attitude_variance().cwiseMax(S(0)).cwiseSqrt();
    if (flags_out) flags_out[k] = fl;
  }
}

}  // namespace quatnav
