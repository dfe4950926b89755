// The robustness parts of the attitude filters, each on its own (attitude/parts/): rest
// detection, the accelerometer part, the magnetometer reference and disturbance tests; float
// and double; no heap in a step.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>

#include <quatnav/attitude/parts/acc_filter.hpp>
#include <quatnav/attitude/parts/mag_disturbance.hpp>
#include <quatnav/attitude/parts/rest.hpp>

#include "same_fields.hpp"

using namespace quatnav;

template <class S> class Parts : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Parts, Scalars);

namespace {
/// A small deterministic wobble in [-a, a] (no random generator: the same in float and double).
template <class S> Vec3<S> wobble(int k, S a) {
  return Vec3<S>(S(a * std::sin(0.37 * k)), S(a * std::sin(0.91 * k + 1.0)), S(a * std::sin(1.73 * k + 2.0)));
}
}  // namespace

// ------------------------------------------------------------------------------------------ rest
TYPED_TEST(Parts, RestIsDeclaredAfterRestTimeAndAgainAfterMotion) {
  using S = TypeParam;
  const RestParams<S> p;  // rest_time 1.5 s
  RestState<S> s;
  const Vec3<S> bias(S(0.01), S(-0.02), S(0.005)), g_b(S(0.1), S(-0.2), S(-9.8));
  const S dt = S(0.01);
  Eigen::internal::set_is_malloc_allowed(false);
  int first_rest = -1;
  for (int k = 0; k < 300; ++k) {
    Rest<S>::predict(p, s, Vec3<S>(bias + wobble<S>(k, S(0.002))), dt);
    const bool rest = Rest<S>::update(p, s, Vec3<S>(g_b + wobble<S>(k + 5, S(0.05))), bias, dt);
    EXPECT_EQ(rest, Rest<S>::at_rest(p, s));
    if (rest && first_rest < 0) first_rest = k;
  }
  Eigen::internal::set_is_malloc_allowed(true);
  // The first sample starts the low-passes; rest_time later (150 steps) rest is declared.
  EXPECT_NEAR(first_rest, 150, 1);
  // A jolt of the accelerometer ends it; rest_time of stillness brings it back.
  Rest<S>::predict(p, s, bias, dt);
  EXPECT_FALSE(Rest<S>::update(p, s, Vec3<S>(g_b + Vec3<S>(S(3), S(0), S(0))), bias, dt));
  EXPECT_EQ(s.rest_t, S(0));
  int back = 0;
  while (back < 1000) {
    Rest<S>::predict(p, s, bias, dt);
    if (Rest<S>::update(p, s, g_b, bias, dt)) break;
    ++back;
  }
  EXPECT_GT(back, 140);
  EXPECT_LT(back, 300);
}

TYPED_TEST(Parts, RestIsNotDeclaredWhileTurningOrWithAWrongBias) {
  using S = TypeParam;
  const RestParams<S> p;
  const Vec3<S> g_b(S(0), S(0), S(-9.81));
  for (const Vec3<S>& rate : {Vec3<S>(S(0), S(0), S(0.2)), Vec3<S>(S(0.05), S(0), S(0))}) {
    RestState<S> s;
    for (int k = 0; k < 500; ++k) {
      Rest<S>::predict(p, s, rate, S(0.01));
      // A steady turn (or a bias estimate 0.05 rad/s off): the low-passed gyro is far from the bias.
      EXPECT_FALSE(Rest<S>::update(p, s, g_b, Vec3<S>::Zero(), S(0.01)));
    }
  }
}

TYPED_TEST(Parts, RestOffLeavesItsStateAndZeroRateVariance) {
  using S = TypeParam;
  RestParams<S> p;
  p.rest_detection = false;
  RestState<S> s;
  const RestState<S> before = s;
  for (int k = 0; k < 300; ++k) {
    Rest<S>::predict(p, s, Vec3<S>::Zero(), S(0.01));
    EXPECT_FALSE(Rest<S>::update(p, s, Vec3<S>(S(0), S(0), S(-9.81)), Vec3<S>::Zero(), S(0.01)));
  }
  EXPECT_TRUE(quatnav_test::same_fields(before, s));
  EXPECT_FALSE(Rest<S>::at_rest(p, s));
  p.rest_rate_noise = S(0.02);
  EXPECT_NEAR(double(Rest<S>::zero_rate_variance(p, S(0.01), S(0.01))), 0.01 * 0.01 / 0.01 + 0.02 * 0.02, 1e-7);
  s.gyr_last = Vec3<S>(S(1), S(2), S(3));
  EXPECT_EQ(Rest<S>::zero_rate_innovation(s, Vec3<S>(S(1), S(1), S(1))), Vec3<S>(S(0), S(1), S(2)));
}

