// Paper 000 filters: Jacobians against finite differences, no heap in a step, bad input leaves
// the state bit-for-bit untouched, convergence on static data, float and double.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <quatnav/quatnav.hpp>

#include "same_fields.hpp"

using namespace quatnav;

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class T> bool bitwise_equal(const T& a, const T& b) {
  return std::memcmp(static_cast<const void*>(&a), static_cast<const void*>(&b), sizeof(T)) == 0;
}
// State structs have padding after the bools; compare field by field.
template <class T> bool same_state(const T& a, const T& b) { return quatnav_test::same_fields(a, b); }
// The estimate: attitude, bias, covariance and the field reference (not the robustness bookkeeping,
// which follows the input signal also through a rejected update).
template <class S> bool same_estimate(const QuaternionEKFPaperState<S>& a, const QuaternionEKFPaperState<S>& b) {
  return bitwise_equal(a.q_nb, b.q_nb) && bitwise_equal(a.gyro_bias, b.gyro_bias) && bitwise_equal(a.P, b.P) &&
         quatnav_test::same_fields(a.mag, b.mag) && a.initialized == b.initialized;
}
template <class S> bool same_estimate(const EulerEKFState<S>& a, const EulerEKFState<S>& b) {
  return bitwise_equal(a.euler, b.euler) && bitwise_equal(a.gyro_bias, b.gyro_bias) && bitwise_equal(a.P, b.P) &&
         quatnav_test::same_fields(a.mag, b.mag) && a.initialized == b.initialized;
}
}  // namespace

TEST(QuaternionEKFPaper, TransitionJacobianMatchesFiniteDifferences) {
  const Quat<double> q = quat::normalized(Quat<double>(0.8, 0.3, -0.4, 0.2));
  const Vec3<double> b(0.01, -0.02, 0.03), w(1.5, -0.7, 2.2);
  const double dt = 0.01;
  Quat<double> q1;
  Mat<double, 7, 7> Phi;
  detail::qekf_propagate(q, b, w, dt, q1, Phi);
  Vec<double, 7> x;
  x << q, b;
  const double h = 1e-7;
  for (int j = 0; j < 7; ++j) {
    Vec<double, 7> xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    Quat<double> qp, qm;
    Mat<double, 7, 7> dummy;
    detail::qekf_propagate(Quat<double>(xp.head<4>()), Vec3<double>(xp.tail<3>()), w, dt, qp, dummy);
    detail::qekf_propagate(Quat<double>(xm.head<4>()), Vec3<double>(xm.tail<3>()), w, dt, qm, dummy);
    EXPECT_LT((Phi.col(j).head<4>() - (qp - qm) / (2 * h)).norm(), 1e-8) << "column " << j;
  }
  EXPECT_TRUE((Phi.bottomLeftCorner<3, 4>().isZero(0.0)));
  EXPECT_TRUE((Phi.bottomRightCorner<3, 3>().isIdentity(0.0)));
}

TEST(QuaternionEKFPaper, TransitionJacobianReducesToPaperEq10) {
  // eq. (10): Phi_qq = I + T/2 Omega(w~), Phi_qb = T/2 * [[q1 q2 q3], [-q0 q3 -q2], [-q3 -q0 q1], [q2 -q1 -q0]].
  const Quat<double> q = quat::normalized(Quat<double>(0.8, 0.3, -0.4, 0.2));
  const Vec3<double> b(0.01, -0.02, 0.03), w(1.5, -0.7, 2.2);
  for (double T : {1e-2, 1e-3}) {
    Quat<double> q1;
    Mat<double, 7, 7> Phi;
    detail::qekf_propagate(q, b, w, T, q1, Phi);
    Mat<double, 7, 7> eq10 = Mat<double, 7, 7>::Identity();
    eq10.topLeftCorner<4, 4>() += T / 2 * quat::omega(Vec3<double>(w - b));
    Mat43<double> G;
    G << q[1], q[2], q[3], -q[0], q[3], -q[2], -q[3], -q[0], q[1], q[2], -q[1], -q[0];
    eq10.topRightCorner<4, 3>() = T / 2 * G;
    // Agreement to second order in T (the exact exponential differs only there).
    EXPECT_LT((Phi - eq10).norm(), 2.0 * T * T * (w - b).squaredNorm()) << "T = " << T;
  }
}

