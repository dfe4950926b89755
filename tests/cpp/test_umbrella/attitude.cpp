// The attitude filters through the umbrella header (umbrella.hpp).
#include "umbrella.hpp"

namespace {

using namespace umbrella;

template <class S> struct UmbrellaAttitude : ::testing::Test {};
TYPED_TEST_SUITE(UmbrellaAttitude, Scalars);

}  // namespace

TYPED_TEST(UmbrellaAttitude, AttitudeFilters) {
  using S = TypeParam;
  quatnav::QuaternionEKFPaper<S> qekf;
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