// ---------------------------------------------------------------------------- accelerometer part
TYPED_TEST(Parts, AccLowPassFollowsRotationAndAveragesOutABurst) {
  using S = TypeParam;
  AccFilterParams<S> p;  // acc_lp_tau 3 s
  p.acc_lp_bias_sigma = S(0);
  AccFilterState<S> s;
  const S dt = S(0.01);
  const Vec3<S> g_n(S(0), S(0), S(-9.81)), w(S(0.3), S(-0.2), S(0.5));
  const Quat<S> dq = quat::from_rotvec(Vec3<S>(w * dt));
  Quat<S> q = quat::from_euler(S(0.2), S(-0.1), S(0.4));  // q_nb
  double max_still = 0, max_burst = 0;
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 1000; ++k) {
    if (k > 0) {
      AccFilter<S>::predict(p, s, dq);
      q = quat::normalized(Quat<S>(quat::mul(q, dq)));
    }
    const Vec3<S> f_b = quat::rotate_inv(q, Vec3<S>(-g_n));
    const Vec3<S> burst = (k >= 500 && k < 550) ? Vec3<S>(S(4), S(0), S(0)) : Vec3<S>::Zero();
    const AccSample<S> a = AccFilter<S>::screen(p, s, Vec3<S>(f_b + burst), dt, S(0));
    EXPECT_FALSE(a.rejected);
    const double e = double((a.acc - f_b).norm());
    (k < 500 ? max_still : max_burst) = std::max(k < 500 ? max_still : max_burst, e);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  // Gravity is constant in the gyro-carried frame: while the body turns the output is the sample.
  EXPECT_LT(max_still, 1e-4 * 9.81);
  // A 4 m/s^2 half-second burst is averaged over tau = 3 s: at most 4 (1 - exp(-0.5/3)) = 0.62.
  EXPECT_GT(max_burst, 0.4);
  EXPECT_LT(max_burst, 0.65);
  // Off (acc_lp_tau 0): the sample itself.
  p.acc_lp_tau = S(0);
  const Vec3<S> raw(S(1), S(2), S(-9));
  EXPECT_EQ(AccFilter<S>::screen(p, s, raw, dt, S(0)).acc, raw);
}

TYPED_TEST(Parts, AccTimeConstantFollowsTheBiasVariance) {
  using S = TypeParam;
  AccFilterParams<S> p;  // acc_lp_tau 3, acc_lp_bias_sigma 0.006
  EXPECT_EQ(AccFilter<S>::time_constant(p, S(0)), p.acc_lp_tau);
  EXPECT_EQ(AccFilter<S>::time_constant(p, S(0.006 * 0.006 / 2)), p.acc_lp_tau);
  EXPECT_NEAR(double(AccFilter<S>::time_constant(p, S(4 * 0.006 * 0.006))), 0.75, 1e-6);
  // The shrink fades out with the low-passed linear acceleration (acc_lp_dev 1 m/s^2).
  EXPECT_NEAR(double(AccFilter<S>::time_constant(p, S(4 * 0.006 * 0.006), S(0))), 0.75, 1e-6);
  EXPECT_NEAR(double(AccFilter<S>::time_constant(p, S(4 * 0.006 * 0.006), S(0.5))), 1.875, 1e-5);
  EXPECT_EQ(AccFilter<S>::time_constant(p, S(4 * 0.006 * 0.006), S(2)), p.acc_lp_tau);
  p.acc_lp_dev = S(0);
  EXPECT_NEAR(double(AccFilter<S>::time_constant(p, S(4 * 0.006 * 0.006), S(2))), 0.75, 1e-6);
  p.acc_lp_bias_sigma = S(0);
  EXPECT_EQ(AccFilter<S>::time_constant(p, S(1)), p.acc_lp_tau);
}

