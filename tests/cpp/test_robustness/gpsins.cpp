// test_robustness: GpsInsFilter, with and without scale-factor states (robustness.hpp); the
// NavFilter13 tests are in nav13.cpp.
#include "robustness.hpp"

// As many inputs as every other filter (kFaultInputsScale). Each cause the longer replay found has
// a focused test below (GpsInsContract), the shortest sequence of calls that showed it.
TEST(FaultSequences, GpsInsFilter) {
  random_fault_sequences<GpsInsFilter<double>>(17, 300);
  random_fault_sequences<GpsInsFilter<float>>(18, 300);
}

TEST(FaultSequences, GpsInsFilterScaleFactors) {
  random_fault_sequences<GpsInsFilter<double, true>>(19, 300);
  random_fault_sequences<GpsInsFilter<float, true>>(20, 300);
}

// --- the causes the replay found, one test each ------------------------------------------------
// A step that refuses leaves the state bit for bit; one that succeeds (or records an aid before
// navigation) leaves a state set_state() takes back (FuzzAdapter::healthy: finite, P symmetric with
// a non-negative diagonal). Each failed before its fix.

template <class F> F gpsins_navigating(double h, const Mat<typename F::Scalar, F::kStates, F::kStates>* P = nullptr) {
  using S = typename F::Scalar;
  F f;
  EXPECT_EQ(f.reset(quat::identity<S>(), Vec3<S>::Zero(), 0.6, 0.2, h, Vec3<S>::Zero(), Vec3<S>::Zero(),
                    P ? *P : f.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5))),
            Status::Ok);
  return f;
}

/// The altimeter offset (its reading minus the INS height) overflowing: the first sample in
/// navigation made the offset infinite and returned Ok (replay: seed 17, input 1937, float64);
/// a sample recorded before navigation did so at the start of navigation (seed 100, input 782).
template <class F> void gpsins_baro_offset_overflow() {
  using S = typename F::Scalar;
  F f = gpsins_navigating<F>(-1e308);
  const auto before = f.state();
  expect_refused_kept(f, before, f.update_baro(1e308).height.status, Status::NumericalFailure);
  ASSERT_EQ(f.update_baro(100.0).height.status, Status::Ok);  // a sample that fits starts the offset
  EXPECT_TRUE(f.state().baro_offset_valid);
  expect_healthy(f);

  F g;
  ASSERT_EQ(g.set_initial(quat::identity<S>(), Vec3<S>::Zero(), true, Vec3<S>::Zero(), Vec3<S>::Zero()), Status::Ok);
  EXPECT_EQ(g.update_baro(1e308).height.status, Status::NotInitialized);  // recorded for the start
  EXPECT_EQ(g.update_gps_position(0.6, 0.2, -1e308, Vec3<S>::Constant(S(3))).status, Status::Ok);
  EXPECT_TRUE(g.navigating());
  EXPECT_FALSE(g.state().baro_offset_valid);  // left to the next sample
  expect_healthy(g);
}

/// Before navigation: a fix whose start of navigation is refused (here a course window that ends
/// beyond the largest latitude the filter navigates at) had recorded the window's GNSS speed on the
/// way (replay: seed 17, input 2978; seed 19, input 2621, an overflowing displacement); a velocity
/// near the float maximum recorded an infinite speed.
template <class F> void gpsins_prenav_fix_refused() {
  using S = typename F::Scalar;
  typename F::Params p;
  p.align_time = S(0.1);
  F f(p);
  const Vec3<S> w = Vec3<S>::Zero(), fb(S(0), S(0), S(-9.81));
  for (int k = 0; k < 12; ++k) ASSERT_EQ(f.predict(w, fb, S(0.01)), Status::Ok);
  ASSERT_EQ(f.phase(), GpsInsPhase::Levelled);  // levelled, no heading: the course between fixes
  const Vec3<S> sig = Vec3<S>::Constant(S(0.01));
  EXPECT_EQ(f.update_gps_position(1.57075, 0.2, 100.0, sig).status, Status::NotInitialized);  // opens the window
  for (int k = 0; k < 100; ++k) ASSERT_EQ(f.predict(w, fb, S(0.01)), Status::Ok);
  const auto before = f.state();
  // 255 m north in 1 s: the course is known, but 1.57079 rad is past detail::kGpsInsMaxAbsLat.
  expect_refused_kept(f, before, f.update_gps_position(1.57079, 0.2, 100.0, sig).status, Status::NumericalFailure);
  const S big = std::numeric_limits<S>::max();
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(big, big, S(0)), Vec3<S>::Constant(S(0.1))).status, Status::NotInitialized);
  expect_healthy(f);  // it gave the heading (heading_from_gps); its speed is not recorded:
  EXPECT_TRUE(quatnav_fuzz::bits_equal(before.gnss_speed, f.state().gnss_speed));
}

/// A correction whose Joseph-form covariance loses its non-negative diagonal (an indefinite P here,
/// as set_state and reset take it; in the replay also P ill-conditioned beyond the precision, seed
/// 100, input 4) was committed: refused now. The compass row on the yaw with the velocity north
/// correlated beyond 1: P_vv+ = P_vv - P_v,yaw^2 / (P_yaw + R) < 0.
template <class F> void gpsins_update_loses_psd() {
  using S = typename F::Scalar;
  F f0;
  Mat<S, F::kStates, F::kStates> P = f0.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5));
  P(3, 3) = S(0.01);
  P(8, 8) = S(1);
  P(3, 8) = P(8, 3) = S(0.5);
  F f = gpsins_navigating<F>(100.0, &P);
  const auto before = f.state();
  expect_refused_kept(f, before, f.update_compass(S(0)).status, Status::NumericalFailure);
  expect_healthy(f);
}