TEST(QuaternionEKFPaper, MeasurementJacobianMatchesFiniteDifferences) {
  const Quat<double> q = quat::normalized(Quat<double>(0.5, -0.3, 0.6, 0.4));
  for (auto r : {Vec2<double>(0.0, -1.0), Vec2<double>(0.45, 0.89)}) {
    const Mat34<double> H = detail::qekf_H(q, r[0], r[1]);
    for (int j = 0; j < 4; ++j) {
      Quat<double> qp = q, qm = q;
      qp[j] += 1e-7;
      qm[j] -= 1e-7;
      const Vec3<double> d = (detail::qekf_h(qp, r[0], r[1]) - detail::qekf_h(qm, r[0], r[1])) / 2e-7;
      EXPECT_LT((H.col(j) - d).norm(), 1e-8);
    }
    // h is C_bn(q) r for unit q.
    EXPECT_LT((detail::qekf_h(q, r[0], r[1]) - quat::rotate_inv(q, Vec3<double>(r[0], 0, r[1]))).norm(), 1e-14);
  }
}

TEST(EulerEKF, JacobiansMatchFiniteDifferences) {
  const Vec3<double> e(0.3, -0.5, 2.0), b(0.01, 0.02, -0.01), w(0.5, -1.0, 0.8);
  const double h = 1e-7;
  Vec3<double> e1;
  Mat3<double> E;
  bool sing = false;
  // The step's F and the central differences of its angles in [e, b].
  const auto step = [&](const Vec3<double>& rate, double T, bool exact, Mat<double, 3, 6>& fd) {
    Mat<double, 6, 6> F, d1;
    detail::euler_propagate(e, b, rate, T, 0.02, exact, e1, F, E, sing);
    Vec<double, 6> x;
    x << e, b;
    for (int j = 0; j < 6; ++j) {
      Vec<double, 6> xp = x, xm = x;
      xp[j] += h;
      xm[j] -= h;
      Vec3<double> ep, em;
      detail::euler_propagate(Vec3<double>(xp.head<3>()), Vec3<double>(xp.tail<3>()), rate, T, 0.02, exact, ep, d1, E,
                              sing);
      detail::euler_propagate(Vec3<double>(xm.head<3>()), Vec3<double>(xm.tail<3>()), rate, T, 0.02, exact, em, d1, E,
                              sing);
      fd.col(j) = (ep - em) / (2 * h);
    }
    return Mat<double, 3, 6>(F.topRows<3>());
  };
  // F is the Jacobian of paper 004's Euler step (exact = false) ...
  Mat<double, 3, 6> fd;
  const Mat<double, 3, 6> F = step(w, 0.01, false, fd);
  for (int j = 0; j < 6; ++j) EXPECT_LT((F.col(j) - fd.col(j)).norm(), 1e-8) << "column " << j;
  // ... and of the exact step to first order in T: the difference shrinks as T^2 (a wrong term
  // of F would leave a difference of order T, the same F in both modes).
  for (const Vec3<double>& rate : {w, Vec3<double>(3.0, -6.0, 5.0)}) {  // 0.5 rad/s and 500 deg/s
    double diff[2];
    for (int i = 0; i < 2; ++i) {
      const double T = i == 0 ? 0.01 : 0.005;
      diff[i] = (step(rate, T, true, fd) - fd).norm();
      EXPECT_LT(diff[i], 4.0 * T * T * (rate - b).squaredNorm()) << "T " << T;
    }
    EXPECT_GT(diff[0] / diff[1], 3.0);  // second order: about 4
    EXPECT_LT(diff[0] / diff[1], 5.0);
  }
  Vec3<double> hv;
  Mat3<double> H;
  detail::euler_measurement(e, 0.45, 0.89, hv, H);
  EXPECT_LT((hv - quat::rotate_inv(quat::from_euler(e), Vec3<double>(0.45, 0, 0.89))).norm(), 1e-14);
  for (int j = 0; j < 3; ++j) {
    Vec3<double> ep = e, em = e, hp, hm;
    ep[j] += h;
    em[j] -= h;
    Mat3<double> d;
    detail::euler_measurement(ep, 0.45, 0.89, hp, d);
    detail::euler_measurement(em, 0.45, 0.89, hm, d);
    EXPECT_LT((H.col(j) - (hp - hm) / (2 * h)).norm(), 1e-8);
  }
}