TYPED_TEST(Parts, AccBiasWeightGrowsOverTheLowPassFirstTwoTimeConstants) {
  // The low-pass has averaged nothing at its first sample: the bias weight is 0 there, a quarter
  // of I - u u^T after tau / 2, the whole after 2 tau, and stays (the age stops counting).
  using S = TypeParam;
  AccFilterParams<S> p;  // acc_lp_tau 3 s: the ramp ends at 6 s
  AccFilterState<S> s;
  const S dt = S(0.01), g = p.gravity;
  const Vec3<S> f_b(S(0), S(0), -g), u(S(0), S(0), S(1));
  const Mat3<S> full = Mat3<S>::Identity() - u * u.transpose();
  Eigen::internal::set_is_malloc_allowed(false);
  AccFilter<S>::screen(p, s, f_b, dt, S(0));
  EXPECT_LT(double(AccFilter<S>::bias_weight(p, s, u).norm()), 1e-12);
  for (int k = 0; k < 150; ++k) AccFilter<S>::screen(p, s, f_b, dt, S(0));
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, s, u) - full * S(0.25)).norm()), 1e-5);
  for (int k = 0; k < 1000; ++k) AccFilter<S>::screen(p, s, f_b, dt, S(0));
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(s.acc_lp_age, S(2) * p.acc_lp_tau);
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, s, u) - full).norm()), 1e-6);
  AccFilter<S>::restart(s);  // a new start ramps again
  AccFilter<S>::screen(p, s, f_b, dt, S(0));
  EXPECT_LT(double(AccFilter<S>::bias_weight(p, s, u).norm()), 1e-12);
}

TYPED_TEST(Parts, AccBiasWeightFallsWithTheLinearAcceleration) {
  // W times 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a| - g| of the raw
  // samples: a body whose specific force keeps a norm 2 m/s^2 off g gets half the weight with the
  // default 2 m/s^2, one at g the whole.
  using S = TypeParam;
  AccFilterParams<S> p;
  ASSERT_EQ(p.acc_bias_dev, S(2));
  AccFilterState<S> still, moving;
  const S dt = S(0.01), g = p.gravity;
  const Vec3<S> u(S(0), S(0), S(1));
  const Mat3<S> full = Mat3<S>::Identity() - u * u.transpose();
  for (int k = 0; k < 1000; ++k) {  // past the ramp (6 s) and the deviation's low-pass (3 s)
    AccFilter<S>::screen(p, still, Vec3<S>(S(0), S(0), -g), dt, S(0));
    AccFilter<S>::screen(p, moving, Vec3<S>(S(0), S(0), -(g + S(2))), dt, S(0));
  }
  EXPECT_NEAR(double(moving.acc_dev_lp), 2.0, 1e-3);
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, still, u) - full).norm()), 1e-5);
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, moving, u) - full * S(0.5)).norm()), 1e-4);
  p.acc_bias_dev = S(0);  // off: the whole weight whatever the acceleration
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, moving, u) - full).norm()), 1e-5);
  p.acc_bias_dev = S(1);
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, moving, u) - full * S(0.2)).norm()), 1e-4);
}

TYPED_TEST(Parts, AccBiasWeightProjectsOffTheLowPassedVertical) {
  // W projects off the filter's vertical in the low-pass frame, low-passed like C (g_i_lp): a
  // vertical that swings by +-0.3 rad about x at 1 Hz (the filter's tilt error in phase with a
  // swing) averages to the z axis, so W stays I - z z^T (to the average's second order) while the
  // current vertical tilts by 0.3 rad; without a vertical given (a filter that uses no W) the
  // current one is used, as before.
  using S = TypeParam;
  AccFilterParams<S> p;
  p.acc_bias_dev = S(0);
  AccFilterState<S> s, none;
  const S dt = S(0.01), g = p.gravity;
  const Vec3<S> z(S(0), S(0), S(1));
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 1000; ++k) {  // 10 s: past the ramp (6 s)
    const S a = S(0.3 * std::sin(2 * 3.141592653589793 * 0.01 * k));
    const Vec3<S> up(S(0), -std::sin(a), std::cos(a));
    AccFilter<S>::screen(p, s, Vec3<S>(S(0), S(0), -g), dt, S(0), up);
    AccFilter<S>::screen(p, none, Vec3<S>(S(0), S(0), -g), dt, S(0));
  }
  Eigen::internal::set_is_malloc_allowed(true);
  const Mat3<S> Wz = Mat3<S>::Identity() - z * z.transpose();
  EXPECT_GT(double(s.g_i_lp.norm()), 0.9);
  // The low-pass leaves 0.3 / |1 + 2 pi i f tau| = 0.016 rad of the swing (f 1 Hz, tau 3 s):
  // |W - Wz| ~ sqrt(2) 0.016 = 0.023, bound 0.05; W of the current vertical at the swing's peak,
  // 0.3 rad away, differs from Wz by about 0.42.
  const Vec3<S> peak(S(0), -std::sin(S(0.3)), std::cos(S(0.3)));
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, s, peak) - Wz).norm()), 0.05);
  EXPECT_EQ(none.g_i_lp, Vec3<S>::Zero());
  const Mat3<S> Wpeak = Mat3<S>::Identity() - peak * peak.transpose();
  EXPECT_LT(double((AccFilter<S>::bias_weight(p, none, peak) - Wpeak).norm()), 1e-5);
  EXPECT_GT(double((Wpeak - Wz).norm()), 0.3);
}

