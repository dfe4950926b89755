// Robustness options of QuaternionEKFPaper: no heap in any step with every option on, bad input
// leaves the state untouched, the heading-only magnetometer update never tilts, rest flags;
// the clipped-gyro part (parts/gyro_clip.hpp) of both quaternion EKFs.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include <quatnav/attitude/batch.hpp>
#include <quatnav/attitude/quaternion_ekf.hpp>
#include <quatnav/attitude/quaternion_ekf_paper.hpp>

#include "same_fields.hpp"

using namespace quatnav;

template <class S> class QekfRobust : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(QekfRobust, Scalars);

namespace {
template <class S> QuaternionEKFParams<S> all_on() {
  QuaternionEKFParams<S> p;  // defaults: heading-only, low-pass, norm/dip tests, gate, rest
  p.acc.acc_adapt = S(3);
  p.acc.acc_reject = S(2);
  p.acc_gate = S(30);
  p.acc.acc_recovery_time = S(1);
  p.mag.mag_settle_time = S(0.2);
  p.mag.mag_recovery_time = S(2);
  return p;
}

template <class S> void samples(int k, const Quat<S>& q, Vec3<S>& acc, Vec3<S>& mag) {
  const Vec3<S> g_n(S(0), S(0), S(-9.81));
  const Vec3<S> m_n(S(20), S(0), S(40));
  acc = quat::rotate_inv(q, g_n);
  mag = quat::rotate_inv(q, m_n);
  if (k > 300 && k < 360) acc += Vec3<S>(S(4), S(0), S(0));  // linear acceleration burst
  if (k > 400 && k < 460) mag += Vec3<S>(S(25), S(-10), S(0));  // magnetic disturbance
}
}  // namespace

TYPED_TEST(QekfRobust, NoHeapInAnyStepWithEveryOption) {
  using S = TypeParam;
  QuaternionEKFPaper<S> f(all_on<S>());
  Quat<S> q = quat::from_euler<S>(S(0.1), S(-0.2), S(0.5));
  Vec3<S> acc, mag;
  samples<S>(0, q, acc, mag);
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  std::uint32_t seen = 0;
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 1; k < 600; ++k) {
    const Vec3<S> w = k < 250 ? Vec3<S>::Zero() : Vec3<S>(S(0.2), S(-0.1), S(0.3));
    q = quat::mul(q, quat::from_rotvec<S>(Vec3<S>(w * S(0.01))));
    samples<S>(k, q, acc, mag);
    f.predict(w, S(0.01));
    f.update_acc(acc);
    f.update_mag(mag);
    seen |= f.extra_flags();
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(seen & flags::kAtRest);
  EXPECT_TRUE(seen & flags::kMagRejected);
  EXPECT_TRUE(f.quat().allFinite());
}

TYPED_TEST(QekfRobust, BatchRunNoHeap) {
  using S = TypeParam;
  constexpr int n = 400;
  static S gyr[3 * n], acc[3 * n], mag[3 * n], dt[n], qo[4 * n];
  static std::uint32_t fl[n];
  Quat<S> q = quat::identity<S>();
  for (int k = 0; k < n; ++k) {
    const Vec3<S> w = k < 200 ? Vec3<S>::Zero() : Vec3<S>(S(0.1), S(0), S(0.2));
    q = quat::mul(q, quat::from_rotvec<S>(Vec3<S>(w * S(0.01))));
    Vec3<S> a, m;
    samples<S>(k, q, a, m);
    for (int i = 0; i < 3; ++i) {
      gyr[3 * k + i] = w[i];
      acc[3 * k + i] = a[i];
      mag[3 * k + i] = m[i];
    }
    dt[k] = S(0.01);
  }
  QuaternionEKFPaper<S> f;
  Eigen::internal::set_is_malloc_allowed(false);
  run_attitude_batch(f, gyr, acc, mag, dt, n, qo, static_cast<S*>(nullptr), static_cast<S*>(nullptr),
                     static_cast<S*>(nullptr), fl);
  Eigen::internal::set_is_malloc_allowed(true);
  bool rest = false;
  for (int k = 0; k < n; ++k) rest = rest || (fl[k] & flags::kAtRest);
  EXPECT_TRUE(rest);
}

