// QuaternionEKFPaper with a declination: the estimate is the magnetic-frame estimate turned by the
// declination about down, sample by sample, in float and double, for the heading-only, the
// paper's 3-row and the joint acc+mag updates; no heap in any step.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>

#include <quatnav/attitude/quaternion_ekf_paper.hpp>

using namespace quatnav;

template <class S> class QekfDeclination : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(QekfDeclination, Scalars);

namespace {
enum class MagMode { HeadingOnly, ThreeRow, Joint };

// Runs two filters on the same samples (a field with 60 deg dip; rotation about all axes), one
// with declination 0 and one with `decl`, and returns the largest difference between
// Rz(decl) * q0 and q1, and between the biases.
template <class S> void run_pair(MagMode mode, S decl, S& dq_max, S& db_max) {
  QuaternionEKFParams<S> p0 = mode == MagMode::HeadingOnly ? QuaternionEKFParams<S>() : QuaternionEKFParams<S>::paper();
  QuaternionEKFParams<S> p1 = p0;
  p1.declination = decl;
  QuaternionEKFPaper<S> f0(p0), f1(p1);
  const S dip = S(1.0472);
  const Vec3<S> m_mag(std::cos(dip), S(0), std::sin(dip));  // the field in the magnetic frame
  // The body's true attitude in the magnetic frame; the samples do not depend on the frame.
  Quat<S> q = quat::from_euler<S>(S(0.2), S(-0.1), S(1.0));
  const Vec3<S> g_n(S(0), S(0), S(-9.81));
  Vec3<S> acc = quat::rotate_inv(q, g_n), mag = quat::rotate_inv(q, Vec3<S>(S(40) * m_mag));
  ASSERT_EQ(f0.initialize(acc, mag), Status::Ok);
  ASSERT_EQ(f1.initialize(acc, mag), Status::Ok);
  const Quat<S> qd = quat::from_rotvec<S>(Vec3<S>(S(0), S(0), decl));
  const Vec3<S> bias(S(0.01), S(-0.02), S(0.015));
  dq_max = db_max = S(0);
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 1; k < 1500; ++k) {
    const S t = S(k) * S(0.01);
    const Vec3<S> w(S(0.6) * std::sin(S(0.7) * t), S(0.4) * std::cos(S(0.5) * t), S(0.8) * std::sin(S(0.3) * t));
    q = quat::mul(q, quat::from_rotvec<S>(Vec3<S>(w * S(0.01))));
    acc = quat::rotate_inv(q, g_n);
    mag = quat::rotate_inv(q, Vec3<S>(S(40) * m_mag));
    const Vec3<S> gyr = w + bias;
    ASSERT_EQ(f0.predict(gyr, S(0.01)), Status::Ok);
    ASSERT_EQ(f1.predict(gyr, S(0.01)), Status::Ok);
    if (mode == MagMode::Joint) {
      ASSERT_EQ(f0.update_acc_mag(acc, mag).status, f1.update_acc_mag(acc, mag).status);
    } else {
      f0.update_acc(acc);
      f1.update_acc(acc);
      ASSERT_EQ(f0.update_mag(mag).status, f1.update_mag(mag).status) << k;
    }
    const Quat<S> turned = quat::mul(qd, f0.quat());
    const S dq = std::min((turned - f1.quat()).cwiseAbs().maxCoeff(), (turned + f1.quat()).cwiseAbs().maxCoeff());
    dq_max = std::max(dq_max, dq);
    db_max = std::max(db_max, (f0.state().gyro_bias - f1.state().gyro_bias).cwiseAbs().maxCoeff());
  }
  Eigen::internal::set_is_malloc_allowed(true);
  // The turned filter's heading is true north: with the field's heading at `decl`, the true
  // yaw is the magnetic yaw plus `decl`. (The paper's parameters learn this run's gyro bias
  // within its 15 s; the slower bias learning of the defaults leaves a few degrees.)
  const S yaw_true = quat::to_euler(quat::mul(qd, q))[2];
  const S tol_yaw = mode == MagMode::HeadingOnly ? S(0.1) : S(0.01);
  EXPECT_NEAR(quat::wrap_pi(S(quat::to_euler(f1.quat())[2] - yaw_true)), S(0), tol_yaw);
}
}  // namespace

TYPED_TEST(QekfDeclination, EstimateIsTheMagneticOneTurnedAboutDown) {
  using S = TypeParam;
  const S tol = std::is_same<S, float>::value ? S(2e-4) : S(1e-10);
  for (MagMode mode : {MagMode::HeadingOnly, MagMode::ThreeRow, MagMode::Joint}) {
    for (S decl : {S(-0.148), S(0.3), S(3.0)}) {
      S dq, db;
      run_pair<S>(mode, decl, dq, db);
      EXPECT_LT(dq, tol) << int(mode) << " " << decl;
      EXPECT_LT(db, tol) << int(mode) << " " << decl;
    }
  }
}