TYPED_TEST(Parts, AccRejectionAdaptiveNoiseAndRecovery) {
  using S = TypeParam;
  AccFilterParams<S> p;
  p.acc_lp_tau = S(0);
  p.acc_reject = S(1);
  p.acc_adapt = S(2);
  p.acc_recovery_time = S(0.5);
  AccFilterState<S> s;
  const S dt = S(0.01), g = p.gravity;
  // Within the tolerance: used, with the adaptive noise acc_adapt * ||a| - g| / g.
  AccSample<S> a = AccFilter<S>::screen(p, s, Vec3<S>(S(0), S(0), -(g + S(0.5))), dt, S(0));
  EXPECT_FALSE(a.rejected);
  EXPECT_NEAR(double(a.sigma_add), 2 * 0.5 / double(g), 1e-6);
  EXPECT_EQ(a.gate(S(0), S(16)), S(16));
  EXPECT_EQ(a.gate(S(4), S(16)), S(4));
  // 3 m/s^2 off: rejected, and the timer runs for acc_recovery_time ...
  const Vec3<S> off(S(0), S(0), -(g + S(3)));
  int n = 0;
  for (; n < 200; ++n) {
    a = AccFilter<S>::screen(p, s, off, dt, S(0));
    if (!a.rejected) break;
    AccFilter<S>::finish(p, s, Status::Rejected, dt);
  }
  EXPECT_NEAR(n, 50, 1);
  // ... then the samples are accepted again, without the default gate.
  EXPECT_TRUE(a.recovering);
  EXPECT_EQ(a.gate(S(0), S(16)), S(0));
  AccFilter<S>::finish(p, s, Status::Ok, dt);
  EXPECT_EQ(s.acc_reject_t, S(0));
  EXPECT_TRUE(AccFilter<S>::screen(p, s, off, dt, S(0)).rejected);
  // Without a recovery time the timer does not run: rejected for ever.
  p.acc_recovery_time = S(0);
  AccFilter<S>::finish(p, s, Status::Rejected, dt);
  EXPECT_EQ(s.acc_reject_t, S(0));
}

// ---------------------------------------------------------------------------- magnetometer part
namespace {
template <class S> Vec3<S> field(S dip) { return Vec3<S>(std::cos(dip), S(0), std::sin(dip)); }
}  // namespace

TYPED_TEST(Parts, MagReferenceIsLearnedAndKeptWhenASampleIsNotUsed) {
  using S = TypeParam;
  MagDisturbanceParams<S> p;
  p.mag_ref_samples = 4;
  p.mag_ref_tau = S(0);
  MagDisturbanceState<S> s;
  MagDisturbance<S>::start(p, s, field<S>(S(1.0)), S(50));
  const S dt = S(0.01);
  for (int k = 0; k < 3; ++k) {
    const MagSample<S> c = MagDisturbance<S>::screen(p, s, S(50), field<S>(S(1.02)), dt);
    ASSERT_TRUE(c.use);
    MagDisturbance<S>::finish(p, s, c, Status::Ok, [] { return field<S>(S(1.02)); }, dt);
  }
  EXPECT_EQ(s.ref.mag_ref_count, 4u);
  const double sd = (std::sin(1.0) + 3 * std::sin(1.02)) / 4;
  EXPECT_NEAR(double(s.ref.mag_ref[2]), sd, 1e-6);
  // A full reference is not learned further (mag_ref_tau 0).
  const MagRef<S> full = s.ref;
  MagSample<S> c = MagDisturbance<S>::screen(p, s, S(50), field<S>(S(1.0)), dt);
  ASSERT_TRUE(c.use);
  MagDisturbance<S>::finish(p, s, c, Status::Ok, [] { return field<S>(S(1.0)); }, dt);
  EXPECT_TRUE(quatnav_test::same_fields(full, s.ref));
  // While learning, a sample the filter refuses (its gate) leaves the reference as it was.
  MagDisturbanceState<S> t;
  MagDisturbance<S>::start(p, t, field<S>(S(1.0)), S(50));
  const MagRef<S> before = t.ref;
  c = MagDisturbance<S>::screen(p, t, S(50), field<S>(S(1.04)), dt);
  EXPECT_EQ(t.ref.mag_ref_count, 2u);  // learned tentatively
  MagDisturbance<S>::finish(p, t, c, Status::Rejected, [] { return field<S>(S(1.04)); }, dt);
  EXPECT_TRUE(quatnav_test::same_fields(before, t.ref));
}

