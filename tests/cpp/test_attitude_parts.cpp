// EulerEKF and MargFilter compose the robustness parts (attitude/parts/) as QuaternionEKF does:
// at rest with a biased gyro the bias is learned (EulerEKF: the zero-rate measurement;
// MargFilter: the low-passed gyro), a magnetic disturbance is flagged and does not turn the
// heading, a linear-acceleration burst is rejected; paper() switches the parts off; float and
// double; no heap in a step with the parts on.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>

#include <quatnav/attitude/euler_ekf.hpp>
#include <quatnav/attitude/marg_filter.hpp>

using namespace quatnav;

namespace {

/// A body at rest, level, heading 0 (x magnetic north): gravity and a 60 deg dip field.
template <class S> struct Still {
  Vec3<S> acc{S(0), S(0), S(-9.81)};
  Vec3<S> mag{S(24), S(0), S(41.569)};  // 48 uT, dip 60 deg
};

/// A small deterministic wobble (the same in float and double).
template <class S> Vec3<S> wobble(int k, S a) {
  return Vec3<S>(S(a * std::sin(0.37 * k)), S(a * std::sin(0.91 * k + 1.0)), S(a * std::sin(1.73 * k + 2.0)));
}

template <class S> S yaw_of(const Quat<S>& q) { return quat::to_euler(q)[2]; }
template <class S> S tilt_of(const Quat<S>& q) {
  const Vec3<S> e = quat::to_euler(q);
  return std::sqrt(e[0] * e[0] + e[1] * e[1]);
}

/// One sample of either filter: predict, then the accelerometer (and magnetometer) update;
/// returns the sample's extra flags.
template <class S> std::uint32_t step(EulerEKF<S>& f, const Vec3<S>& g, const Vec3<S>& a, const Vec3<S>* m, S dt) {
  f.predict(g, dt);
  f.update_acc(a);
  if (m) f.update_mag(*m);
  return f.extra_flags();
}
template <class S> std::uint32_t step(MargFilter<S>& f, const Vec3<S>& g, const Vec3<S>& a, const Vec3<S>* m, S dt) {
  f.predict(g, dt);
  if (m) {
    f.update_acc_mag(a, *m);
  } else {
    f.update_acc(a);
  }
  return f.extra_flags();
}

template <class F> F make(bool paper) { return F(paper ? F::Params::paper() : typename F::Params()); }

}  // namespace

template <class F> class AttitudeParts : public ::testing::Test {};
using Filters = ::testing::Types<EulerEKF<float>, EulerEKF<double>, MargFilter<float>, MargFilter<double>>;
TYPED_TEST_SUITE(AttitudeParts, Filters);

TYPED_TEST(AttitudeParts, PaperSwitchesThePartsOff) {
  using F = TypeParam;
  const auto p = F::Params::paper();
  EXPECT_FALSE(p.rest.rest_detection);
  EXPECT_EQ(p.acc.acc_lp_tau, 0);
  EXPECT_EQ(p.acc.acc_reject, 0);
  EXPECT_EQ(p.mag.mag_norm_tol, 0);
  EXPECT_EQ(p.mag.mag_dip_tol, 0);
  const typename F::Params d;
  EXPECT_TRUE(d.rest.rest_detection);
  EXPECT_GT(d.acc.acc_lp_tau, 0);
  EXPECT_GT(d.mag.mag_norm_tol, 0);
}

TYPED_TEST(AttitudeParts, AtRestTheGyroBiasIsLearned) {
  using F = TypeParam;
  using S = typename F::Scalar;
  const Still<S> w;
  const Vec3<S> bias(S(0.01), S(-0.02), S(0.015));
  const S dt = S(0.01);
  for (bool paper : {true, false}) {
    F f = make<F>(paper);
    ASSERT_EQ(f.initialize(w.acc), Status::Ok);
    int rest = 0;
    Eigen::internal::set_is_malloc_allowed(false);
    for (int k = 0; k < 3000; ++k) {
      const std::uint32_t fl = step(f, Vec3<S>(bias + wobble<S>(k, S(0.001))), w.acc, static_cast<const Vec3<S>*>(nullptr), dt);
      rest += (fl & flags::kAtRest) ? 1 : 0;
    }
    Eigen::internal::set_is_malloc_allowed(true);
    if (paper) {
      EXPECT_EQ(rest, 0);
      // Without the magnetometer the z bias is not observed by the accelerometer.
      EXPECT_GT(std::abs(f.bias()[2] - bias[2]), S(0.005));
    } else {
      EXPECT_GT(rest, 2500);
      EXPECT_TRUE(f.at_rest());
      EXPECT_LT((f.bias() - bias).norm(), S(2e-3)) << f.bias().transpose();
    }
  }
}