TYPED_TEST(QekfRobust, BadInputLeavesStateUntouched) {
  using S = TypeParam;
  QuaternionEKFPaper<S> f(all_on<S>());
  Quat<S> q = quat::from_euler<S>(S(0.1), S(-0.2), S(0.5));
  Vec3<S> acc, mag;
  samples<S>(0, q, acc, mag);
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  for (int k = 1; k < 50; ++k) {
    f.predict(Vec3<S>::Zero(), S(0.01));
    f.update_acc(acc);
    f.update_mag(mag);
  }
  const auto before = f.state();
  const S nan = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(f.predict(Vec3<S>(nan, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(Vec3<S>::Zero(), S(-1)), Status::InvalidDt);
  EXPECT_EQ(f.update_acc(Vec3<S>(S(0), nan, S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_acc(Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_mag(Vec3<S>(nan, S(0), S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_mag(Vec3<S>::Zero()).status, Status::ZeroNorm);
  const auto after = f.state();
  EXPECT_TRUE(quatnav_test::same_fields(before, after));
}

TYPED_TEST(QekfRobust, HeadingOnlyMagnetometerNeverTilts) {
  using S = TypeParam;
  auto p = QuaternionEKFParams<S>::paper();
  p.mag_heading_only = true;
  QuaternionEKFPaper<S> f(p);
  const Quat<S> q = quat::from_euler<S>(S(0.3), S(-0.2), S(1.0));
  Vec3<S> acc, mag;
  samples<S>(0, q, acc, mag);
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  const Vec3<S> down = quat::rotate_inv(f.quat(), Vec3<S>(S(0), S(0), S(1)));
  const Vec3<S> bad = quat::rotate(quat::from_rotvec<S>(Vec3<S>(S(0.2), S(0.3), S(0.1))), mag);
  const auto r = f.update_mag(bad);
  ASSERT_EQ(r.status, Status::Ok);
  EXPECT_GT(std::abs(r.innovation[0]), S(0.05));
  const Vec3<S> down2 = quat::rotate_inv(f.quat(), Vec3<S>(S(0), S(0), S(1)));
  EXPECT_LT((down2 - down).norm(), sizeof(S) == 4 ? 1e-5 : 1e-12);
}

TYPED_TEST(QekfRobust, DisturbedFieldRejectedAndFlagged) {
  using S = TypeParam;
  QuaternionEKFPaper<S> f;  // defaults: norm tolerance 5 %
  const Quat<S> q = quat::identity<S>();
  Vec3<S> acc, mag;
  samples<S>(0, q, acc, mag);
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  f.predict(Vec3<S>::Zero(), S(0.01));
  EXPECT_EQ(f.update_mag(Vec3<S>(mag * S(1.3))).status, Status::Rejected);
  EXPECT_TRUE(f.extra_flags() & flags::kMagRejected);
  f.predict(Vec3<S>::Zero(), S(0.01));
  EXPECT_EQ(f.update_mag(mag).status, Status::Ok);
  EXPECT_FALSE(f.extra_flags() & flags::kMagRejected);
}

// ---- clipped gyro readings (parts/gyro_clip.hpp) --------------------------------------------
TEST(GyroClip, RecognizesAnAxisStuckAtTheLargestMagnitude) {
  GyroClipParams<double> p;  // min rate 1 rad/s, two repeats
  GyroClipState<double> s;
  const double dt = 0.005;
  const auto clipped = [&](double x, double y, double z) {
    return GyroClip<double>::step(p, s, Vec3<double>(x, y, z), dt);
  };
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(clipped(0.5, 0.5, 0.5).isZero());  // repeated, below the min rate
  EXPECT_TRUE(clipped(8.0, -3.0, 0.0).isZero());  // a new largest value
  EXPECT_TRUE(clipped(8.0, -3.0, 0.1).isZero());  // x repeats once
  const Vec3<double> v = clipped(8.0, -3.0, 0.2);  // x twice, at the largest: clipped
  EXPECT_DOUBLE_EQ(v[0], std::pow(p.gyro_clip_noise * 8.0 * dt, 2));
  EXPECT_EQ(v[1], 0.0);  // -3 repeats twice too, below the largest
  EXPECT_EQ(v[2], 0.0);
  EXPECT_TRUE(clipped(7.0, -3.0, 0.2).isZero());
  EXPECT_TRUE(clipped(-8.0, 1.0, 0.2).isZero());  // the negative extreme, not yet repeated
  EXPECT_TRUE(clipped(-8.0, 1.0, 0.2).isZero());
  EXPECT_GT(clipped(-8.0, 1.0, 0.2)[0], 0.0);
  GyroClip<double>::off(p);
  EXPECT_TRUE(clipped(-8.0, 1.0, 0.2).isZero());
}

/// A roll flip of 360 deg peaking at 700 deg/s read by a gyro that clips at 500 deg/s, then rest,
/// gravity only: the clipped steps turn the attitude by less than the body turned. Recognized
/// (the default), the filter distrusts those steps and restarts the accelerometer's low-pass, so
/// the tilt is back within a degree 2 s after the flip; without (gyro_clip = false) the low-pass
/// frame, carried by the clipped rate, holds the wrong vertical and the error stays for seconds.
template <class F> double tilt_error_after_flip_deg(const typename F::Params& p) {
  const double pi = 3.14159265358979323846, dt = 0.005, range = 500.0 * pi / 180.0, peak = 700.0 * pi / 180.0;
  const double T = 2.0 * 2.0 * pi / peak;  // a raised-cosine rate of mean peak / 2 turns 2 pi
  F f(p);
  Quat<double> q_true = quat::identity<double>();
  const Vec3<double> g_n(0.0, 0.0, -9.81);
  f.initialize(Vec3<double>(g_n));
  double worst_after = 0.0;
  for (int k = 0; k < static_cast<int>(6.0 / dt); ++k) {
    const double t = k * dt - 2.0;  // 2 s at rest, the flip, then rest
    const double w = (t > 0.0 && t < T) ? 0.5 * peak * (1.0 - std::cos(2.0 * pi * t / T)) : 0.0;
    q_true = quat::mul(q_true, quat::from_rotvec(Vec3<double>(w * dt, 0.0, 0.0)));
    const Vec3<double> gyr(std::min(w, range), 0.0, 0.0);
    f.predict(gyr, dt);
    f.update_acc(quat::rotate_inv(q_true, g_n));
    if (t > T + 2.0) {
      const Vec3<double> up_est = quat::rotate_inv(f.quat(), Vec3<double>(0, 0, 1));
      const Vec3<double> up_true = quat::rotate_inv(q_true, Vec3<double>(0, 0, 1));
      worst_after = std::max(worst_after, std::acos(std::min(1.0, up_est.dot(up_true))) * 180.0 / pi);
    }
  }
  return worst_after;
}

TEST(GyroClip, TheQuaternionEKFsTakeTheTiltBackAfterAClippedFlip) {
  for (const bool paper_form : {false, true}) {
    QuaternionEKFParams<double> on, off;
    off.clip.gyro_clip = false;
    const double e_on = paper_form ? tilt_error_after_flip_deg<QuaternionEKFPaper<double>>(on)
                                   : tilt_error_after_flip_deg<QuaternionEKF<double>>(on);
    const double e_off = paper_form ? tilt_error_after_flip_deg<QuaternionEKFPaper<double>>(off)
                                    : tilt_error_after_flip_deg<QuaternionEKF<double>>(off);
    std::printf("paper form %d: tilt error 2-4 s after the flip %.3f deg recognized, %.3f deg not\n", paper_form, e_on,
                e_off);
    EXPECT_LT(e_on, 1.0) << paper_form;
    EXPECT_GT(e_off, 3.0 * e_on + 2.0) << paper_form;
  }
}
