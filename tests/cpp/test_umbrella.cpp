// The umbrella header alone is enough: this file includes only <quatnav/quatnav.hpp> and runs
// every filter (each NavFilter13 time update) and the strapdown a few steps, in float and double.
#include <gtest/gtest.h>

#include <quatnav/quatnav.hpp>

namespace {

template <class S> struct Umbrella : ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Umbrella, Scalars);

// A level body at rest facing magnetic north, 100 Hz.
template <class S> struct Still {
  const S dt = S(0.01);
  const quatnav::Vec3<S> gyr = quatnav::Vec3<S>::Zero();
  const quatnav::Vec3<S> acc = quatnav::Vec3<S>(S(0), S(0), S(-9.81));
  const quatnav::Vec3<S> mag = quatnav::Vec3<S>(S(0.4), S(0), S(0.9));
};

template <class S> bool near_identity(const quatnav::Quat<S>& q, S tol) {
  return std::abs(std::abs(q[0]) - S(1)) < tol && q.template tail<3>().norm() < tol;
}

template <class F> void run_attitude(F& f) {
  using S = typename F::Scalar;
  const Still<S> in;
  ASSERT_EQ(f.initialize(in.acc, in.mag), quatnav::Status::Ok);
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(f.predict(in.gyr, in.dt), quatnav::Status::Ok);
    ASSERT_TRUE(f.update_acc(in.acc).accepted());
    ASSERT_TRUE(f.update_mag(in.mag).accepted());
  }
  EXPECT_TRUE(near_identity<S>(f.quat(), S(1e-4)));
}

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

TYPED_TEST(Umbrella, AttitudeFilters) {
  using S = TypeParam;
  quatnav::QuaternionEKF<S> qekf;
  run_attitude(qekf);
  quatnav::EulerEKF<S> euler;
  run_attitude(euler);

  quatnav::MargFilter<S> marg;
  const Still<S> in;
  ASSERT_EQ(marg.initialize(in.acc, in.mag), quatnav::Status::Ok);
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(marg.predict(in.gyr, in.dt), quatnav::Status::Ok);
    ASSERT_TRUE(marg.update_acc_mag(in.acc, in.mag).accepted());
  }
  EXPECT_TRUE(near_identity<S>(marg.quat(), S(1e-4)));
}

TYPED_TEST(Umbrella, NavFilter13EveryTimeUpdate) {
  run_nav13<TypeParam, quatnav::TimeUpdate::Ekf>();
  run_nav13<TypeParam, quatnav::TimeUpdate::SecondOrder>();
  run_nav13<TypeParam, quatnav::TimeUpdate::Ukf>();
}

TYPED_TEST(Umbrella, GpsInsFilter) {
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

TYPED_TEST(Umbrella, Strapdown) {
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