TYPED_TEST(AttitudeParts, AWrongBiasEstimateDoesNotLockRestOut) {
  // A bias estimate far off (as after fast motion without a heading reference) must not keep
  // rest from being detected: the still gyro reads near zero, so rest is declared and the
  // zero-rate measurement brings the bias back. With the test against the estimate alone the
  // low-passed gyro (0.02 rad/s) stays 0.3 rad/s from the estimate and rest never comes.
  using F = TypeParam;
  using S = typename F::Scalar;
  const Still<S> w;
  const Vec3<S> bias(S(0.01), S(-0.02), S(0.015));
  const S dt = S(0.01);
  F f = make<F>(false);
  ASSERT_EQ(f.initialize(w.acc), Status::Ok);
  auto st = f.state();
  st.gyro_bias = Vec3<S>(S(0.1), S(-0.2), S(0.2));  // 0.3 rad/s off
  ASSERT_EQ(f.set_state(st), Status::Ok);
  int rest = 0;
  for (int k = 0; k < 1500; ++k) {
    const std::uint32_t fl = step(f, Vec3<S>(bias + wobble<S>(k, S(0.001))), w.acc, static_cast<const Vec3<S>*>(nullptr), dt);
    rest += (fl & flags::kAtRest) ? 1 : 0;
  }
  EXPECT_GT(rest, 1000);
  EXPECT_LT((f.bias() - bias).norm(), S(5e-3)) << f.bias().transpose();
}

TYPED_TEST(AttitudeParts, AMagneticDisturbanceIsFlaggedAndDoesNotTurnTheHeading) {
  using F = TypeParam;
  using S = typename F::Scalar;
  const Still<S> w;
  const S dt = S(0.01);
  S yaw_err[2];
  for (bool paper : {true, false}) {
    F f = make<F>(paper);
    ASSERT_EQ(f.initialize(w.acc, w.mag), Status::Ok);
    int flagged = 0;
    for (int k = 0; k < 1500; ++k) {
      const Vec3<S> m = k >= 500 ? Vec3<S>(w.mag + Vec3<S>(S(0), S(20), S(0))) : w.mag;  // a field turned 40 deg
      const std::uint32_t fl = step(f, wobble<S>(k, S(0.001)), w.acc, &m, dt);
      flagged += (k >= 500 && (fl & flags::kMagRejected)) ? 1 : 0;
    }
    yaw_err[paper] = std::abs(yaw_of(f.quat()));
    if (!paper) {
      EXPECT_GT(flagged, 990);
    }
  }
  EXPECT_LT(yaw_err[false], S(0.01));
  EXPECT_GT(yaw_err[true], S(0.2));
}

TYPED_TEST(AttitudeParts, ALinearAccelerationBurstIsRejected) {
  using F = TypeParam;
  using S = typename F::Scalar;
  const Still<S> w;
  const S dt = S(0.01);
  S tilt_err[2];
  for (bool paper : {true, false}) {
    auto p = paper ? F::Params::paper() : typename F::Params();
    if (!paper) {
      p.acc.acc_lp_tau = S(0);  // the rejection alone
      p.acc.acc_reject = S(1);
    }
    F f(p);
    ASSERT_EQ(f.initialize(w.acc, w.mag), Status::Ok);
    int rejected = 0;
    S worst = S(0);
    for (int k = 0; k < 600; ++k) {
      const bool burst = k >= 200 && k < 400;
      const Vec3<S> a = burst ? Vec3<S>(w.acc + Vec3<S>(S(6), S(0), S(0))) : w.acc;  // 6 m/s^2 forward: ||a| - g| = 1.7
      const std::uint32_t fl = step(f, wobble<S>(k, S(0.001)), a, &w.mag, dt);
      rejected += (burst && (fl & flags::kAccRejected)) ? 1 : 0;
      worst = std::max(worst, tilt_of(f.quat()));
    }
    tilt_err[paper] = worst;
    if (!paper) {
      EXPECT_EQ(rejected, 200);
    }
  }
  EXPECT_LT(tilt_err[false], S(0.01));
  EXPECT_GT(tilt_err[true], S(0.1));
}
