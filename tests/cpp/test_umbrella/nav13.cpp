// NavFilter13, every time update, through the umbrella header (umbrella.hpp).
#include "umbrella.hpp"

namespace {

using namespace umbrella;

template <class S> struct UmbrellaNav13 : ::testing::Test {};
TYPED_TEST_SUITE(UmbrellaNav13, Scalars);

template <class S, quatnav::TimeUpdate TU> void run_nav13() {
  using F = quatnav::NavFilter13<S, TU>;
  const Still<S> in;
  F f;
  typename F::Mat13 P = F::Mat13::Identity() * S(1e-4);
  ASSERT_EQ(f.reset(quatnav::Vec3<S>::Zero(), quatnav::quat::identity<S>(), quatnav::Vec3<S>::Zero(),
                    quatnav::Vec3<S>::Zero(), P, 0.8, 0.2, 100.0),
            quatnav::Status::Ok);
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(f.predict(in.gyr, in.acc, in.dt), quatnav::Status::Ok) << quatnav::to_string(TU);
    ASSERT_TRUE(f.update_velocity_yaw(quatnav::Vec3<S>::Zero(), S(0)).accepted()) << quatnav::to_string(TU);
  }
  EXPECT_LT(f.state().v_n.norm(), S(0.05)) << quatnav::to_string(TU);
  EXPECT_TRUE(near_identity<S>(f.state().q_nb, S(1e-2))) << quatnav::to_string(TU);
}

}  // namespace

TYPED_TEST(UmbrellaNav13, NavFilter13EveryTimeUpdate) {
  run_nav13<TypeParam, quatnav::TimeUpdate::Ekf>();
  run_nav13<TypeParam, quatnav::TimeUpdate::SecondOrder>();
  run_nav13<TypeParam, quatnav::TimeUpdate::Ukf>();
}