/// The exact step: a constant rate integrated over a second in 100 steps lands on q exp(w T) to
/// rounding, where paper 004's Euler step is off by degrees at 500 deg/s; a step across pitch 90 deg
/// keeps the branch of the angles continuous (pitch beyond 90 deg, roll and yaw kept).
TEST(EulerEKF, ExactStepFollowsTheQuaternionAndKeepsTheBranch) {
  const Vec3<double> e0(0.3, -0.5, 2.0), b(0.01, 0.02, -0.01), w(3.0, -6.0, 5.0);
  const double dt = 0.01;
  for (const bool exact : {true, false}) {
    Vec3<double> e = e0, e1;
    Mat<double, 6, 6> F;
    Mat3<double> E;
    bool sing = false;
    for (int k = 0; k < 100; ++k) {
      detail::euler_propagate(e, b, w, dt, 0.02, exact, e1, F, E, sing);
      ASSERT_FALSE(sing);
      e = e1;
    }
    const Quat<double> q_true = quat::mul(quat::from_euler(e0), quat::from_rotvec(Vec3<double>(1.0 * (w - b))));
    const double err = quat::angle_between(quat::from_euler(e), q_true);
    if (exact) {
      EXPECT_LT(err, 1e-10);
    } else {
      EXPECT_GT(err, 0.02);  // the paper's step: degrees after one second at this rate
    }
  }
  // Pitch 87 deg, a 6 deg step about body y: the rotation ends at pitch 93 deg on the branch of
  // the start (to_euler would give pitch 87 deg with roll and yaw turned by 180 deg).
  const double deg = 3.14159265358979323846 / 180.0;
  const Vec3<double> start(0.0, 87.0 * deg, -0.4), zero = Vec3<double>::Zero();
  const Vec3<double> rate(0.0, 6.0 * deg / dt, 0.0);
  Vec3<double> e1;
  Mat<double, 6, 6> F;
  Mat3<double> E;
  bool sing = true;
  detail::euler_propagate(start, zero, rate, dt, 0.02, true, e1, F, E, sing);
  EXPECT_FALSE(sing);
  EXPECT_NEAR(e1[1], 93.0 * deg, 1e-9);
  EXPECT_NEAR(e1[0], 0.0, 1e-9);
  EXPECT_NEAR(e1[2], -0.4, 1e-9);
  const Quat<double> q1 = quat::mul(quat::from_euler(start), quat::from_rotvec(Vec3<double>(dt * rate)));
  EXPECT_LT(quat::angle_between(quat::from_euler(e1), q1), 1e-12);
}

template <class F> void expect_no_heap_in_steps() {
  using S = typename F::Scalar;
  F f;
  const Vec3<S> acc(S(0.5), S(-0.3), S(-9.7)), mag(S(20), S(3), S(40)), gyr(S(0.1), S(-0.2), S(0.3));
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 10; ++k) {
    f.predict(gyr, S(0.01));
    f.update_acc(acc);
    f.update_mag(mag);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(f.quat().allFinite());
}

TEST(NoHeap, QuaternionEKFPaper) {
  expect_no_heap_in_steps<QuaternionEKFPaper<double>>();
  expect_no_heap_in_steps<QuaternionEKFPaper<float>>();
}
TEST(NoHeap, EulerEKF) {
  expect_no_heap_in_steps<EulerEKF<double>>();
  expect_no_heap_in_steps<EulerEKF<float>>();
}

TEST(NoHeap, BatchRun) {
  QuaternionEKFPaper<double> f;
  const int n = 50;
  std::vector<double> gyr(3 * n, 0.01), acc(3 * n), mag(3 * n), dt(n, 0.01), q(4 * n), b(3 * n), s(7 * n), as(3 * n);
  std::vector<std::uint32_t> fl(n);
  for (int k = 0; k < n; ++k) {
    acc[3 * k + 2] = -9.81;
    mag[3 * k] = 20;
    mag[3 * k + 2] = 40;
  }
  Eigen::internal::set_is_malloc_allowed(false);
  run_attitude_batch(f, gyr.data(), acc.data(), mag.data(), dt.data(), n, q.data(), b.data(), s.data(), as.data(),
                     fl.data());
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(fl[0] & flags::kInitialized, flags::kInitialized);
  EXPECT_TRUE(std::isfinite(q[4 * n - 1]));
}

