// The umbrella header alone is enough: of quatnav, the units of this test include only
// <quatnav/quatnav.hpp> (through this file) and run every filter (each NavFilter13 time update)
// and the strapdown a few steps, in float and double. One executable of three translation units
// (the attitude filters; NavFilter13; GpsInsFilter and the strapdown) that compile in parallel:
// as one unit it took 280 s at -O3, the longest of the test build.
#pragma once

#include <gtest/gtest.h>

#include <quatnav/quatnav.hpp>

namespace umbrella {

using Scalars = ::testing::Types<float, double>;

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

}  // namespace umbrella
