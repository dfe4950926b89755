// Robustness options of QuaternionEKFPaper: no heap in any step with every option on, bad input
// leaves the state untouched, the heading-only magnetometer update never tilts, rest flags.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include <quatnav/attitude/batch.hpp>
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