/// The time update: a rate near the range's end (no gyro_range) while aligning left the motion
/// window's rotation NaN (seed 100, input 524) and the rest low-pass infinite (seed 107, input
/// 1781); an indefinite P propagated to a negative variance. Each refused now.
template <class F> void gpsins_predict_refused() {
  using S = typename F::Scalar;
  const Vec3<S> fb(S(0), S(0), S(-9.81));
  F a;
  ASSERT_EQ(a.predict(Vec3<S>::Zero(), fb, S(0.01)), Status::Ok);
  const auto before = a.state();
  const S huge = sizeof(S) == 4 ? S(3e38f) : S(1e200);
  expect_refused_kept(a, before, a.predict(Vec3<S>(S(0), huge, S(0)), fb, S(0.01)), Status::NumericalFailure);

  F f0;
  Mat<S, F::kStates, F::kStates> P = f0.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5));
  P(0, 0) = P(3, 3) = S(1e-6);
  P(0, 3) = P(3, 0) = S(-10);  // P_pp+ = P_pp + 2 dt P_pv + ... < 0
  F f = gpsins_navigating<F>(100.0, &P);
  const auto b2 = f.state();
  expect_refused_kept(f, b2, f.predict(Vec3<S>::Zero(), fb, S(0.01)), Status::NumericalFailure);
}

#define QUATNAV_GPSINS_CONTRACT_TEST(NAME, FN)      \
  TEST(GpsInsContract, NAME) {                      \
    FN<GpsInsFilter<double>>();                     \
    FN<GpsInsFilter<float>>();                      \
    FN<GpsInsFilter<double, true>>();               \
    FN<GpsInsFilter<float, true>>();                \
  }
QUATNAV_GPSINS_CONTRACT_TEST(AltimeterOffsetOverflowRefused, gpsins_baro_offset_overflow)
QUATNAV_GPSINS_CONTRACT_TEST(PreNavigationFixRefusedKept, gpsins_prenav_fix_refused)
QUATNAV_GPSINS_CONTRACT_TEST(CorrectionLosingPsdRefused, gpsins_update_loses_psd)
QUATNAV_GPSINS_CONTRACT_TEST(TimeUpdateNonFiniteRefused, gpsins_predict_refused)

template <class S> void gpsins_bad_input() {
  GpsInsParams<S> p;
  p.gyro_range = S(35);
  p.acc_range = S(156.9);
  p.max_dt = S(0.5);
  GpsInsFilter<S> f(p);
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  const Vec3<S> fb(S(0.1), S(-0.2), S(-9.8)), wb(S(0.01), S(0.02), S(-0.01)), nan3 = Vec3<S>::Constant(nan);
  ASSERT_EQ(f.reset(quat::from_euler(S(0.1), S(0.2), S(0.3)), Vec3<S>(S(1), S(0), S(0)), 0.6, 0.2, 100.0,
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
  EXPECT_EQ(f.reset(Quat<S>(big, big, S(0), S(0)), Vec3<S>::Zero(), 0.6, 0.2, 100.0, Vec3<S>::Zero(),
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
  p.acc_noise = S(1e-6);
  p.gyro_bias_noise = S(1e-9);
  p.acc_bias_noise = S(1e-9);
  p.baro_sigma = S(1e-3);
  p.compass_sigma = S(1e-5);
  p.gate_gps_pos = p.gate_gps_vel = p.gate_baro = p.gate_compass = S(0);
  p.gps_pos_sigma_min = p.gps_vel_sigma_min = p.lever_arm_sigma = p.gps_time_sigma = S(0);  // as given
  p.cov_floor = floor;
  GpsInsFilter<S> f(p);
  const Quat<S> q = quat::from_euler(S(0.1), S(-0.05), S(0.4));
  EXPECT_EQ(f.reset(q, Vec3<S>::Zero(), 0.6, 0.2, 100.0, Vec3<S>::Zero(), Vec3<S>::Zero(),
                         f.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5))),
            Status::Ok);
  const Vec3<double> g_n = earth::gravity_n(0.6, 100.0);
  const Vec3<S> fb = quat::rotate_inv(q, Vec3<S>(-g_n.cast<S>())), wb = quat::rotate_inv(q, earth::earth_rate_n(S(0.6)));
  double min_eig = 1e300;
  for (int k = 0; k < steps; ++k) {
    const Status sp = f.predict(wb, fb, S(0.01));
    if (floor > S(0)) { EXPECT_EQ(sp, Status::Ok); }
    f.update_compass(S(0.4));
    f.update_baro(100.0);
    if (k % 10 == 0) f.update_gps(0.6, 0.2, 100.0, Vec3<S>::Zero(), Vec3<S>::Constant(S(1e-3)), Vec3<S>::Constant(S(1e-4)));
    EXPECT_TRUE(f.covariance() == f.covariance().transpose()) << "step " << k;
    if (k % 10 != 9) continue;  // eigenvalues every 10th step (as above)
    constexpr int N = GpsInsFilter<S>::kStates;
    const auto h = covariance_health<double, N>(Mat<double, N, N>(f.covariance().template cast<double>()));
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
  QUATNAV_SKIP_NUMERICAL_UNDER_SANITIZERS();
  EXPECT_LT(gpsins_near_singular<float>(0.0f, 2000), 0.0);
  EXPECT_GE(gpsins_near_singular<float>(1e-8f, 2000), 0.99e-8);
  EXPECT_LT(gpsins_near_singular<double>(0.0, 1000), 1e-12);
  EXPECT_GE(gpsins_near_singular<double>(1e-12, 1000), 0.99e-12);
}