TYPED_TEST(Parts, MagDisturbanceTestsSettlingAndRecovery) {
  using S = TypeParam;
  MagDisturbanceParams<S> p;  // mag_norm_tol 0.05, mag_dip_tol 0.05 rad
  p.mag_ref_samples = 1;
  p.mag_ref_tau = S(0);
  p.mag_settle_time = S(0.2);
  p.mag_recovery_time = S(1);
  MagDisturbanceState<S> s;
  const S dip = S(1.0), dt = S(0.01);
  MagDisturbance<S>::start(p, s, field<S>(dip), S(50));
  auto step = [&](S norm, S d) {
    const MagSample<S> c = MagDisturbance<S>::screen(p, s, norm, field<S>(d), dt);
    if (c.use) MagDisturbance<S>::finish(p, s, c, Status::Ok, [d] { return field<S>(d); }, dt);
    return c;
  };
  EXPECT_TRUE(step(S(50.5), dip).use);
  EXPECT_FALSE(step(S(56), dip).use);         // norm 12 % off
  EXPECT_FALSE(step(S(50), dip + S(0.1)).use);  // dip 0.1 rad off
  // After the disturbance: 0.2 s of clean samples before the field is used again.
  int settle = 0;
  while (!step(S(50), dip).use) ++settle;
  EXPECT_NEAR(settle, 20, 1);
  EXPECT_EQ(s.mag_reject_t, S(0));
  // A steady new field (another building): after mag_recovery_time it becomes the reference.
  int n = 0;
  while (!step(S(70), dip + S(0.2)).use && n < 1000) ++n;
  EXPECT_NEAR(n, 100, 1);
  EXPECT_EQ(s.mag_norm_ref, S(70));
  EXPECT_NEAR(double(std::asin(s.ref.mag_ref[2])), double(dip + S(0.2)), 1e-5);
}

// The dip test and the reference's learning work on the unit vectors (no asin, atan2 or sincos of
// the dips): against the angles, for random dips and fields.
TYPED_TEST(Parts, MagDipTestAndLearningAreThoseOfTheAngles) {
  using S = TypeParam;
  const double tol_num = std::is_same<S, float>::value ? 2e-6 : 1e-13;
  std::mt19937 g(11);
  std::uniform_real_distribution<double> dip_d(-1.45, 1.45), off(-0.3, 0.3), az(-3.1, 3.1), tol_d(0.01, 1.0);
  int differs = 0;
  for (int k = 0; k < 2000; ++k) {
    const double d_ref = dip_d(g), d = std::max(-1.5, std::min(1.5, d_ref + off(g))), a = az(g);
    const Vec3<S> ref = field<S>(S(d_ref));
    const Vec3<S> m(S(std::cos(d) * std::cos(a)), S(std::cos(d) * std::sin(a)), S(std::sin(d)));
    const double tol = tol_d(g);
    const double true_off = std::asin(double(m[2])) - std::atan2(double(ref[2]), double(ref[0]));
    if (std::abs(std::abs(true_off) - tol) > 10 * tol_num) {
      EXPECT_EQ(MagDisturbance<S>::dip_differs(ref, m, S(tol)), std::abs(true_off) > tol) << k;
    }
    differs += MagDisturbance<S>::dip_differs(ref, m, S(tol));
    // One learning step: the reference's dip moves by lowpass_gain * (d - d_ref) and stays a unit vector.
    MagDisturbanceParams<S> p;
    p.mag_ref_samples = 1;
    p.mag_ref_tau = S(0.5);
    p.mag_norm_tol = p.mag_dip_tol = S(0);
    MagDisturbanceState<S> s;
    s.ref.mag_ref = ref;
    s.ref.mag_ref_count = 1;
    s.mag_norm_ref = S(50);
    const S dt = S(0.01);
    const MagSample<S> c = MagDisturbance<S>::screen(p, s, S(50), m, dt);
    ASSERT_TRUE(c.use);
    MagDisturbance<S>::finish(p, s, c, Status::Ok, [&] { return m; }, dt);
    const double w = 0.01 / 0.51;
    EXPECT_NEAR(std::atan2(double(s.ref.mag_ref[2]), double(s.ref.mag_ref[0])), d_ref + w * true_off, tol_num) << k;
    EXPECT_NEAR(double(s.ref.mag_ref.norm()), 1.0, tol_num) << k;
    EXPECT_EQ(s.ref.mag_ref[1], S(0));
  }
  EXPECT_GT(differs, 200);
  EXPECT_LT(differs, 1800);
}

