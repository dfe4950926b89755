// GpsInsFilter's one gated correction path for the GNSS aids: an isolated outlier is rejected and
// changes nothing but the counters; a fix that fails its gate after a failing one inflates the
// position and velocity block of P until the fix is consistent and is applied; beyond inflate_max the state
// is reset to the fix; inflate_after = 0 keeps the plain gate (which locks out); the process-noise
// scale rises while the GNSS NIS stays large and stays at 1 on consistent fixes. No heap in any
// step; float and double.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/nav/gps_ins.hpp>

using namespace quatnav;

namespace {

constexpr double kLat = 0.7, kLon = -1.8, kH = 1600.0;

template <class S> Vec3<S> rest_gravity() { return Vec3<S>(S(0), S(0), S(-earth::gravity<double>(kLat, kH))); }
template <class S> Vec3<S> rest_rate() {
  return Vec3<S>(earth::earth_rate_n<double>(kLat).template cast<S>());  // level, yaw 0: body = NED
}

// A filter navigating at rest at (kLat, kLon, kH), fed with consistent fixes for a while.
template <class S> GpsInsFilter<S> navigating(S inflate_after, S inflate_max = S(1e4)) {
  GpsInsParams<S> p;
  p.inflate_after = inflate_after;
  p.inflate_max = inflate_max;
  GpsInsFilter<S> f(p);
  auto P = f.initial_covariance(Vec3<S>(S(0.05), S(0.05), S(0.1)), S(0.05));
  EXPECT_EQ(f.reset(Quat<S>(S(1), S(0), S(0), S(0)), Vec3<S>::Zero(), kLat, kLon, kH, Vec3<S>::Zero(),
                    Vec3<S>::Zero(), P),
            Status::Ok);
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03)), vsig(S(0.05), S(0.05), S(0.05));
  for (int k = 0; k < 200; ++k) {
    EXPECT_EQ(f.predict(rest_rate<S>(), rest_gravity<S>(), S(0.01)), Status::Ok);
    if (k % 25 == 0) f.update_gps(kLat, kLon, kH, Vec3<S>::Zero(), sig, vsig);
  }
  return f;
}

}  // namespace

template <class S> class GpsInsGateTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(GpsInsGateTest, Scalars);

TYPED_TEST(GpsInsGateTest, IsolatedOutlierIsRejectedAndChangesNothing) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(1));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const GpsInsState<S> before = f.state();
  Eigen::internal::set_is_malloc_allowed(false);
  const GpsInsUpdate<S, 3> r = f.update_gps_position(kLat + 30.0 / 6.37e6, kLon, kH, sig);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(r.status, Status::Rejected);
  EXPECT_EQ(r.decision, GpsInsDecision::Rejected);
  EXPECT_GT(double(r.nis), 1e3);
  EXPECT_EQ(f.state().nav.lat, before.nav.lat);
  EXPECT_TRUE((f.state().P.array() == before.P.array()).all());
  EXPECT_EQ(f.state().reject_run[0], 1u);
  // The next (good) fix is accepted and ends the run: the outlier was isolated.
  const GpsInsUpdate<S, 3> r2 = f.update_gps_position(kLat, kLon, kH, sig);
  EXPECT_EQ(r2.decision, GpsInsDecision::Accepted);
  EXPECT_EQ(f.state().reject_run[0], 0u);
  EXPECT_EQ(f.state().counters.inflated[0], 0u);
}

TYPED_TEST(GpsInsGateTest, FixesThatKeepFailingInflateTheCovariance) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(1));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 0.6 / 6.37e6;  // the fixes say 0.6 m further north: the INS is off
  EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).decision, GpsInsDecision::Rejected);
  const double P00 = double(f.state().P(0, 0));
  Eigen::internal::set_is_malloc_allowed(false);
  const GpsInsUpdate<S, 3> r = f.update_gps_position(lat2, kLon, kH, sig);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(r.status, Status::Ok);
  EXPECT_EQ(r.decision, GpsInsDecision::Inflated);
  EXPECT_GT(double(r.inflation), 10.0);
  EXPECT_GT(double(r.nis), double(f.params().gate_gps_pos));  // the NIS the gate saw
  EXPECT_EQ(f.state().counters.inflated[0], 1u);
  EXPECT_EQ(f.state().counters.accepted[0] , 1u + 200u / 25u);
  // With P inflated until the NIS equals 3, the fix pulls most of the way.
  EXPECT_NEAR((f.state().nav.lat - kLat) * 6.37e6, 0.6, 0.2);
  EXPECT_LT(double(f.state().P(0, 0)), P00 * double(r.inflation));
  // The adaptation raised the process noise.
  EXPECT_GT(double(f.q_scale()), 1.0);
}

