// Quaternion helpers: identities, round trips, and the exponential map's Jacobian.
#include <gtest/gtest.h>

#include <quatnav/core/quaternion.hpp>
#include <cmath>
#include <limits>
#include <random>

using namespace quatnav;

namespace {
template <class S> Quat<S> random_quat(std::mt19937& g) {
  std::normal_distribution<double> n;
  Quat<S> q(S(n(g)), S(n(g)), S(n(g)), S(n(g)));
  return q / q.norm();
}
}  // namespace

TEST(Quaternion, ProductMatchesEigen) {
  std::mt19937 g(1);
  for (int i = 0; i < 100; ++i) {
    const Quat<double> a = random_quat<double>(g), b = random_quat<double>(g);
    const Quat<double> ref = quat::from_eigen<double>(quat::to_eigen(a) * quat::to_eigen(b));
    EXPECT_LT((quat::mul(a, b) - ref).norm(), 1e-14);
    EXPECT_LT((quat::left(a) * b - ref).norm(), 1e-14);
    EXPECT_LT((quat::right(b) * a - ref).norm(), 1e-14);
  }
}

TEST(Quaternion, RotationMatrixAgreesWithEigenAndRotate) {
  std::mt19937 g(2);
  for (int i = 0; i < 100; ++i) {
    const Quat<double> q = random_quat<double>(g);
    const Mat3<double> C = quat::to_rotmat(q);
    EXPECT_LT((C - quat::to_eigen(q).toRotationMatrix()).norm(), 1e-14);
    const Vec3<double> v(0.3, -1.2, 2.0);
    EXPECT_LT((quat::rotate(q, v) - C * v).norm(), 1e-13);
    EXPECT_LT((quat::rotate_inv(q, v) - C.transpose() * v).norm(), 1e-13);
    EXPECT_LT((quat::nav_z_in_body(q) - quat::rotate_inv(q, Vec3<double>(0, 0, 1))).norm(), 1e-15);
    EXPECT_EQ(quat::nav_z_in_body(q), Vec3<double>(C.row(2).transpose()));
    EXPECT_LT(quat::angle_between(quat::from_rotmat(C), q), 1e-7);
  }
}

TEST(Quaternion, EulerRoundTripAndOrder) {
  // ZYX: C_nb = Rz(yaw) Ry(pitch) Rx(roll).
  const double r = 0.3, p = -0.4, y = 2.5;
  const Mat3<double> C = (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
                          Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX())).toRotationMatrix();
  const Quat<double> q = quat::from_euler(r, p, y);
  EXPECT_LT((quat::to_rotmat(q) - C).norm(), 1e-14);
  EXPECT_LT((quat::to_euler(q) - Vec3<double>(r, p, y)).norm(), 1e-14);
}

TEST(Quaternion, RotvecJacobianMatchesFiniteDifferences) {
  for (double scale : {1e-9, 1e-4, 0.3, 2.0, 3.0}) {
    const Vec3<double> r = scale * Vec3<double>(0.6, -0.3, 0.74);
    const Mat43<double> J = quat::from_rotvec_jacobian(r);
    const double h = 1e-6;
    for (int j = 0; j < 3; ++j) {
      Vec3<double> rp = r, rm = r;
      rp[j] += h;
      rm[j] -= h;
      const Quat<double> d = (quat::from_rotvec(rp) - quat::from_rotvec(rm)) / (2 * h);
      EXPECT_LT((J.col(j) - d).norm(), 1e-8) << "scale " << scale << " col " << j;
    }
    EXPECT_LT((quat::to_rotvec(quat::from_rotvec(r)) - r).norm(), 1e-12 * std::max(1.0, scale));
  }
}

