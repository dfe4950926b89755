// GpsInsFilter gate-lockout recovery: after gps_reset_after consecutive gate rejections the next
// rejected GPS position (velocity) resets the position (velocity) to the fix with the fix's
// covariance block; without it (gps_reset_after = 0) the filter rejects every later fix for good.
// No heap in any step; float and double.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/nav/gps_ins.hpp>

using namespace quatnav;

namespace {

constexpr double kLat = 0.7, kLon = -1.8, kH = 1600.0;

// A filter navigating at rest at (kLat, kLon, kH), fed with consistent fixes for a while.
template <class S> GpsInsFilter<S> navigating(S reset_after) {
  GpsInsParams<S> p;
  p.gps_reset_after = reset_after;
  GpsInsFilter<S> f(p);
  Mat<S, 15, 15> P = f.initial_covariance(Vec3<S>(S(0.05), S(0.05), S(0.1)), S(0.05));
  EXPECT_EQ(f.reset(Quat<S>(S(1), S(0), S(0), S(0)), Vec3<S>::Zero(), kLat, kLon, kH, Vec3<S>::Zero(),
                         Vec3<S>::Zero(), P),
            Status::Ok);
  const Vec3<S> g_b(S(0), S(0), S(-earth::gravity<double>(kLat, kH)));
  const Vec3<S> w_b = (quat::to_rotmat(Quat<S>(S(1), S(0), S(0), S(0))).transpose() *
                       earth::earth_rate_n<double>(kLat).template cast<S>());
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03)), vsig(S(0.05), S(0.05), S(0.05));
  for (int k = 0; k < 200; ++k) {
    EXPECT_EQ(f.predict(w_b, g_b, S(0.01)), Status::Ok);
    if (k % 25 == 0) f.update_gps(kLat, kLon, kH, Vec3<S>::Zero(), sig, vsig);
  }
  return f;
}

}  // namespace

template <class S> class GpsInsResetTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(GpsInsResetTest, Scalars);

TYPED_TEST(GpsInsResetTest, PositionResetAfterConsecutiveRejections) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(3));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 100.0 / 6.37e6;  // the fixes jump ~100 m north
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 3; ++k) {
    const GpsInsState<S> before = f.state();
    const UpdateResult<S, 3> r = f.update_gps_position(lat2, kLon, kH, sig);
    EXPECT_EQ(r.status, Status::Rejected);
    // A rejection (no reset yet) changes nothing but the counters.
    EXPECT_EQ(f.state().nav.lat, before.nav.lat);
    EXPECT_TRUE((f.state().P.array() == before.P.array()).all());
    EXPECT_EQ(f.state().counters.resets[0], 0u);
  }
  const UpdateResult<S, 3> r = f.update_gps_position(lat2, kLon, kH, sig);  // 4th rejection: reset
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(r.status, Status::Rejected);
  EXPECT_EQ(f.state().counters.resets[0], 1u);
  EXPECT_NEAR(f.state().nav.lat, lat2, 1e-10);
  EXPECT_NEAR(f.state().nav.h, kH, 1e-6);
  const auto& P = f.state().P;
  EXPECT_NEAR(double(P(0, 0)), 0.02 * 0.02, 1e-9);
  EXPECT_NEAR(double(P(2, 2)), 0.03 * 0.03, 1e-9);
  EXPECT_EQ(double(P(0, 3)), 0.0);
  EXPECT_EQ(double(P(6, 1)), 0.0);
  // The next fix at the new place is accepted.
  EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).status, Status::Ok);
}

TYPED_TEST(GpsInsResetTest, VelocityResetAfterConsecutiveRejections) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(2));
  const Vec3<S> v(S(3), S(-1), S(0)), vsig(S(0.05), S(0.05), S(0.05));
  for (int k = 0; k < 2; ++k) EXPECT_EQ(f.update_gps_velocity(v, vsig).status, Status::Rejected);
  EXPECT_EQ(f.state().counters.resets[1], 0u);
  EXPECT_EQ(f.update_gps_velocity(v, vsig).status, Status::Rejected);
  EXPECT_EQ(f.state().counters.resets[1], 1u);
  EXPECT_LT((f.state().nav.v_n - v).norm(), S(1e-4));  // zero lever arm
  EXPECT_NEAR(double(f.state().P(4, 4)), 0.05 * 0.05, 1e-9);
  EXPECT_EQ(f.update_gps_velocity(v, vsig).status, Status::Ok);
}

TYPED_TEST(GpsInsResetTest, NoResetMeansLockout) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(0));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 100.0 / 6.37e6;
  for (int k = 0; k < 20; ++k) EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).status, Status::Rejected);
  EXPECT_EQ(f.state().counters.resets[0], 0u);
  EXPECT_NEAR(f.state().nav.lat, kLat, 1e-9);
}

TYPED_TEST(GpsInsResetTest, AcceptedFixRestartsTheCount) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(2));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 100.0 / 6.37e6;
  for (int round = 0; round < 3; ++round) {
    EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).status, Status::Rejected);
    EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).status, Status::Rejected);
    EXPECT_EQ(f.update_gps_position(kLat, kLon, kH, sig).status, Status::Ok);
  }
  EXPECT_EQ(f.state().counters.resets[0], 0u);
}
