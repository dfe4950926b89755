// test_robustness: QuaternionEKF, QuaternionEKFPaper and EulerEKF (robustness.hpp).
#include "robustness.hpp"

TEST(FaultSequences, QuaternionEKF) {
  random_fault_sequences<QuaternionEKF<double>>(5, 300);
  random_fault_sequences<QuaternionEKF<float>>(6, 300);
}

TEST(FaultSequences, QuaternionEKFPaper) {
  random_fault_sequences<QuaternionEKFPaper<double>>(1, 300);
  random_fault_sequences<QuaternionEKFPaper<float>>(2, 300);
}
TEST(FaultSequences, EulerEKF) {
  random_fault_sequences<EulerEKF<double>>(3, 300);
  random_fault_sequences<EulerEKF<float>>(4, 300);
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

TEST(Saturation, QuaternionEKFPaper) {
  expect_saturation_reported<QuaternionEKFPaper<double>>();
  expect_saturation_reported<QuaternionEKFPaper<float>>();
  QuaternionEKFParams<double> p;
  p.acc_range = 100;
  QuaternionEKFPaper<double> f(p);
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  const auto before = f.state();
  EXPECT_EQ(f.update_acc_mag(Vec3<double>(0, 120, -9.8), Vec3<double>(20, 0, 40)).status, Status::Saturated);
  EXPECT_TRUE(FuzzAdapter<QuaternionEKFPaper<double>>::same(before, f.state()));
}
TEST(Saturation, EulerEKF) {
  expect_saturation_reported<EulerEKF<double>>();
  expect_saturation_reported<EulerEKF<float>>();
}

TEST(Saturation, BatchFlagsAndSkips) {
  QuaternionEKFParams<double> p;
  p.gyro_range = 10;
  p.acc_range = 50;
  QuaternionEKFPaper<double> f(p);
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

// --- covariance floor (covariance.cpp: the floor itself) -----------------------------------
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
  const Mat3<double> Pa = QuatBlock<double, 7, 0>::attitude_covariance(q, P);
  EXPECT_NEAR(Pa(0, 0), 1e-10, 1e-16);
  EXPECT_NEAR(Pa(1, 1), 1e-4, 1e-16);
  // A healthy, symmetric P is untouched bit for bit.
  const Mat<double, 7, 7> P1 = P;
  EXPECT_FALSE(detail::qekf_floor_covariance(q, P, 1e-10));
  EXPECT_TRUE(quatnav_fuzz::bits_equal(P, P1));
}

/// Error-state covariance of a filter: QuaternionEKFPaper maps its 7x7 P to [dtheta, db].
template <class S> Mat<S, 6, 6> error_cov(const QuaternionEKFPaper<S>& f) {
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
  p.acc_sigma = S(1e-5);
  p.mag_sigma = S(1e-5);
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
  QUATNAV_SKIP_NUMERICAL_UNDER_SANITIZERS();
  const float floor = 1e-12f;
  EXPECT_GE(near_singular_run<QuaternionEKFPaper<float>>(floor, 3000), 0.99 * floor);
  EXPECT_GE(near_singular_run<EulerEKF<float>>(floor, 3000), 0.99 * floor);
  EXPECT_GE(near_singular_run<QuaternionEKFPaper<double>>(1e-12, 3000), 0.99e-12);
}

// --- refused states --------------------------------------------------------------------------
TEST(RefusedState, MalformedCovarianceAndQuaternion) {
  QuaternionEKFPaper<double> f;
  ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  const auto before = f.state();
  auto s = before;
  s.P(0, 1) += 1e-9;  // not symmetric
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  s = before;
  s.P(5, 5) = -1e-6;  // negative variance
  EXPECT_EQ(f.set_state(s), Status::InvalidArgument);
  EXPECT_EQ(f.reset(before.q_nb, before.gyro_bias, s.P), Status::InvalidArgument);
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(f.reset(Quat<double>(big, big, 0, 0), before.gyro_bias, before.P), Status::InvalidArgument);
  EXPECT_TRUE(FuzzAdapter<QuaternionEKFPaper<double>>::same(before, f.state()));

  EulerEKF<double> e;
  ASSERT_EQ(e.initialize(Vec3<double>(0, 0, -9.8), Vec3<double>(20, 0, 40)), Status::Ok);
  const auto eb = e.state();
  auto es = eb;
  es.P(2, 3) = 1;  // asymmetric
  EXPECT_EQ(e.set_state(es), Status::InvalidArgument);
  es = eb;
  es.P(1, 1) = -1;
  EXPECT_EQ(e.reset(eb.euler, eb.gyro_bias, es.P), Status::InvalidArgument);
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
  expect_failed_mag_update_keeps_reference<QuaternionEKFPaper<double>>(QuaternionEKFParams<double>::paper());
  expect_failed_mag_update_keeps_reference<EulerEKF<double>>();
}

TEST(NoHeap, FloorAndSaturationChecks) {
  QuaternionEKFParams<double> p;
  p.gyro_range = 1;
  p.cov_floor = 1e-3;  // high enough to be applied at every step
  QuaternionEKFPaper<double> f(p);
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

// --- every state a filter keeps is one set_state takes back ------------------------------------
// FuzzAdapter::healthy ends with that check (a fresh filter with the same parameters accepts the
// state); the fault replay above found these causes, one test each, the shortest sequence of calls
// that shows it. Each failed before its fix.

/// A reading with finite components whose norm overflows (|v|^2 beyond the largest S): its unit
/// vector was v / inf = 0 and the update went on, leaving the accelerometer low-pass's deviation
/// (replay: QuaternionEKF seed 5, input 49: a low-passed sample, then this one: the low-pass of
/// v dt / acc_lp_tau has a finite norm, its raw deviation |v| - g is infinite) or the magnetometer
/// part's reference norm (float, seed 6, input 562: initialize, predict, update_mag) infinite.
/// Refused now as a non-finite input (detail::unit_vector), nothing changed.
template <class F> void reading_norm_overflow() {
  using S = typename F::Scalar;
  typename F::Params p;
  if constexpr (!std::is_same_v<F, EulerEKF<S>>) p.mag_heading_only = false;  // the 3-row update
  F f(p);
  const Vec3<S> g(S(0.3), S(-0.2), S(-9.8)), w(S(0.1), S(0), S(0));
  ASSERT_EQ(f.initialize(g), Status::Ok);
  ASSERT_EQ(f.predict(w, S(0.01)), Status::Ok);
  ASSERT_EQ(f.update_acc(g).status, Status::Ok);
  ASSERT_EQ(f.predict(w, S(0.01)), Status::Ok);
  const auto before = f.state();
  const Vec3<S> huge(sizeof(S) == 4 ? S(1e20f) : S(1e155), S(0.3), S(-9.8));  // |v|^2 > max(S)
  expect_refused_kept(f, before, f.update_acc(huge).status, Status::NonFinite);
  expect_refused_kept(f, before, f.update_mag(huge).status, Status::NonFinite);
  expect_healthy(f);
}

/// The level state of an attitude filter with the covariance P (reset).
template <class F, class P_t> Status reset_level(F& f, const P_t& P) {
  using S = typename F::Scalar;
  if constexpr (std::is_same_v<F, EulerEKF<S>>)
    return f.reset(Vec3<S>::Zero(), Vec3<S>::Zero(), P);
  else
    return f.reset(quat::identity<S>(), Vec3<S>::Zero(), P);
}

/// A level filter's covariance (attitude variance a, gyro-bias variance b on the diagonal) with
/// the tilt about x and the gyro bias about x correlated by c: indefinite when c^2 > a b, as
/// set_state and reset take it (they check the diagonal, not the eigenvalues). Row/column of the
/// tilt about x and of the bias about x: 0 and 3 in the 6-state filters, q_x (1, where the
/// quaternion block is a / 4 Xi Xi^T at identity) and 4 in QuaternionEKFPaper.
template <class F> Mat<typename F::Scalar, F::kStates, F::kStates> correlated_P(double a, double b, double c) {
  using S = typename F::Scalar;
  constexpr int N = F::kStates, kTilt = N == 7 ? 1 : 0, kBias = N == 7 ? 4 : 3;
  Mat<S, N, N> P = Mat<S, N, N>::Zero();
  if constexpr (N == 7) {
    const Mat43<S> X = quat::xi(quat::identity<S>());
    P.template topLeftCorner<4, 4>() = S(a / 4) * X * X.transpose();
  } else {
    P.diagonal().template head<3>().setConstant(S(a));
  }
  P.diagonal().template tail<3>().setConstant(S(b));
  P(kTilt, kBias) = P(kBias, kTilt) = S(c);
  return P;
}

/// The papers' filters (parts off) without the covariance floor, which would repair an
/// indefinite P: what the filter commits is then the correction's or the time update's own.
template <class F> F unfloored() {
  typename F::Params p = F::Params::paper();
  p.cov_floor = 0;
  return F(p);
}

/// A correction whose covariance loses its non-negative diagonal was committed (replay: every
/// filter, e.g. QuaternionEKF seed 5, input 103: reset with an indefinite P, update_acc; in float
/// also P ill-conditioned beyond the precision, 115 of QuaternionEKF float's 305 failing inputs
/// after update_acc_mag): refused now. Tilt variance 1e-2, bias variance 1e-6, their covariance
/// 1e-2 (correlation 100): the accelerometer observes the tilt, and the bias variance becomes
/// 1e-6 - (1e-2)^2 / (1e-2 + r) < 0 for the accelerometer's r = acc_sigma^2 (below 0.16 in every
/// filter's paper() parameters, so below -5e-4).
template <class F> void correction_loses_psd() {
  using S = typename F::Scalar;
  F f = unfloored<F>();
  ASSERT_EQ(reset_level(f, correlated_P<F>(1e-2, 1e-6, 1e-2)), Status::Ok);
  const auto before = f.state();
  expect_refused_kept(f, before, f.update_acc(Vec3<S>(S(0.3), S(-0.2), S(-9.8))).status, Status::NumericalFailure);
  expect_healthy(f);
}

/// A time update that propagates an indefinite P to a negative variance was committed (replay:
/// QuaternionEKF seed 5, input 88: set_state, predict): refused now. Tilt and bias variance 1e-6,
/// their covariance 1e-2: the tilt about x integrates -dt times the bias about x (-dt / 2 in the
/// quaternion of QuaternionEKFPaper), so its variance becomes about 1e-6 - 2 dt 1e-2 = -2e-4 at
/// dt = 0.01 (-1e-4 in the quaternion), beyond the process noise dt gyro_noise^2 (<= 1e-5).
template <class F> void time_update_loses_psd() {
  using S = typename F::Scalar;
  F f = unfloored<F>();
  ASSERT_EQ(reset_level(f, correlated_P<F>(1e-6, 1e-6, 1e-2)), Status::Ok);
  const auto before = f.state();
  expect_refused_kept(f, before, f.predict(Vec3<S>::Zero(), S(0.01)), Status::NumericalFailure);
  expect_healthy(f);
}

#define QUATNAV_ATTITUDE_CONTRACT_TEST(NAME, FN) \
  TEST(AttitudeContract, NAME) {                 \
    FN<QuaternionEKF<double>>();                 \
    FN<QuaternionEKF<float>>();                  \
    FN<QuaternionEKFPaper<double>>();            \
    FN<QuaternionEKFPaper<float>>();             \
    FN<EulerEKF<double>>();                      \
    FN<EulerEKF<float>>();                       \
  }
QUATNAV_ATTITUDE_CONTRACT_TEST(ReadingNormOverflowRefused, reading_norm_overflow)
QUATNAV_ATTITUDE_CONTRACT_TEST(CorrectionLosingPsdRefused, correction_loses_psd)
QUATNAV_ATTITUDE_CONTRACT_TEST(TimeUpdateLosingPsdRefused, time_update_loses_psd)

/// EulerEKF: a rate whose rotation over the step overflows the accelerometer part's frame (the
/// Euler angles wrap, the part's quaternion exp((w - b) dt) does not: |w dt|^2 overflows) left
/// that frame NaN after an Ok step (replay: seed 3, input 1972: initialize, predict). Refused
/// now. At level the rate about x moves only the roll (E's first column is e_x), so paper 004's
/// Euler step and its covariance stay finite and only the part overflows.
template <class S> void euler_rate_overflows_acc_frame() {
  EulerEKFParams<S> p;
  p.exact_propagation = false;  // the exact step's own quaternion overflows too (and was refused)
  EulerEKF<S> f(p);
  ASSERT_GT(f.params().acc.acc_lp_tau, S(0));  // the part's frame is carried
  ASSERT_EQ(f.initialize(Vec3<S>(S(0), S(0), S(-9.81))), Status::Ok);
  const auto before = f.state();
  const Vec3<S> w(std::numeric_limits<S>::max() / S(2), S(0), S(0));
  expect_refused_kept(f, before, f.predict(w, S(0.01)), Status::NumericalFailure);
  expect_healthy(f);
}

TEST(AttitudeContract, EulerRateOverflowingAccFrameRefused) {
  euler_rate_overflows_acc_frame<double>();
  euler_rate_overflows_acc_frame<float>();
}

/// EulerEKF float32: a state taken by set_state whose magnetometer update returned Ok with a
/// non-finite innovation covariance (replay: seed 4, input 18861; found by a replay ten times the
/// default length). Refused now: an accepted update reports finite outputs.
TEST(AttitudeContract, EulerUpdateWithNonFiniteOutputsRefused) { replay_input<EulerEKF<float>>(4, 18861); }