// cos_sinc replaces libm by Taylor polynomials below |x| = 0.125 rad (double) and 0.25 (float): as
// close as libm there (double within 2 units in the last place of long-double libm, float within
// 1.5 float epsilon), on both sides of the switch, and from_rotvec's quaternion of unit norm.
TEST(Quaternion, CosSincIsAsCloseAsLibm) {
  auto check = [](double x) {
    double c, sc;
    quat::cos_sinc(x * x, c, sc);
    const long double xl = x;
    const double c_true = double(std::cos(xl)), sc_true = x == 0 ? 1.0 : double(std::sin(xl) / xl);
    EXPECT_LE(std::abs(c - c_true), 2 * std::numeric_limits<double>::epsilon() * std::abs(c_true)) << x;
    EXPECT_LE(std::abs(sc - sc_true), 2 * std::numeric_limits<double>::epsilon() * sc_true) << x;
    float cf, scf;
    quat::cos_sinc(float(x) * float(x), cf, scf);
    const long double xf = float(x);
    EXPECT_LE(std::abs(double(cf) - double(std::cos(xf))), 1.5 * std::numeric_limits<float>::epsilon()) << x;
    EXPECT_LE(std::abs(double(scf) - (xf == 0 ? 1.0 : double(std::sin(xf) / xf))),
              1.5 * std::numeric_limits<float>::epsilon()) << x;
    const Quat<double> q = quat::from_rotvec(Vec3<double>(2 * x * 0.6, -2 * x * 0.48, 2 * x * 0.64));
    EXPECT_LE(std::abs(q.norm() - 1), 4 * std::numeric_limits<double>::epsilon()) << x;
  };
  for (int i = 0; i <= 4000; ++i) check(0.3 * i / 4000.0);
  for (double x : {0.125 * (1 - 1e-16), 0.125, 0.25 * (1 - 1e-7), 0.25}) check(x);
  check(1.3);
  check(3.1);
  // Not finite stays not finite.
  double c, sc;
  quat::cos_sinc(std::numeric_limits<double>::infinity(), c, sc);
  EXPECT_FALSE(std::isfinite(c));
  quat::cos_sinc(std::numeric_limits<double>::quiet_NaN(), c, sc);
  EXPECT_FALSE(std::isfinite(c) || std::isfinite(sc));
}

// atan2_small replaces libm by the Taylor polynomial of atan(y/x) for x > 0, |y/x| <= 1/8: as close
// as libm there (within 2 units in the last place of long-double libm in double and in float: the
// quotient's rounding and Horner's), the same signs and zeros, and libm's result elsewhere
// (beyond the switch, x <= 0, infinities, NaN).
TEST(Quaternion, Atan2SmallIsAsCloseAsLibm) {
  auto check = [](double y, double x) {
    const double a = quat::atan2_small(y, x);
    const double a_true = double(std::atan2((long double)y, (long double)x));
    EXPECT_LE(std::abs(a - a_true), 2 * std::numeric_limits<double>::epsilon() * std::abs(a_true)) << y << " " << x;
    const float yf = float(y), xf = float(x);
    const float af = quat::atan2_small(yf, xf);
    const double af_true = double(std::atan2((long double)yf, (long double)xf));
    EXPECT_LE(std::abs(double(af) - af_true), 2 * std::numeric_limits<float>::epsilon() * std::abs(af_true)) << y << " " << x;
  };
  for (int i = -4000; i <= 4000; ++i) {
    check(0.2 * i / 4000.0, 1.0);
    check(0.2 * i / 4000.0 * 3e-5, 3e-5);  // a scale other than 1 (the dip's cosine, a field)
  }
  for (double t : {0.125 * (1 - 1e-16), 0.125, 0.125 * (1 + 1e-16), 0.125 * (1 - 1e-7), -0.125}) check(t, 1.0);
  for (double x : {-1.0, -1e-3, 0.0}) {
    check(0.01, x);
    check(-0.01, x);
  }
  check(1.0, 0.5);
  EXPECT_EQ(std::signbit(quat::atan2_small(-0.0, 1.0)), true);
  EXPECT_EQ(quat::atan2_small(0.0, 1.0), 0.0);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(quat::atan2_small(1.0, inf), 0.0);
  EXPECT_EQ(quat::atan2_small(inf, inf), std::atan2(inf, inf));
  EXPECT_TRUE(std::isnan(quat::atan2_small(nan, 1.0)));
  EXPECT_TRUE(std::isnan(quat::atan2_small(0.01, nan)));
}

TEST(Quaternion, EnuNedConversion) {
  // A body aligned with ENU axes (q_enu_b = identity) has, w.r.t. NED, C_nb = [[0,1,0],[1,0,0],[0,0,-1]].
  const Quat<double> q = quat::enu_to_ned(quat::identity<double>());
  Mat3<double> C;
  C << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  EXPECT_LT((quat::to_rotmat(q) - C).norm(), 1e-15);
  EXPECT_LT((quat::ned_to_enu(q) - quat::identity<double>()).norm(), 1e-15);
}

TEST(Quaternion, FloatAndDoubleAgree) {
  std::mt19937 g(3);
  const Quat<double> a = random_quat<double>(g);
  const Quat<float> af = a.cast<float>();
  EXPECT_LT((quat::to_euler(af).cast<double>() - quat::to_euler(a)).norm(), 1e-5);
  EXPECT_LT((quat::from_rotvec(Vec3<float>(1e-4f, 2e-4f, 0.f)).cast<double>() -
             quat::from_rotvec(Vec3<double>(1e-4, 2e-4, 0.))).norm(), 1e-7);
}
