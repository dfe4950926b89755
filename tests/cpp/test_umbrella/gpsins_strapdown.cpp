// GpsInsFilter and the strapdown through the umbrella header (umbrella.hpp).
#include "umbrella.hpp"

namespace {

using namespace umbrella;

template <class S> struct UmbrellaNav : ::testing::Test {};
TYPED_TEST_SUITE(UmbrellaNav, Scalars);

}  // namespace

TYPED_TEST(UmbrellaNav, GpsInsFilter) {
  using S = TypeParam;
  const Still<S> in;
  quatnav::GpsInsFilter<S> f;
  constexpr int N = quatnav::GpsInsFilter<S>::kStates;
  const quatnav::Mat<S, N, N> P = quatnav::Mat<S, N, N>::Identity() * S(1e-4);
  const double lat = 0.8, lon = 0.2, h = 100.0;
  ASSERT_EQ(f.reset(quatnav::quat::identity<S>(), quatnav::Vec3<S>::Zero(), lat, lon, h, quatnav::Vec3<S>::Zero(),
                         quatnav::Vec3<S>::Zero(), P),
            quatnav::Status::Ok);
  ASSERT_TRUE(f.navigating());
  // At rest the specific force is -g_n: measured with the model's own gravity, the fixes agree.
  const quatnav::Vec3<S> f_b = -quatnav::earth::gravity_n<S>(S(lat), S(h));
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(f.predict(in.gyr, f_b, in.dt), quatnav::Status::Ok);
    if (k % 10 == 9) {
      const auto r = f.update_gps_position(lat, lon, h, quatnav::Vec3<S>::Constant(S(1)));
      ASSERT_TRUE(r.accepted()) << quatnav::to_string(r.status);
    }
  }
  EXPECT_TRUE(near_identity<S>(f.q_nb(), S(1e-3)));
}

TYPED_TEST(UmbrellaNav, Strapdown) {
  using S = TypeParam;
  quatnav::StrapdownState<S> st;
  st.lat = 0.8;
  st.h = 100.0;
  const quatnav::Vec3<S> f_b = -quatnav::earth::gravity_n<S>(S(st.lat), S(st.h));
  for (int k = 0; k < 50; ++k)
    ASSERT_EQ(quatnav::strapdown_step<S>(st, quatnav::Vec3<S>::Zero(), f_b, S(0.01), quatnav::StrapdownParams{false}),
              quatnav::Status::Ok);
  EXPECT_LT(st.v_n.norm(), S(1e-4));
  EXPECT_NEAR(st.lat, 0.8, 1e-9);
}
