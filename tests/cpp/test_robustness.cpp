// Faults and bad input: saturated readings, the covariance floor (forced near-singular case),
// refused states, and a replay of random fault sequences through the fuzz driver (the same
// checks as the libFuzzer target tests/fuzz/fuzz_filters.cpp, here on a fixed random corpus so
// that every ctest run, also under ASan + UBSan, exercises them).
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>

#include <random>
#include <vector>

#include "../fuzz/filter_fuzz.hpp"

using namespace quatnav;
using quatnav_fuzz::FuzzAdapter;

namespace {

template <class F> void random_fault_sequences(unsigned seed, int inputs) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < inputs; ++i) {
    bytes.resize(64 + rng() % 3000);
    for (auto& b : bytes) b = std::uint8_t(rng());
    quatnav_fuzz::Reader r(bytes.data(), bytes.size());
    const bool ok = quatnav_fuzz::run_one<F>(r, [&](const std::string& msg) { ADD_FAILURE() << msg << " (input " << i << ")"; });
    if (!ok) return;
  }
}

}  // namespace

TEST(FaultSequences, QuaternionEKF) {
  random_fault_sequences<QuaternionEKF<double>>(1, 300);
  random_fault_sequences<QuaternionEKF<float>>(2, 300);
}
TEST(FaultSequences, EulerEKF) {
  random_fault_sequences<EulerEKF<double>>(3, 300);
  random_fault_sequences<EulerEKF<float>>(4, 300);
}

TEST(FaultSequences, MargFilter) {
  random_fault_sequences<MargFilter<double>>(5, 300);
  random_fault_sequences<MargFilter<float>>(6, 300);
}

TEST(FaultSequences, NavFilter13) {
  random_fault_sequences<NavFilter13<double, TimeUpdate::Ekf>>(11, 150);
  random_fault_sequences<NavFilter13<float, TimeUpdate::Ekf>>(12, 150);
  random_fault_sequences<NavFilter13<double, TimeUpdate::SecondOrder>>(13, 150);
  random_fault_sequences<NavFilter13<float, TimeUpdate::SecondOrder>>(14, 150);
  random_fault_sequences<NavFilter13<double, TimeUpdate::Ukf>>(15, 150);
  random_fault_sequences<NavFilter13<float, TimeUpdate::Ukf>>(16, 150);
}

TEST(FaultSequences, GpsInsFilter) {
  random_fault_sequences<GpsInsFilter<double>>(17, 300);
  random_fault_sequences<GpsInsFilter<float>>(18, 300);
}