TYPED_TEST(GpsInsGateTest, BeyondInflateMaxTheStateIsResetToTheFix) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(1), S(100));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 100.0 / 6.37e6;  // the fixes jump ~100 m north
  EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).decision, GpsInsDecision::Rejected);
  Eigen::internal::set_is_malloc_allowed(false);
  const GpsInsUpdate<S, 3> r = f.update_gps_position(lat2, kLon, kH, sig);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(r.status, Status::Rejected);
  EXPECT_EQ(r.decision, GpsInsDecision::Reset);
  EXPECT_EQ(f.state().counters.resets[0], 1u);
  EXPECT_NEAR(f.state().nav.lat, lat2, 1e-10);
  EXPECT_NEAR(f.state().nav.h, kH, 1e-6);
  const auto& P = f.state().P;
  // The fix's covariance: its sigma, the lever arm's and the time's (at rest: none).
  const double sl = double(f.params().lever_arm_sigma);
  EXPECT_NEAR(double(P(0, 0)), 0.02 * 0.02 + sl * sl, 1e-9);
  EXPECT_NEAR(double(P(2, 2)), 0.03 * 0.03 + sl * sl, 1e-9);
  EXPECT_EQ(double(P(0, 3)), 0.0);
  EXPECT_EQ(double(P(6, 1)), 0.0);
  EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).status, Status::Ok);
}

TYPED_TEST(GpsInsGateTest, VelocityResetBeyondInflateMax) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(1), S(2));
  const Vec3<S> v(S(3), S(-1), S(0)), vsig(S(0.05), S(0.05), S(0.05));
  EXPECT_EQ(f.update_gps_velocity(v, vsig).status, Status::Rejected);
  const GpsInsUpdate<S, 3> r = f.update_gps_velocity(v, vsig);
  EXPECT_EQ(r.decision, GpsInsDecision::Reset);
  EXPECT_EQ(f.state().counters.resets[1], 1u);
  EXPECT_LT((f.state().nav.v_n - v).norm(), S(1e-4));  // zero lever arm
  EXPECT_EQ(f.update_gps_velocity(v, vsig).status, Status::Ok);
}

TYPED_TEST(GpsInsGateTest, NoInflationMeansLockout) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(0));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 100.0 / 6.37e6;
  for (int k = 0; k < 20; ++k) EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).status, Status::Rejected);
  EXPECT_EQ(f.state().counters.resets[0], 0u);
  EXPECT_NEAR(f.state().nav.lat, kLat, 1e-9);
}

TYPED_TEST(GpsInsGateTest, AlternatingOutliersAreAllRejected) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(1));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  const double lat2 = kLat + 100.0 / 6.37e6;
  for (int round = 0; round < 3; ++round) {
    EXPECT_EQ(f.update_gps_position(lat2, kLon, kH, sig).decision, GpsInsDecision::Rejected);
    EXPECT_EQ(f.update_gps_position(kLat, kLon, kH, sig).decision, GpsInsDecision::Accepted);
  }
  EXPECT_EQ(f.state().counters.inflated[0] + f.state().counters.resets[0], 0u);
  EXPECT_NEAR(f.state().nav.lat, kLat, 1e-8);
}

TYPED_TEST(GpsInsGateTest, ConsistentFixesLeaveTheProcessNoiseAlone) {
  using S = TypeParam;
  GpsInsFilter<S> f = navigating<S>(S(1));
  const Vec3<S> sig(S(0.02), S(0.02), S(0.03));
  for (int k = 0; k < 2000; ++k) {
    f.predict(rest_rate<S>(), rest_gravity<S>(), S(0.01));
    if (k % 20 == 0) { EXPECT_EQ(f.update_gps_position(kLat, kLon, kH, sig).status, Status::Ok); }
  }
  EXPECT_EQ(double(f.q_scale()), 1.0);
}