// A field that became the reference by recovery is learned from, not from the reference it replaced.
TYPED_TEST(Parts, MagRecoveryKeepsTheNewReferenceWhileLearning) {
  using S = TypeParam;
  MagDisturbanceParams<S> p;
  p.mag_ref_samples = 1;
  p.mag_ref_tau = S(1);
  p.mag_recovery_time = S(0.5);
  MagDisturbanceState<S> s;
  MagDisturbance<S>::start(p, s, field<S>(S(1.0)), S(50));
  const S dt = S(0.01);
  int used = 0;
  for (int k = 0; k < 200; ++k) {
    const MagSample<S> c = MagDisturbance<S>::screen(p, s, S(50), field<S>(S(1.2)), dt);
    if (c.use) {
      ++used;
      MagDisturbance<S>::finish(p, s, c, Status::Ok, [] { return field<S>(S(1.2)); }, dt);
    }
  }
  EXPECT_GE(used, 140);  // every sample after the recovery (0.5 s)
  EXPECT_NEAR(double(std::asin(s.ref.mag_ref[2])), 1.2, 1e-5);
}

TYPED_TEST(Parts, MagReferenceFollowsTheFieldWithMagRefTau) {
  using S = TypeParam;
  MagDisturbanceParams<S> p;
  p.mag_ref_samples = 1;
  p.mag_ref_tau = S(1);
  p.mag_norm_tol = p.mag_dip_tol = S(0);
  MagDisturbanceState<S> s;
  MagDisturbance<S>::start(p, s, field<S>(S(1.0)), S(50));
  const S dt = S(0.01);
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 100; ++k) {  // 1 s = one time constant
    const MagSample<S> c = MagDisturbance<S>::screen(p, s, S(60), field<S>(S(1.1)), dt);
    MagDisturbance<S>::finish(p, s, c, Status::Ok, [] { return field<S>(S(1.1)); }, dt);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  const double a = 1 - std::pow(1 - 0.01 / 1.01, 100);  // the discrete low-pass over 100 steps
  EXPECT_NEAR(double(s.mag_norm_ref), 50 + 10 * a, 1e-3);
  EXPECT_NEAR(double(std::asin(s.ref.mag_ref[2])), 1.0 + 0.1 * a, 1e-4);
  // A user-fixed dip is not learned; the norm still is.
  s.ref.fix(S(0.5));
  const MagSample<S> c = MagDisturbance<S>::screen(p, s, S(60), field<S>(S(1.1)), dt);
  MagDisturbance<S>::finish(p, s, c, Status::Ok, [] { return field<S>(S(1.1)); }, dt);
  EXPECT_EQ(s.ref.mag_ref, field<S>(S(0.5)));
}