// --- saturation ------------------------------------------------------------------------------
template <class F> void expect_saturation_reported() {
  using S = typename F::Scalar;
  typename F::Params p;
  p.gyro_range = S(35);   // rad/s (2000 deg/s)
  p.acc_range = S(156.9);  // m/s^2 (16 g)
  F f(p);
  const Vec3<S> acc(S(0.5), S(-0.3), S(-9.7)), mag(S(20), S(3), S(40));
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  ASSERT_EQ(f.predict(Vec3<S>(S(0.1), S(0.2), S(34.9)), S(0.01)), Status::Ok);
  ASSERT_EQ(f.update_acc(Vec3<S>(S(0), S(0), S(-156))).status, Status::Ok);
  const auto before = f.state();
  EXPECT_EQ(f.predict(Vec3<S>(S(0.1), S(35), S(0)), S(0.01)), Status::Saturated);
  EXPECT_EQ(f.predict(Vec3<S>(S(-40), S(0), S(0)), S(0.01)), Status::Saturated);
  EXPECT_EQ(f.update_acc(Vec3<S>(S(156.9), S(0), S(-9))).status, Status::Saturated);
  EXPECT_EQ(f.update_acc(Vec3<S>(S(0), S(0), S(-200))).status, Status::Saturated);
  // Non-finite input is reported as such, not as saturated.
  EXPECT_EQ(f.predict(Vec3<S>(std::numeric_limits<S>::infinity(), S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_TRUE(FuzzAdapter<F>::same(before, f.state()));
}

TEST(Saturation, QuaternionEKF) {
  expect_saturation_reported<QuaternionEKF<double>>();
  expect_saturation_reported<QuaternionEKF<float>>();
  QuaternionEKFParams<double> p;
  p.acc_range = 100;
  QuaternionEKF<double> f(p);
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  const auto before = f.state();
  EXPECT_EQ(f.update_acc_mag(Vec3<double>(0, 120, -9.8), Vec3<double>(20, 0, 40)).status, Status::Saturated);
  EXPECT_TRUE(FuzzAdapter<QuaternionEKF<double>>::same(before, f.state()));
}
TEST(Saturation, EulerEKF) {
  expect_saturation_reported<EulerEKF<double>>();
  expect_saturation_reported<EulerEKF<float>>();
}

TEST(Saturation, BatchFlagsAndSkips) {
  QuaternionEKFParams<double> p;
  p.gyro_range = 10;
  p.acc_range = 50;
  QuaternionEKF<double> f(p);
  const int n = 6;
  std::vector<double> gyr(3 * n, 0.0), acc(3 * n, 0.0), dt(n, 0.01), q(4 * n);
  std::vector<std::uint32_t> fl(n);
  for (int k = 0; k < n; ++k) acc[3 * k + 2] = -9.81;
  gyr[3 * 2 + 1] = 12;    // row 2: gyro saturated
  acc[3 * 4 + 0] = -60;   // row 4: accelerometer saturated
  double* none = nullptr;
  run_attitude_batch(f, gyr.data(), acc.data(), static_cast<const double*>(nullptr), dt.data(), std::size_t(n),
                     q.data(), none, none, none, fl.data());
  for (int k = 0; k < n; ++k) {
    const bool sat = k == 2 || k == 4;
    EXPECT_EQ((fl[k] & flags::kSaturated) != 0, sat) << "row " << k;
  }
  EXPECT_TRUE(fl[2] & flags::kPredictSkipped);
  EXPECT_FALSE(fl[2] & flags::kAccSkipped);
  EXPECT_TRUE(fl[4] & flags::kAccSkipped);
  EXPECT_FALSE(fl[4] & flags::kPredictSkipped);
  // The saturated rows left the attitude as it was.
  for (int i = 0; i < 4; ++i) EXPECT_EQ(q[4 * 4 + i], q[4 * 3 + i]);
}

// --- covariance floor ------------------------------------------------------------------------
// The fixed-size Jacobi eigen-decomposition against Eigen's solver, on random symmetric matrices
// (including a repeated eigenvalue), in double and float.
template <class S, int N> void check_symmetric_eigen(std::mt19937& rng, S tol) {
  std::normal_distribution<double> nd;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix<double, N, N> B;
    for (int i = 0; i < N * N; ++i) B(i) = nd(rng);
    Eigen::Matrix<double, N, N> A = B + B.transpose();
    if (trial % 5 == 0) {  // repeated eigenvalue
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(A);
      Eigen::Matrix<double, N, 1> lam = es.eigenvalues();
      lam(1) = lam(0);
      A = es.eigenvectors() * lam.asDiagonal() * es.eigenvectors().transpose();
      A = (A + A.transpose()).eval() * 0.5;
    }
    const Mat<S, N, N> As = A.template cast<S>();
    Vec<S, N> lam;
    Mat<S, N, N> V;
    ASSERT_TRUE((detail::symmetric_eigen<S, N>(As, lam, &V)));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> ref(As.template cast<double>());
    Eigen::Matrix<double, N, 1> sorted = lam.template cast<double>();
    std::sort(sorted.data(), sorted.data() + N);
    const double scale = A.cwiseAbs().maxCoeff();
    EXPECT_LT((sorted - ref.eigenvalues()).cwiseAbs().maxCoeff(), tol * scale);
    EXPECT_LT((V.transpose() * V - Mat<S, N, N>::Identity()).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT((V * lam.asDiagonal() * V.transpose() - As).cwiseAbs().maxCoeff(), tol * scale);
  }
}

TEST(CovarianceFloor, JacobiEigenMatchesEigenSolver) {
  std::mt19937 rng(7);
  check_symmetric_eigen<double, 6>(rng, 1e-12);
  check_symmetric_eigen<double, 15>(rng, 1e-11);
  check_symmetric_eigen<float, 6>(rng, 2e-5f);
  check_symmetric_eigen<float, 15>(rng, 5e-5f);
}

TEST(CovarianceFloor, RepairsIndefiniteAndLeavesHealthyBitForBit) {
  Mat<double, 4, 4> A;
  A << 4, 1, 0.5, 0, 1, 3, 0.2, 0.1, 0.5, 0.2, 2, 0.3, 0, 0.1, 0.3, 1;
  Mat<double, 4, 4> P = A * A.transpose();
  const Mat<double, 4, 4> P0 = P;
  EXPECT_FALSE((floor_covariance<double, 4>(P, 1e-9)));
  EXPECT_TRUE(quatnav_fuzz::bits_equal(P, P0));
  // Rank-deficient and indefinite: eigenvalues {2, 1, 0, -1e-6}.
  Eigen::Matrix4d V = Eigen::Matrix4d::Identity();
  V.block<3, 3>(0, 0) = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized().toRotationMatrix();
  Mat<double, 4, 4> Q = V * Eigen::Vector4d(2, 1, 0, -1e-6).asDiagonal() * V.transpose();
  symmetrize(Q);
  const double floor = 1e-9;
  EXPECT_TRUE((floor_covariance<double, 4>(Q, floor)));
  const auto h = covariance_health<double, 4>(Q);
  EXPECT_TRUE(h.ok());
  EXPECT_GE(h.min_eig, floor * (1 - 1e-6));
  EXPECT_NEAR(h.max_eig, 2.0, 1e-12);
  EXPECT_EQ(h.asymmetry, 0.0);
  // floor <= 0 disables it.
  Mat<double, 4, 4> Qn = V * Eigen::Vector4d(2, 1, 0, -1e-6).asDiagonal() * V.transpose();
  const Mat<double, 4, 4> Qn0 = Qn;
  EXPECT_FALSE((floor_covariance<double, 4>(Qn, 0.0)));
  EXPECT_TRUE(quatnav_fuzz::bits_equal(Qn, Qn0));
}

TEST(CovarianceFloor, QuaternionEKFErrorStateKeepsStructure) {
  const Quat<double> q = quat::normalized(Quat<double>(0.7, 0.2, -0.5, 0.3));
  const Mat43<double> X = quat::xi(q);
  // Error-state covariance with a negative eigenvalue, mapped to the 7x7 quaternion form.
  Mat<double, 6, 6> Pe = Mat<double, 6, 6>::Identity() * 1e-4;
  Pe(0, 0) = -1e-8;
  Mat<double, 7, 6> Tp = Mat<double, 7, 6>::Zero();
  Tp.topLeftCorner<4, 3>() = X / 2;
  Tp.bottomRightCorner<3, 3>().setIdentity();
  Mat<double, 7, 7> P = Tp * Pe * Tp.transpose();
  symmetrize(P);
  EXPECT_TRUE(detail::qekf_floor_covariance(q, P, 1e-10));
  EXPECT_LT((P.topLeftCorner<4, 4>() * q).norm(), 1e-18);  // no variance along q (the constraint)
  const Mat3<double> Pa = detail::quat_cov_to_angle_cov(q, Mat4<double>(P.topLeftCorner<4, 4>()));
  EXPECT_NEAR(Pa(0, 0), 1e-10, 1e-16);
  EXPECT_NEAR(Pa(1, 1), 1e-4, 1e-16);
  // A healthy, symmetric P is untouched bit for bit.
  const Mat<double, 7, 7> P1 = P;
  EXPECT_FALSE(detail::qekf_floor_covariance(q, P, 1e-10));
  EXPECT_TRUE(quatnav_fuzz::bits_equal(P, P1));
}

/// Error-state covariance of a filter: QuaternionEKF maps its 7x7 P to [dtheta, db].
template <class S> Mat<S, 6, 6> error_cov(const QuaternionEKF<S>& f) {
  Mat<S, 6, 7> T = Mat<S, 6, 7>::Zero();
  T.template topLeftCorner<3, 4>() = S(2) * quat::xi(f.quat()).transpose();
  T.template bottomRightCorner<3, 3>().setIdentity();
  return T * f.covariance() * T.transpose();
}
template <class S> Mat<S, 6, 6> error_cov(const EulerEKF<S>& f) { return f.covariance(); }

/// Forced near-singular case: float32, measurement noise 1e-5 (far below what the data has),
/// a fixed attitude: the covariance collapses towards rounding level. Returns the smallest
/// eigenvalue of the error-state covariance seen after any step, and checks symmetry.
template <class F> double near_singular_run(typename F::Scalar floor, int steps) {
  using S = typename F::Scalar;
  typename F::Params p;
  p.acc_noise = S(1e-5);
  p.mag_noise = S(1e-5);
  p.gyro_noise = S(1e-6);
  p.gyro_bias_noise = S(1e-9);
  p.cov_floor = floor;
  F f(p);
  const Quat<double> qt = quat::from_euler(0.3, -0.2, 1.0);
  const Vec3<S> acc = quat::rotate_inv(qt, Vec3<double>(0, 0, -9.81)).template cast<S>();
  const Vec3<S> mag = quat::rotate_inv(qt, Vec3<double>(25, 0, 43.3)).template cast<S>();
  EXPECT_EQ(f.initialize(acc, mag), Status::Ok);
  double min_eig = 1e300;
  for (int k = 0; k < steps; ++k) {
    f.predict(Vec3<S>(S(1e-4), S(0), S(0)), S(0.01));
    f.update_acc(acc);
    f.update_mag(mag);
    // The filter keeps its own P exactly symmetric; the eigenvalues are those of the
    // (symmetric part of the) error-state covariance.
    EXPECT_TRUE(f.covariance() == f.covariance().transpose()) << "step " << k;
    const auto h = covariance_health<S, 6>(error_cov(f));
    EXPECT_TRUE(h.finite);
    min_eig = std::min(min_eig, double(h.min_eig));
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_TRUE(f.quat().allFinite());
  return min_eig;
}

TEST(CovarianceFloor, ForcedNearSingularStaysPositiveDefinite) {
  const float floor = 1e-12f;
  EXPECT_GE(near_singular_run<QuaternionEKF<float>>(floor, 3000), 0.99 * floor);
  EXPECT_GE(near_singular_run<EulerEKF<float>>(floor, 3000), 0.99 * floor);
  EXPECT_GE(near_singular_run<QuaternionEKF<double>>(1e-12, 3000), 0.99e-12);
}

// --- refused states --------------------------------------------------------------------------
TEST(RefusedState, MalformedCovarianceAndQuaternion) {
  QuaternionEKF<double> f;
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  const auto before = f.state();
  auto s = before;
  s.P(0, 1) += 1e-9;  // not symmetric
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.P(5, 5) = -1e-6;  // negative variance
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  EXPECT_EQ(f.reset(before.q, before.bias, s.P), Status::InvalidArgument);
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(f.reset(Quat<double>(big, big, 0, 0), before.bias, before.P), Status::InvalidArgument);
  EXPECT_TRUE(FuzzAdapter<QuaternionEKF<double>>::same(before, f.state()));

  EulerEKF<double> e;
  ASSERT_EQ(e.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  const auto eb = e.state();
  auto es = eb;
  es.P(2, 3) = 1;  // asymmetric
  EXPECT_EQ(e.set_state(es), Status::InvalidArgument);
  es = eb;
  es.P(1, 1) = -1;
  EXPECT_EQ(e.reset(eb.euler, eb.bias, es.P), Status::InvalidArgument);
  EXPECT_TRUE(FuzzAdapter<EulerEKF<double>>::same(eb, e.state()));
}

template <class F> void expect_failed_mag_update_keeps_reference(const typename F::Params& p = {}) {
  // An indefinite (but symmetric, non-negative diagonal) covariance makes S = H P H^T + R
  // indefinite: the solve fails, and the field reference must not have learned the sample.
  // (The full 3-vector field update: the scalar heading-only update can stay solvable.)
  F f(p);
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  auto s = f.state();
  s.P.setZero();
  s.P.template topLeftCorner<3, 3>() << 1, 5, 5, 5, 1, 5, 5, 5, 1;
  ASSERT_EQ(f.set_state(s), Status::Ok);
  const auto before = f.state();
  const auto r = f.update_mag(Vec3<double>(20, 3, 40));
  EXPECT_NE(r.status, Status::Ok);
  EXPECT_TRUE(FuzzAdapter<F>::same(before, f.state()));
}

TEST(RefusedState, FailedMagUpdateLeavesFieldReference) {
  expect_failed_mag_update_keeps_reference<QuaternionEKF<double>>(QuaternionEKFParams<double>::paper());
  expect_failed_mag_update_keeps_reference<EulerEKF<double>>();
}

TEST(NoHeap, FloorAndSaturationChecks) {
  QuaternionEKFParams<double> p;
  p.gyro_range = 1;
  p.cov_floor = 1e-3;  // high enough to be applied at every step
  QuaternionEKF<double> f(p);
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 10; ++k) {
    f.predict(Vec3<double>(0.1, 0, 0), 0.01);
    f.predict(Vec3<double>(2, 0, 0), 0.01);
    f.update_acc(Vec3<double>(0, 0, -9.8));
  }
  Mat<double, 6, 6> P = Mat<double, 6, 6>::Identity();
  P(0, 0) = -1;
  floor_covariance<double, 6>(P, 1e-6);
  (void)covariance_health<double, 6>(P);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_GE(P(0, 0), 1e-6 * 0.99);
}

// --- the navigation filters ------------------------------------------------------------------
template <class S> Mat<S, 13, 13> nav13_P0() {
  Mat<S, 13, 13> P = Mat<S, 13, 13>::Zero();
  P.diagonal() << S(0.01), S(0.01), S(0.01), S(1e-4), S(1e-4), S(1e-4), S(1e-4), S(1e-3), S(1e-3), S(1e-3), S(1e-5),
      S(1e-5), S(1e-5);
  return P;
}

template <class F> void nav13_bad_input() {
  using S = typename F::Scalar;
  typename F::Params p;
  p.gyro_range = S(35);
  p.acc_range = S(156.9);
  p.max_dt = S(0.5);
  F f(p);
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  const Vec3<S> fb(S(0.1), S(-0.2), S(-9.8)), wb(S(0.01), S(0.02), S(-0.01));
  EXPECT_EQ(f.predict(fb, wb, S(0.01)), Status::NotInitialized);
  ASSERT_EQ(f.reset(Vec3<S>(S(1), S(0), S(0)), quat::from_euler(S(0.1), S(0.2), S(0.3)), Vec3<S>::Zero(),
                    Vec3<S>::Zero(), nav13_P0<S>(), S(0.6), S(0.2), S(100)),
            Status::Ok);
  ASSERT_EQ(f.predict(fb, Vec3<S>(S(0), S(34.9), S(0)), S(0.01)), Status::Ok);
  const auto before = f.state();
  EXPECT_EQ(f.predict(Vec3<S>(nan, S(0), S(0)), wb, S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(fb, Vec3<S>(S(0), inf, S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(fb, wb, S(0)), Status::InvalidDt);
  EXPECT_EQ(f.predict(fb, wb, S(-0.01)), Status::InvalidDt);
  EXPECT_EQ(f.predict(fb, wb, nan), Status::InvalidDt);
  EXPECT_EQ(f.predict(fb, wb, S(0.6)), Status::InvalidDt);
  EXPECT_EQ(f.predict(fb, Vec3<S>(S(0), S(-35), S(0)), S(0.01)), Status::Saturated);
  EXPECT_EQ(f.predict(Vec3<S>(S(0), S(0), S(-160)), wb, S(0.01)), Status::Saturated);
  EXPECT_EQ(f.update_velocity(Vec3<S>(nan, S(0), S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_yaw(inf).status, Status::NonFinite);
  EXPECT_EQ(f.update_velocity_yaw(Vec3<S>::Zero(), nan).status, Status::NonFinite);
  // A huge velocity overflows the correction (float) or leaves it finite (double); never stored non-finite.
  const auto r = f.update_velocity(Vec3<S>::Constant(std::numeric_limits<S>::max()));
  if (r.status != Status::Ok) EXPECT_TRUE(FuzzAdapter<F>::same(before, f.state()));
  else EXPECT_TRUE(f.state().v_n.allFinite());
  ASSERT_EQ(f.set_state(before), Status::Ok);
  // Malformed states are refused.
  auto s = before;
  s.P(0, 1) += S(1e-3);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.P(8, 8) = S(-1);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.q_nb *= S(2);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.lat = S(1.6);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  const S big = std::numeric_limits<S>::max();
  EXPECT_EQ(f.reset(Vec3<S>::Zero(), Quat<S>(big, big, S(0), S(0)), Vec3<S>::Zero(), Vec3<S>::Zero(), nav13_P0<S>(),
                    S(0.6), S(0.2), S(100)),
            Status::InvalidArgument);
  EXPECT_TRUE(FuzzAdapter<F>::same(before, f.state()));
  // An indefinite P makes the velocity solve fail: SolveFailed, state kept.
  s = before;
  s.P.template topLeftCorner<3, 3>() << S(1), S(5), S(5), S(5), S(1), S(5), S(5), S(5), S(1);
  ASSERT_EQ(f.set_state(s), Status::Ok);
  const auto b2 = f.state();
  EXPECT_EQ(f.update_velocity(Vec3<S>(S(1), S(0), S(0))).status, Status::SolveFailed);
  EXPECT_TRUE(FuzzAdapter<F>::same(b2, f.state()));
}

TEST(NavFilter13Robust, BadInputRefusedStateKept) {
  nav13_bad_input<NavFilter13<double, TimeUpdate::Ekf>>();
  nav13_bad_input<NavFilter13<float, TimeUpdate::Ekf>>();
  nav13_bad_input<NavFilter13<double, TimeUpdate::SecondOrder>>();
  nav13_bad_input<NavFilter13<float, TimeUpdate::SecondOrder>>();
  nav13_bad_input<NavFilter13<double, TimeUpdate::Ukf>>();
  nav13_bad_input<NavFilter13<float, TimeUpdate::Ukf>>();
}

TEST(NavFilter13Robust, BatchFlagsSaturation) {
  NavFilter13Params<double> p;
  p.gyro_range = 10;
  NavFilter13<double> f(p);
  ASSERT_EQ(f.reset(Vec3<double>::Zero(), quat::identity<double>(), Vec3<double>::Zero(), Vec3<double>::Zero(),
                    nav13_P0<double>(), 0.6, 0.2, 100),
            Status::Ok);
  const int n = 5;
  std::vector<double> fb(3 * n, 0.0), wb(3 * n, 0.0), t(n), dt(n, 0.01), x(13 * n);
  std::vector<std::uint32_t> fl(n);
  for (int k = 0; k < n; ++k) {
    fb[3 * k + 2] = -9.8;
    t[k] = 0.01 * (k + 1);
  }
  wb[3 * 2] = 11;  // row 2 saturated
  run_nav13_batch<NavFilter13<double>, double>(f, fb.data(), wb.data(), t.data(), dt.data(), std::size_t(n), nullptr, nullptr, 0, nullptr,
                  nullptr, 0, 0.0, 0.0, x.data(), nullptr, nullptr, nullptr, fl.data(), nullptr, nullptr, nullptr,
                  nullptr, nullptr, nullptr);
  for (int k = 0; k < n; ++k) EXPECT_EQ((fl[k] & flags::kSaturated) != 0, k == 2) << k;
  EXPECT_TRUE(fl[2] & flags::kPredictSkipped);
  for (int i = 0; i < 13; ++i) EXPECT_EQ(x[13 * 2 + i], x[13 * 1 + i]);
}

/// Forced near-singular case: velocity and yaw noise 1e-4, no process noise on the biases, the
/// vehicle at rest: the error-state covariance collapses towards rounding level (float32 without
/// the floor: eigenvalues of -3e-2, failed updates or failed sigma-point Cholesky factors). With
/// the floor its smallest eigenvalue stays >= the floor; P stays exactly symmetric and finite.
/// The eigenvalues are those of the stored P, computed in double (a float32 eigen-solver's own
/// rounding, about eps32 * max eigenvalue = 1e-10 here, would hide what is measured).
template <class S, TimeUpdate TU> double nav13_near_singular(S floor, int steps, int stride = 10) {
  NavFilter13Params<S> p;
  p.vel_noise = S(1e-4);
  p.yaw_noise = S(1e-4);
  p.cov_floor = floor;
  NavFilter13<S, TU> f(p);
  const Quat<S> q = quat::from_euler(S(0.1), S(-0.05), S(0.4));
  EXPECT_EQ(f.reset(Vec3<S>::Zero(), q, Vec3<S>::Zero(), Vec3<S>::Zero(), nav13_P0<S>(), S(0.6), S(0.2), S(100)),
            Status::Ok);
  const Vec3<S> g_n = earth::gravity_n(S(0.6), S(100));
  const Vec3<S> fb = quat::rotate_inv(q, Vec3<S>(-g_n)), wb = quat::rotate_inv(q, earth::earth_rate_n(S(0.6)));
  double min_eig = 1e300;
  for (int k = 0; k < steps; ++k) {
    const Status sp = f.predict(fb, wb, S(0.01));
    if (floor > S(0)) EXPECT_EQ(sp, Status::Ok);  // without the floor the UKF's Cholesky fails
    f.update_velocity_yaw(Vec3<S>::Zero(), S(0.4));
    f.set_position(S(0.6), S(0.2), S(100));
    EXPECT_TRUE(f.covariance() == f.covariance().transpose()) << "step " << k;
    if (k % stride != stride - 1) continue;  // a 12x12 Jacobi per step is slow under ASan
    const Mat<double, 12, 13> T = detail::nav13_to_error<double>(f.state().q_nb.template cast<double>());
    const Mat<double, 12, 12> Pe =
        fixed_mul(fixed_mul(T, Mat<double, 13, 13>(f.covariance().template cast<double>())), T.transpose());
    const auto h = covariance_health<double, 12>(Pe);
    EXPECT_TRUE(h.finite);
    min_eig = std::min(min_eig, double(h.min_eig));
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  NavFilter13<%s> %s, floor %g, %d steps: smallest error-state eigenvalue %.2e\n", to_string(TU),
              sizeof(S) == 4 ? "float32" : "float64", double(floor), steps, min_eig);
  return min_eig;
}

// The float32 floor is 1e-9, not 1e-12: with the largest error-state eigenvalue at 1e-3 here,
// float32 resolves eigenvalues only to about eps32 * 1e-3 = 1.2e-10 (the Cholesky test that
// decides whether to floor has that backward error), so a floor of 1e-12 cannot be held in
// float32 (measured: -3e-12 with it, i.e. rounding level). Each case is first run without the
// floor to show that it does collapse below the floor.
TEST(CovarianceFloor, NavFilter13ForcedNearSingular) {
  const float ff = 1e-9f;
  EXPECT_LT((nav13_near_singular<float, TimeUpdate::Ekf>(0.0f, 3000)), 0.0);
  EXPECT_GE((nav13_near_singular<float, TimeUpdate::Ekf>(ff, 3000)), 0.99 * ff);
  // The unscented update repairs a sigma-point factor that round-off made indefinite (an
  // eigenvalue floor of 64 eps on the correlation scale, unscented.hpp), so without cov_floor
  // it stays positive but far below the floor.
  EXPECT_LT((nav13_near_singular<float, TimeUpdate::Ukf>(0.0f, 1000)), 1e-3 * ff);
  EXPECT_GE((nav13_near_singular<float, TimeUpdate::Ukf>(ff, 1000)), 0.99 * ff);
  // float64: every step (the dips below 1e-12 are short and a 10-step stride can miss them).
  EXPECT_LT((nav13_near_singular<double, TimeUpdate::Ekf>(0.0, 1000, 1)), 1e-12);
  EXPECT_GE((nav13_near_singular<double, TimeUpdate::Ekf>(1e-12, 1000, 1)), 0.99e-12);
}

template <class S> void gpsins_bad_input() {
  GpsInsParams<S> p;
  p.gyro_range = S(35);
  p.acc_range = S(156.9);
  p.max_dt = S(0.5);
  GpsInsFilter<S> f(p);
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  const Vec3<S> fb(S(0.1), S(-0.2), S(-9.8)), wb(S(0.01), S(0.02), S(-0.01)), nan3 = Vec3<S>::Constant(nan);
  ASSERT_EQ(f.initialize(quat::from_euler(S(0.1), S(0.2), S(0.3)), Vec3<S>(S(1), S(0), S(0)), 0.6, 0.2, 100.0,
                         Vec3<S>::Zero(), Vec3<S>::Zero(), f.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5))),
            Status::Ok);
  ASSERT_EQ(f.predict(wb, fb, S(0.01)), Status::Ok);
  ASSERT_EQ(f.update_baro(100.0).height.status, Status::Ok);
  const auto before = f.state();
  using A = FuzzAdapter<GpsInsFilter<S>>;
  EXPECT_EQ(f.predict(Vec3<S>(nan, S(0), S(0)), fb, S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(wb, Vec3<S>(S(0), inf, S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(wb, fb, S(0)), Status::InvalidDt);
  EXPECT_EQ(f.predict(wb, fb, S(-1)), Status::InvalidDt);
  EXPECT_EQ(f.predict(wb, fb, nan), Status::InvalidDt);
  EXPECT_EQ(f.predict(wb, fb, S(0.6)), Status::InvalidDt);
  EXPECT_EQ(f.predict(Vec3<S>(S(0), S(0), S(35)), fb, S(0.01)), Status::Saturated);
  EXPECT_EQ(f.predict(wb, Vec3<S>(S(-157), S(0), S(0)), S(0.01)), Status::Saturated);
  EXPECT_EQ(f.update_gps_position(std::nan(""), 0.2, 100.0, nan3).status, Status::NonFinite);
  EXPECT_EQ(f.update_gps_position(0.6, 0.2, 100.0, Vec3<S>(S(-1), S(1), S(1))).status, Status::InvalidArgument);
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(S(0), nan, S(0)), nan3).status, Status::NonFinite);
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>::Zero(), Vec3<S>(S(0), S(1), S(1))).status, Status::InvalidArgument);
  EXPECT_EQ(f.update_baro(std::numeric_limits<double>::infinity()).height.status, Status::NonFinite);
  EXPECT_EQ(f.update_compass(nan).status, Status::NonFinite);
  // A fix far beyond the float range: the correction cannot be computed; the altimeter-offset
  // tracking of the fix is undone too.
  const auto g = f.update_gps_position(0.6, 0.2, 1e300, nan3);
  EXPECT_NE(g.status, Status::Ok);
  if (g.status != Status::Rejected) {
    EXPECT_TRUE(A::same(before, f.state()));
  }
  EXPECT_TRUE(A::same(before, f.state()) || g.status == Status::Rejected);
  ASSERT_EQ(f.set_state(before), Status::Ok);
  // Malformed states.
  auto s = before;
  s.P(0, 1) += S(1e-3);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.P(4, 4) = S(-1);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.nav.q_nb *= S(3);
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.nav.lat = std::nan("");
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  const S big = std::numeric_limits<S>::max();
  EXPECT_EQ(f.initialize(Quat<S>(big, big, S(0), S(0)), Vec3<S>::Zero(), 0.6, 0.2, 100.0, Vec3<S>::Zero(),
                         Vec3<S>::Zero(), before.P),
            Status::InvalidArgument);
  EXPECT_TRUE(A::same(before, f.state()));
  // An indefinite P: the GPS velocity solve fails, state kept.
  s = before;
  s.P.template block<3, 3>(3, 3) << S(1), S(5), S(5), S(5), S(1), S(5), S(5), S(5), S(1);
  ASSERT_EQ(f.set_state(s), Status::Ok);
  const auto b2 = f.state();
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(S(1), S(0), S(0)), nan3).status, Status::SolveFailed);
  EXPECT_TRUE(A::same(b2, f.state()));
}

TEST(GpsInsRobust, BadInputRefusedStateKept) {
  gpsins_bad_input<double>();
  gpsins_bad_input<float>();
}

/// Forced near-singular case for the GPS/INS filter: GPS sigmas 1e-3 m and 1e-4 m/s, altimeter
/// 1e-3 m, compass 1e-5 rad, tiny process noise, at rest (float32 without the floor: an
/// eigenvalue of -1.5e6): with the floor the smallest eigenvalue of P (computed in double) stays
/// >= the floor, P exactly symmetric and finite.
template <class S> double gpsins_near_singular(S floor, int steps) {
  GpsInsParams<S> p;
  p.gyro_noise = S(1e-6);
  p.accel_noise = S(1e-6);
  p.gyro_bias_rw = S(1e-9);
  p.accel_bias_rw = S(1e-9);
  p.baro_sigma = S(1e-3);
  p.compass_sigma = S(1e-5);
  p.gate_gps_pos = p.gate_gps_vel = p.gate_baro = p.gate_compass = S(0);
  p.cov_floor = floor;
  GpsInsFilter<S> f(p);
  const Quat<S> q = quat::from_euler(S(0.1), S(-0.05), S(0.4));
  EXPECT_EQ(f.initialize(q, Vec3<S>::Zero(), 0.6, 0.2, 100.0, Vec3<S>::Zero(), Vec3<S>::Zero(),
                         f.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5))),
            Status::Ok);
  const Vec3<double> g_n = earth::gravity_n(0.6, 100.0);
  const Vec3<S> fb = quat::rotate_inv(q, Vec3<S>(-g_n.cast<S>())), wb = quat::rotate_inv(q, earth::earth_rate_n(S(0.6)));
  double min_eig = 1e300;
  for (int k = 0; k < steps; ++k) {
    const Status sp = f.predict(wb, fb, S(0.01));
    if (floor > S(0)) EXPECT_EQ(sp, Status::Ok);
    f.update_compass(S(0.4));
    f.update_baro(100.0);
    if (k % 10 == 0) f.update_gps(0.6, 0.2, 100.0, Vec3<S>::Zero(), Vec3<S>::Constant(S(1e-3)), Vec3<S>::Constant(S(1e-4)));
    EXPECT_TRUE(f.covariance() == f.covariance().transpose()) << "step " << k;
    if (k % 10 != 9) continue;  // eigenvalues every 10th step (as above)
    const auto h = covariance_health<double, 15>(Mat<double, 15, 15>(f.covariance().template cast<double>()));
    EXPECT_TRUE(h.finite);
    min_eig = std::min(min_eig, double(h.min_eig));
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  GpsInsFilter %s, floor %g, %d steps: smallest eigenvalue of P %.2e\n",
              sizeof(S) == 4 ? "float32" : "float64", double(floor), steps, min_eig);
  return min_eig;
}

// float32: floor 1e-8 (the largest eigenvalue is 1e-2 here, float32 resolves about 1.2e-9; a
// floor of 1e-12 measured -7.7e-12, rounding level), as for NavFilter13 above.
TEST(CovarianceFloor, GpsInsForcedNearSingular) {
  EXPECT_LT(gpsins_near_singular<float>(0.0f, 2000), 0.0);
  EXPECT_GE(gpsins_near_singular<float>(1e-8f, 2000), 0.99e-8);
  EXPECT_LT(gpsins_near_singular<double>(0.0, 1000), 1e-12);
  EXPECT_GE(gpsins_near_singular<double>(1e-12, 1000), 0.99e-12);
}
