// QuaternionEKF's joint accelerometer + magnetometer update (update_acc_mag, 6 rows): its
// innovation covariance and NIS against the dense formulas in double,
//   S = H P H^T + R,  H = [[h_a]x 0; [h_m]x 0],  R = diag(acc_sigma^2 I3, mag_sigma^2 I3),
//   NIS = y^T S^-1 y,
// where h_a, h_m are the predicted unit directions of gravity's reaction and of the field (the
// direction models of the top of quaternion_ekf.hpp). The separate updates (update_acc,
// update_mag) have tests of their own; this is the only test of the joint one's R.
#include <gtest/gtest.h>

#include <cmath>

#include <quatnav/attitude/quaternion_ekf.hpp>

using namespace quatnav;

template <class S> class EskfJointUpdate : public ::testing::Test {};
using JointTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(EskfJointUpdate, JointTypes);

TYPED_TEST(EskfJointUpdate, InnovationCovarianceAndNisAreTheDenseOnes) {
  using S = TypeParam;
  auto p = QuaternionEKFParams<S>::paper();
  p.mag_heading_only = false;
  p.acc_sigma = S(0.03);  // unequal: a scaled or swapped R shows in both blocks
  p.mag_sigma = S(0.07);
  QuaternionEKF<S> f(p);
  // A covariance with attitude-bias correlations (what a run leaves): A A^T / 1e4 + 1e-5 I.
  Mat<double, 6, 6> A;
  A << 0.9, 0.1, -0.2, 0.3, 0.0, 0.1, 0.2, 0.8, 0.1, -0.1, 0.2, 0.0, -0.1, 0.3, 0.7, 0.0, 0.1, 0.2,  //
      0.1, 0.0, 0.2, 0.05, 0.01, 0.0, 0.0, 0.1, -0.1, 0.01, 0.04, 0.02, 0.2, 0.0, 0.1, 0.0, 0.01, 0.06;
  const Mat<double, 6, 6> P0 = A * A.transpose() / 1e4 + 1e-5 * Mat<double, 6, 6>::Identity();
  const Quat<S> q = quat::from_euler<S>(S(0.2), S(-0.3), S(1.1));
  ASSERT_EQ(f.reset(q, Vec3<S>(S(0.01), S(-0.02), S(0.005)), P0.cast<S>()), Status::Ok);
  const double dip = 1.1;
  f.set_mag_dip(S(dip));
  const Mat<double, 6, 6> P = f.covariance().template cast<double>();
  // Samples from an attitude 2 deg off the estimate, well inside the gates.
  const Quat<S> qt = quat::mul(q, quat::from_rotvec<S>(Vec3<S>(S(0.02), S(-0.025), S(0.03))));
  const Vec3<S> acc = quat::rotate_inv(qt, Vec3<S>(S(0), S(0), S(-9.81)));
  const Vec3<S> mag = quat::rotate_inv(qt, Vec3<S>(S(48 * std::cos(dip)), S(0), S(48 * std::sin(dip))));
  const auto r = f.update_acc_mag(acc, mag);
  ASSERT_EQ(r.status, Status::Ok);

  const Vec<double, 6> y = r.innovation.template cast<double>();
  const Vec3<double> ha = acc.template cast<double>().normalized() - y.head<3>();
  const Vec3<double> hm = mag.template cast<double>().normalized() - y.tail<3>();
  const Quat<double> qd = q.template cast<double>();
  const double tol = sizeof(S) == 4 ? 2e-5 : 1e-12;
  // The innovation is the sample's direction minus the prediction from the prior attitude.
  EXPECT_LT((ha - quat::rotate_inv(qd, Vec3<double>(0, 0, -1))).norm(), tol);
  EXPECT_LT((hm - quat::rotate_inv(qd, Vec3<double>(std::cos(dip), 0, std::sin(dip)))).norm(), tol);
  EXPECT_GT(y.norm(), 0.02);

  Mat<double, 6, 6> H = Mat<double, 6, 6>::Zero();
  H.template block<3, 3>(0, 0) = quat::skew<double>(ha);
  H.template block<3, 3>(3, 0) = quat::skew<double>(hm);
  Vec<double, 6> rd;
  const double sa = double(p.acc_sigma), sm = double(p.mag_sigma);
  rd << sa * sa, sa * sa, sa * sa, sm * sm, sm * sm, sm * sm;
  const Mat<double, 6, 6> Sd = H * P * H.transpose() + Mat<double, 6, 6>(rd.asDiagonal());
  const Mat<double, 6, 6> Sf = r.innovation_cov.template cast<double>();
  // R is at least a quarter of every diagonal entry of S here: scaling either block of R by 2
  // moves S by far more than the tolerance.
  EXPECT_LT((Sf - Sd).norm() / Sd.norm(), 10 * tol);
  for (int i = 0; i < 6; ++i) EXPECT_GT(rd[i], 0.25 * Sd(i, i)) << i;
  const double nis = y.dot(Sd.ldlt().solve(y));
  EXPECT_NEAR(double(r.nis), nis, 10 * tol * nis);
}
