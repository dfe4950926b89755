// The helpers shared by the translation units of test_robustness: faults and bad input
// (saturated readings, the covariance floor's forced near-singular cases, refused states) and a
// replay of random fault sequences through the fuzz driver (the same checks as the libFuzzer
// target tests/fuzz/fuzz_filters.cpp, here on a fixed random corpus so that every ctest run, also
// under ASan + UBSan, exercises them).
//
// One unit per filter family (attitude.cpp, marg.cpp, nav13.cpp, gpsins.cpp, covariance.cpp).
// The units of the filters are compiled in their filters' test groups (tests/cpp/CMakeLists.txt:
// the group's tests instantiate the same filters, whose code is then compiled once); the
// covariance unit is the executable test_robustness.
#pragma once

// Before any Eigen header, in every unit of the executable alike: this header comes first.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>

#include <random>
#include <vector>

#include "../../fuzz/filter_fuzz.hpp"

using namespace quatnav;
using quatnav_fuzz::FuzzAdapter;

/// How many times more random inputs a build without the sanitizers replays: the contract checks
/// are numerical and need many inputs (the default QuaternionEKF's refused updates that changed the
/// low-pass, and the floors that overflowed, were found past the first 300), while a sanitizer
/// finds a memory fault in the code paths, which a few hundred inputs reach (and a run there costs
/// 20-50 times more).
#ifdef QUATNAV_TEST_SANITIZED
inline constexpr int kFaultInputsScale = 1;
#else
inline constexpr int kFaultInputsScale = 10;
#endif

/// The forced near-singular runs check a number (the covariance floor's eigenvalue after thousands
/// of steps), in the step code the fault sequences drive under the sanitizers too; at -O0 under
/// ASan they took most of that run (430 s of its 490, 2026-12-06): a build with the sanitizers
/// skips them, the Release run checks them.
#ifdef QUATNAV_TEST_SANITIZED
#define QUATNAV_SKIP_NUMERICAL_UNDER_SANITIZERS() \
  GTEST_SKIP() << "a numerical check: run by the build without sanitizers"
#else
#define QUATNAV_SKIP_NUMERICAL_UNDER_SANITIZERS() static_cast<void>(0)
#endif

template <class F> void random_fault_sequences(unsigned seed, int inputs, int scale = kFaultInputsScale) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bytes;
  inputs *= scale;
  for (int i = 0; i < inputs; ++i) {
    bytes.resize(64 + rng() % 3000);
    for (auto& b : bytes) b = std::uint8_t(rng());
    quatnav_fuzz::Reader r(bytes.data(), bytes.size());
    const bool ok = quatnav_fuzz::run_one<F>(r, [&](const std::string& msg) { ADD_FAILURE() << msg << " (input " << i << ")"; });
    if (!ok) return;
  }
}

/// The focused tests of the causes the replay found (the units' *Contract tests): a step that
/// refuses leaves the state bit for bit; after one that succeeds the filter is healthy
/// (FuzzAdapter::healthy: finite, P symmetric, and a state set_state takes back).
template <class F> void expect_refused_kept(const F& f, const typename F::State& before, Status got, Status want) {
  EXPECT_EQ(got, want);
  EXPECT_TRUE(FuzzAdapter<F>::same(before, f.state()));
}

template <class F> void expect_healthy(const F& f) {
  std::string why;
  EXPECT_TRUE(FuzzAdapter<F>::healthy(f, why)) << why;
}

/// Input `index` of random_fault_sequences(seed, ...) alone: the same bytes, without the inputs
/// before it (a cause a longer replay found, kept as a test of its own).
template <class F> void replay_input(unsigned seed, int index) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i <= index; ++i) {
    bytes.resize(64 + rng() % 3000);
    for (auto& b : bytes) b = std::uint8_t(rng());
  }
  quatnav_fuzz::Reader r(bytes.data(), bytes.size());
  quatnav_fuzz::run_one<F>(r, [&](const std::string& msg) { ADD_FAILURE() << msg << " (input " << index << ")"; });
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
  EXPECT_EQ(f.predict(wb, fb, S(0.01)), Status::NotInitialized);
  ASSERT_EQ(f.reset(Vec3<S>(S(1), S(0), S(0)), quat::from_euler(S(0.1), S(0.2), S(0.3)), Vec3<S>::Zero(),
                    Vec3<S>::Zero(), nav13_P0<S>(), S(0.6), S(0.2), S(100)),
            Status::Ok);
  ASSERT_EQ(f.predict(Vec3<S>(S(0), S(34.9), S(0)), fb, S(0.01)), Status::Ok);
  const auto before = f.state();
  EXPECT_EQ(f.predict(wb, Vec3<S>(nan, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(Vec3<S>(S(0), inf, S(0)), fb, S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(wb, fb, S(0)), Status::InvalidDt);
  EXPECT_EQ(f.predict(wb, fb, S(-0.01)), Status::InvalidDt);
  EXPECT_EQ(f.predict(wb, fb, nan), Status::InvalidDt);
  EXPECT_EQ(f.predict(wb, fb, S(0.6)), Status::InvalidDt);
  EXPECT_EQ(f.predict(Vec3<S>(S(0), S(-35), S(0)), fb, S(0.01)), Status::Saturated);
  EXPECT_EQ(f.predict(wb, Vec3<S>(S(0), S(0), S(-160)), S(0.01)), Status::Saturated);
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

/// Forced near-singular case: velocity and yaw noise 1e-4, no process noise on the biases, the
/// vehicle at rest: the error-state covariance collapses towards rounding level (float32 without
/// the floor: eigenvalues of -3e-2, failed updates or failed sigma-point Cholesky factors). With
/// the floor its smallest eigenvalue stays >= the floor; P stays exactly symmetric and finite.
/// The eigenvalues are those of the stored P, computed in double (a float32 eigen-solver's own
/// rounding, about eps32 * max eigenvalue = 1e-10 here, would hide what is measured).
template <class S, TimeUpdate TU> double nav13_near_singular(S floor, int steps, int stride = 10) {
  NavFilter13Params<S> p;
  p.gps_vel_sigma = S(1e-4);
  p.yaw_sigma = S(1e-4);
  p.cov_floor = floor;
  NavFilter13<S, TU> f(p);
  const Quat<S> q = quat::from_euler(S(0.1), S(-0.05), S(0.4));
  EXPECT_EQ(f.reset(Vec3<S>::Zero(), q, Vec3<S>::Zero(), Vec3<S>::Zero(), nav13_P0<S>(), S(0.6), S(0.2), S(100)),
            Status::Ok);
  const Vec3<S> g_n = earth::gravity_n(S(0.6), S(100));
  const Vec3<S> fb = quat::rotate_inv(q, Vec3<S>(-g_n)), wb = quat::rotate_inv(q, earth::earth_rate_n(S(0.6)));
  double min_eig = 1e300;
  for (int k = 0; k < steps; ++k) {
    const Status sp = f.predict(wb, fb, S(0.01));
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