// The dip's variance from the attitude covariance (dip_variance): its direction a_b against finite
// differences of the dip of the field rotated by q exp(dtheta), and its null direction (a rotation
// about the field's horizontal direction keeps the dip).
TYPED_TEST(Parts, MagDipVarianceIsTheDipsFirstOrderVariance) {
  using S = TypeParam;
  MagDisturbanceParams<S> p;  // mag_dip_tol 0.05
  p.mag_dip_sigmas = S(3);
  const double dip = 1.1;
  const Vec3<S> m_n0(S(std::cos(dip)), S(0), S(std::sin(dip)));  // magnetic north frame
  const Quat<S> q = quat::from_euler(Vec3<S>(S(0.3), S(-0.2), S(2.0)));
  const Mat3<S> C = quat::to_rotmat(q);
  const Vec3<S> m_b = C.transpose() * m_n0;  // the body-frame field at q
  Eigen::internal::set_is_malloc_allowed(false);
  // P = e_i e_i^T: the variance is a_b,i^2; the finite difference of the dip along e_i gives a_b,i.
  constexpr bool kFloat = std::is_same_v<S, float>;
  const double h = kFloat ? 1e-3 : 1e-6;
  for (int i = 0; i < 3; ++i) {
    Mat3<S> P = Mat3<S>::Zero();
    P(i, i) = S(1);
    const S var = MagDisturbance<S>::dip_variance(p, C, m_n0, P);
    Vec3<S> d = Vec3<S>::Zero();
    d[i] = S(h);
    const Vec3<S> mp = quat::rotate(quat::mul(q, quat::from_rotvec(d)), m_b);
    const Vec3<S> mm = quat::rotate(quat::mul(q, quat::from_rotvec(Vec3<S>(-d))), m_b);
    const double slope = (std::asin(double(mp[2])) - std::asin(double(mm[2]))) / (2 * h);
    EXPECT_NEAR(double(var), slope * slope, kFloat ? 2e-3 : 1e-8) << i;
  }
  // Isotropic P = s^2 I: s^2 (a_b is a unit vector); P along the field's horizontal direction: 0.
  EXPECT_NEAR(double(MagDisturbance<S>::dip_variance(p, C, m_n0, Mat3<S>::Identity() * S(4e-4))), 4e-4, 1e-9);
  const Vec3<S> along = C.transpose() * Vec3<S>(S(1), S(0), S(0));
  EXPECT_NEAR(double(MagDisturbance<S>::dip_variance(p, C, m_n0, Mat3<S>(along * along.transpose()))), 0.0, 1e-7);
  // Off (mag_dip_sigmas 0 or mag_dip_tol 0), or a vertical field: 0.
  MagDisturbanceParams<S> off = p;
  off.mag_dip_sigmas = S(0);
  EXPECT_EQ(MagDisturbance<S>::dip_variance(off, C, m_n0, Mat3<S>::Identity()), S(0));
  EXPECT_EQ(MagDisturbance<S>::dip_variance(p, C, Vec3<S>(S(0), S(0), S(1)), Mat3<S>::Identity()), S(0));
  Eigen::internal::set_is_malloc_allowed(true);
}

// The dip test's tolerance: a field whose dip at the estimated attitude is 0.1 rad off (a tilt
// error of 0.1 rad about the dip's axis) is rejected by the fixed 0.05 rad tolerance; with the
// filter's own dip sigma of 0.04 rad and mag_dip_sigmas 3 the tolerance is sqrt(0.05^2 + 0.12^2)
// = 0.13 rad and it is used; a 0.2 rad disturbance is still rejected at that sigma.
TYPED_TEST(Parts, MagDipToleranceGrowsWithTheFiltersDipSigma) {
  using S = TypeParam;
  MagDisturbanceParams<S> p;
  EXPECT_EQ(p.mag_dip_sigmas, S(0));  // off by default: the fixed tolerance
  p.mag_dip_sigmas = S(3);
  p.mag_ref_samples = 1;
  p.mag_ref_tau = S(0);
  const S dip = S(1.0), dt = S(0.01), var = S(0.04 * 0.04);
  EXPECT_NEAR(double(MagDisturbance<S>::dip_tolerance(p, var)), std::sqrt(0.05 * 0.05 + 9 * 0.04 * 0.04), 1e-6);
  EXPECT_EQ(MagDisturbance<S>::dip_tolerance(p, S(0)), p.mag_dip_tol);
  auto used = [&](const MagDisturbanceParams<S>& pp, S d, S v) {
    MagDisturbanceState<S> s;
    MagDisturbance<S>::start(pp, s, field<S>(dip), S(50));
    return MagDisturbance<S>::screen(pp, s, S(50), field<S>(d), dt, v).use;
  };
  EXPECT_FALSE(used(p, dip + S(0.1), S(0)));
  EXPECT_TRUE(used(p, dip + S(0.1), var));
  EXPECT_FALSE(used(p, dip + S(0.2), var));
  MagDisturbanceParams<S> fixed = p;
  fixed.mag_dip_sigmas = S(0);
  EXPECT_FALSE(used(fixed, dip + S(0.1), var));
}