template <class F> void expect_bad_input_leaves_state() {
  using S = typename F::Scalar;
  F f;
  const Vec3<S> acc(S(0.5), S(-0.3), S(-9.7)), mag(S(20), S(3), S(40)), gyr(S(0.1), S(-0.2), S(0.3));
  EXPECT_EQ(f.predict(gyr, S(0.01)), Status::NotInitialized);
  EXPECT_EQ(f.initialize(Vec3<S>::Zero(), mag), Status::ZeroNorm);
  EXPECT_EQ(f.initialize(Vec3<S>(S(kNaN), S(0), S(1)), mag), Status::NonFinite);
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  f.predict(gyr, S(0.01));
  f.update_acc(acc);
  const auto before = f.state();
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  EXPECT_EQ(f.predict(Vec3<S>(nan, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(Vec3<S>(inf, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(gyr, S(0)), Status::InvalidDt);
  EXPECT_EQ(f.predict(gyr, S(-0.01)), Status::InvalidDt);
  EXPECT_EQ(f.predict(gyr, nan), Status::InvalidDt);
  EXPECT_EQ(f.predict(gyr, S(100)), Status::InvalidDt);
  EXPECT_EQ(f.update_acc(Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_acc(Vec3<S>(S(0), nan, S(1))).status, Status::NonFinite);
  EXPECT_EQ(f.update_mag(Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_mag(Vec3<S>(inf, S(0), S(0))).status, Status::NonFinite);
  EXPECT_TRUE(same_state(before, f.state()));
  // A gate of 1e-12 rejects any real innovation: the estimate stays.
  EXPECT_EQ(f.update_acc(Vec3<S>(S(3), S(0), S(-9)), S(1e-12)).status, Status::Rejected);
  EXPECT_TRUE(same_estimate(before, f.state()));
}

TEST(BadInput, QuaternionEKFStateUntouched) {
  expect_bad_input_leaves_state<QuaternionEKFPaper<double>>();
  expect_bad_input_leaves_state<QuaternionEKFPaper<float>>();
}
TEST(BadInput, EulerEKFStateUntouched) {
  expect_bad_input_leaves_state<EulerEKF<double>>();
  expect_bad_input_leaves_state<EulerEKF<float>>();
}

TEST(BadInput, QuaternionEKFRefusesMalformedState) {
  QuaternionEKFPaper<double> f;
  auto s = f.state();
  s.q_nb = Quat<double>(2, 0, 0, 0);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s.q_nb = Quat<double>(kNaN, 0, 0, 0);
  EXPECT_EQ(f.set_state(s), Status::NonFinite);
}

template <class F> void expect_static_convergence() {
  using S = typename F::Scalar;
  // True attitude roll 20, pitch -10, yaw 50 deg; field dip 60 deg.
  const Quat<double> qt = quat::from_euler(0.349, -0.1745, 0.8727);
  const Vec3<double> g_n(0, 0, -9.81), m_n(25, 0, 43.3);
  const Vec3<S> acc = quat::rotate_inv(qt, g_n).template cast<S>(), mag = quat::rotate_inv(qt, m_n).template cast<S>();
  F f;
  // Start from a wrong attitude: initialize from a perturbed sample.
  const Quat<double> qw = quat::mul(qt, quat::from_rotvec(Vec3<double>(0.2, -0.15, 0.3)));
  ASSERT_EQ(f.initialize(quat::rotate_inv(qw, g_n).template cast<S>(), quat::rotate_inv(qw, m_n).template cast<S>()),
            Status::Ok);
  f.set_mag_dip(S(std::atan2(43.3, 25.0)));
  // The initial error leaks into the bias states, which settle slowly: 100 s.
  for (int k = 0; k < 10000; ++k) {
    ASSERT_EQ(f.predict(Vec3<S>::Zero(), S(0.01)), Status::Ok);
    ASSERT_EQ(f.update_acc(acc).status, Status::Ok);
    ASSERT_EQ(f.update_mag(mag).status, Status::Ok);
  }
  const double err = quat::angle_between(Quat<double>(f.quat().template cast<double>()), qt);
  EXPECT_LT(err, 1e-3);
  // ... and lies within the filter's own 3 sigma.
  const Mat3<S> Pa = f.attitude_covariance();
  EXPECT_LT(err, 3.0 * std::sqrt(double(Pa.trace())));
}

TEST(Static, QuaternionEKFConverges) {
  expect_static_convergence<QuaternionEKFPaper<double>>();
  expect_static_convergence<QuaternionEKFPaper<float>>();
}
TEST(Static, EulerEKFConverges) {
  expect_static_convergence<EulerEKF<double>>();
  expect_static_convergence<EulerEKF<float>>();
}

TEST(QuaternionEKFPaper, JointUpdateEqualsPaperStackedForm) {
  // update_acc_mag is eq. (11)-(12) as one 6-vector; it must accept and move toward the truth.
  QuaternionEKFPaper<double> f;
  const Quat<double> qt = quat::from_euler(0.1, 0.2, 0.3);
  const Vec3<double> acc = quat::rotate_inv(qt, Vec3<double>(0, 0, -9.81)), mag = quat::rotate_inv(qt, Vec3<double>(25, 0, 43));
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.81), Vec3<double>(25, 0, 43)), Status::Ok);
  const double e0 = quat::angle_between(f.quat(), qt);
  const auto r = f.update_acc_mag(acc, mag);
  EXPECT_EQ(r.status, Status::Ok);
  EXPECT_LT(quat::angle_between(f.quat(), qt), e0);
  EXPECT_NEAR(f.quat().norm(), 1.0, 1e-15);
}
