// Paper 001 MargFilter: Gauss-Newton Jacobian against finite differences, convergence of the
// solve on static data, eq. (7') against exact rigid-body kinematics, no heap in a step, bad
// input leaves the state untouched, split-run round trip, float and double.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <quatnav/quatnav.hpp>
#include <random>
#include <vector>

#include "same_fields.hpp"

using namespace quatnav;

namespace {
template <class T> bool bitwise_equal(const T& a, const T& b) {
  return std::memcmp(static_cast<const void*>(&a), static_cast<const void*>(&b), sizeof(T)) == 0;
}
template <class S> bool same_state(const MargFilterState<S>& a, const MargFilterState<S>& b) {
  return quatnav_test::same_fields(a, b);
}
const Vec3<double> kMagN(0.6, 0.0, 0.8);  // unit reference field, dip 53 deg
const Vec3<double> kGravUp(0.0, 0.0, -1.0);
}  // namespace

TEST(MargFilter, JacobianMatchesFiniteDifferences) {
  std::mt19937 g(3);
  std::normal_distribution<double> n;
  for (int trial = 0; trial < 20; ++trial) {
    // Not unit on purpose: eq. (2)'s quadratic form is differentiated as it stands.
    const Quat<double> q(n(g), n(g), n(g), n(g));
    const Vec3<double> r(n(g), n(g), n(g));
    const Mat34<double> X = detail::marg_jacobian(q, r);
    const double h = 1e-6;
    for (int j = 0; j < 4; ++j) {
      Quat<double> qp = q, qm = q;
      qp[j] += h;
      qm[j] -= h;
      const Vec3<double> fd = (detail::marg_h(qp, r) - detail::marg_h(qm, r)) / (2 * h);
      EXPECT_LT((X.col(j) - fd).norm(), 1e-8 * (1 + fd.norm())) << "column " << j;
    }
  }
}

TEST(MargFilter, ModelIsEq2RotationForUnitQuaternion) {
  // eq. (1)-(2): y = R^{n->b} r = C_nb^T r.
  const Quat<double> q = quat::from_euler(0.3, -0.2, 1.1);
  const Vec3<double> r(0.2, -0.5, 0.9);
  EXPECT_LT((detail::marg_h(q, r) - quat::rotate_inv(q, r)).norm(), 1e-14);
  // Homogeneous of degree 2 in q.
  EXPECT_LT((detail::marg_h(Quat<double>(2.0 * q), r) - 4.0 * quat::rotate_inv(q, r)).norm(), 1e-13);
}

template <class S> void expect_static_convergence(double tol) {
  // Exact measurements of a known attitude; start 0.5 rad off: the solve reaches the truth in a
  // few iterations (Gauss-Newton converges quadratically on a zero-residual problem).
  const Quat<S> q_true = quat::from_euler<S>(S(0.4), S(-0.3), S(2.0));
  Mat<S, 3, 2> meas, refs;
  refs.col(0) = kMagN.cast<S>();
  refs.col(1) = kGravUp.cast<S>();
  for (int j = 0; j < 2; ++j) meas.col(j) = quat::rotate_inv(q_true, Vec3<S>(refs.col(j)));
  const Quat<S> q0 = quat::mul(q_true, quat::from_rotvec(Vec3<S>(S(0.3), S(-0.25), S(0.3))));
  Quat<S> q;
  int iters = 0;
  bool conv = false;
  ASSERT_EQ((detail::marg_gauss_newton<S, 2>(q0, meas, refs, 20, S(tol), q, iters, conv)), Status::Ok);
  EXPECT_TRUE(conv);
  EXPECT_LE(iters, 7);
  EXPECT_LT(quat::angle_between(Quat<S>(q / q.norm()), q_true), S(sizeof(S) == 4 ? 1e-5 : 1e-10));
  EXPECT_NEAR(double(q.norm()), 1.0, sizeof(S) == 4 ? 1e-5 : 1e-10);
  // Fewer iterations than needed: not converged, but closer than the start.
  Quat<S> q1;
  ASSERT_EQ((detail::marg_gauss_newton<S, 2>(q0, meas, refs, 1, S(tol), q1, iters, conv)), Status::Ok);
  EXPECT_FALSE(conv);
  EXPECT_EQ(iters, 1);
  EXPECT_LT(quat::angle_between(Quat<S>(q1 / q1.norm()), q_true), S(0.3) * quat::angle_between(q0, q_true));
}

TEST(MargFilter, GaussNewtonConvergesOnStaticData) {
  expect_static_convergence<double>(1e-12);
  expect_static_convergence<float>(1e-6);
}

TEST(MargFilter, GravityOnlyKeepsHeading) {
  // 6D mode: the minimum-norm step corrects tilt and leaves rotation about gravity alone.
  const Quat<double> q_true = quat::from_euler(0.2, 0.1, 0.5);
  Mat<double, 3, 1> meas, refs;
  refs.col(0) = kGravUp;
  meas.col(0) = quat::rotate_inv(q_true, kGravUp);
  const Quat<double> q0 = quat::from_euler(0.0, 0.0, 1.2);
  Quat<double> q;
  int iters = 0;
  bool conv = false;
  ASSERT_EQ((detail::marg_gauss_newton<double, 1>(q0, meas, refs, 20, 1e-12, q, iters, conv)), Status::Ok);
  EXPECT_TRUE(conv);
  q /= q.norm();
  EXPECT_LT((quat::rotate_inv(q, kGravUp) - meas.col(0)).norm(), 1e-10);
  // The heading (about gravity) is that of q0: measured by the body x axis in the horizontal plane.
  const Vec3<double> ex = Vec3<double>::UnitX();
  const Vec3<double> x0 = quat::rotate(q0, ex), x1 = quat::rotate(q, ex);
  EXPECT_NEAR(std::atan2(x1[1], x1[0]), std::atan2(x0[1], x0[0]), 0.15);
}

TEST(MargFilter, LeverArmCorrectionMatchesRigidBodyKinematics) {
  // A body rotating about a fixed point with varying rate: the antenna's acceleration by
  // finite differences of its position must satisfy eq. (7'):
  //   f_b + w_dot x d + w x (w x d) = C_bn (a_g_n - g_n), with f_b = C_bn (a_i_n - g_n).
  const Vec3<double> d(0.8, 0.3, -0.9), g_n(0, 0, 9.80665);
  auto omega = [](double t) { return Vec3<double>(0.3 * std::sin(t), 0.5 + 0.1 * t, -0.2 * std::cos(2 * t)); };
  auto r_i = [](double t) { return Vec3<double>(std::sin(0.7 * t), 0.5 * t * t, std::cos(t)); };
  // Attitude by fine integration.
  Quat<double> q = quat::identity<double>();
  const double h = 1e-4, T = 1.0;
  std::vector<Quat<double>> qs;
  for (double t = 0; t < T + 3 * h; t += h) {
    qs.push_back(q);
    q = quat::mul(q, quat::from_rotvec(Vec3<double>(omega(t + h / 2) * h)));
  }
  const int k = int(T / h);
  auto r_g = [&](int i) { return Vec3<double>(r_i(i * h) + quat::rotate(qs[i], d)); };
  const Vec3<double> a_g = (r_g(k + 1) - 2 * r_g(k) + r_g(k - 1)) / (h * h);
  const Vec3<double> a_i = (r_i((k + 1) * h) - 2 * r_i(k * h) + r_i((k - 1) * h)) / (h * h);
  const Vec3<double> w = omega(k * h), wdot = (omega(k * h + h) - omega(k * h - h)) / (2 * h);
  const Vec3<double> f_b = quat::rotate_inv(qs[k], Vec3<double>(a_i - g_n));
  const Vec3<double> lhs = detail::marg_lever_corrected(f_b, w, wdot, d);
  const Vec3<double> rhs = quat::rotate_inv(qs[k], Vec3<double>(a_g - g_n));
  EXPECT_LT((lhs - rhs).norm(), 1e-4);
  // Without the lever-arm terms the two sides differ by the size of those terms.
  EXPECT_GT((f_b - rhs).norm(), 0.05);
}

template <class S> void expect_no_heap() {
  MargFilterParams<S> p;
  p.bias_gain = S(0.01);
  p.lever_arm_b = Vec3<S>(S(0.8), S(0.3), S(-0.9));
  MargFilter<S> f(p);
  const Vec3<S> acc(S(0.5), S(-0.3), S(-9.7)), mag(S(20), S(3), S(40)), gyr(S(0.1), S(-0.2), S(0.3));
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 10; ++k) {
    f.update_gps_velocity(Vec3<S>(S(k), S(1), S(0)), S(0.05) * S(k));
    f.predict(gyr, S(0.01));
    f.update_acc_mag(acc, mag);
    f.update_acc(acc);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(f.quat().allFinite());
  // The batch loop too.
  const std::size_t n = 50, m = 3;
  std::vector<S> dt(n, S(0.01)), gyr_b(3 * n, S(0.1)), acc_b(3 * n, S(0)), mag_b(3 * n, S(0)), q(4 * n), b(3 * n),
      ga(3 * n), res(n), gv(3 * m, S(1));
  std::vector<double> t(n), gt = {0.1, 0.2, 0.3};  // times are double for every S
  std::vector<std::uint32_t> fl(n);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = S(0.01) * S(k);
    acc_b[3 * k + 2] = S(-9.8);
    mag_b[3 * k] = S(20);
    mag_b[3 * k + 2] = S(40);
  }
  MargFilter<S> f2(p);
  Eigen::internal::set_is_malloc_allowed(false);
  run_marg_batch(f2, t.data(), dt.data(), gyr_b.data(), acc_b.data(), mag_b.data(), n, gt.data(), gv.data(), m,
                 q.data(), b.data(), ga.data(), res.data(), fl.data());
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(fl[0] & flags::kInitialized, flags::kInitialized);
  EXPECT_EQ(fl[n - 1] & flags::kGpsCorrected, flags::kGpsCorrected);  // fixes at 0.1..0.3 s, timeout 0.5 s
  EXPECT_TRUE(std::isfinite(q[4 * n - 1]));
}

TEST(MargFilter, NoHeapInSteps) {
  expect_no_heap<double>();
  expect_no_heap<float>();
}

template <class S> void expect_bad_input_leaves_state() {
  using F = MargFilter<S>;
  F f;
  const Vec3<S> acc(S(0.5), S(-0.3), S(-9.7)), mag(S(20), S(3), S(40)), gyr(S(0.1), S(-0.2), S(0.3));
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  EXPECT_EQ(f.predict(gyr, S(0.01)), Status::NotInitialized);
  EXPECT_EQ(f.update_acc(acc).status, Status::NotInitialized);
  EXPECT_EQ(f.initialize(Vec3<S>::Zero(), mag), Status::ZeroNorm);
  EXPECT_EQ(f.initialize(Vec3<S>(nan, S(0), S(1)), mag), Status::NonFinite);
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  ASSERT_EQ(f.update_gps_velocity(Vec3<S>(S(1), S(2), S(0)), S(1)), Status::Ok);
  ASSERT_EQ(f.predict(gyr, S(0.01)), Status::Ok);
  const typename F::State before = f.state();
  EXPECT_EQ(f.predict(Vec3<S>(nan, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(Vec3<S>(inf, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(gyr, S(0)), Status::InvalidDt);
  EXPECT_EQ(f.predict(gyr, S(-0.01)), Status::InvalidDt);
  EXPECT_EQ(f.predict(gyr, nan), Status::InvalidDt);
  EXPECT_EQ(f.predict(gyr, S(5)), Status::InvalidDt);
  EXPECT_EQ(f.update_acc(Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_acc(Vec3<S>(nan, S(0), S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_acc_mag(acc, Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_acc_mag(acc, Vec3<S>(S(0), inf, S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(nan, S(0), S(0)), S(2)), Status::NonFinite);
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(S(1), S(0), S(0)), S(1)), Status::InvalidDt);   // same time
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(S(1), S(0), S(0)), S(0.5)), Status::InvalidDt); // backwards
  EXPECT_EQ(f.update_gps_velocity(Vec3<S>(S(1), S(0), S(0)), nan), Status::NonFinite);
  EXPECT_TRUE(same_state(before, f.state()));
  // Reference field parallel to gravity: no heading information, X^T X is singular (the plain
  // filter: with the parts on, the dip test refuses that field first and gravity alone updates).
  F g(F::Params::paper());
  g.set_mag_dip(S(-1.5707963267948966));
  ASSERT_EQ(g.initialize(acc, mag), Status::Ok);  // (the field norm is learned here, not by the failing update)
  ASSERT_EQ(g.predict(gyr, S(0.01)), Status::Ok);
  const typename F::State before_g = g.state();
  EXPECT_EQ(g.update_acc_mag(acc, mag).status, Status::SolveFailed);
  EXPECT_TRUE(same_state(before_g, g.state()));
  typename F::State bad = before;
  bad.q_nb *= S(2);
  EXPECT_EQ(f.set_state(bad), Status::InvalidArgument);
  bad = before;
  bad.gps_acc_n[1] = nan;
  EXPECT_EQ(f.set_state(bad), Status::NonFinite);
  EXPECT_TRUE(same_state(before, f.state()));
}

TEST(MargFilter, BadInputLeavesStateUntouched) {
  expect_bad_input_leaves_state<double>();
  expect_bad_input_leaves_state<float>();
}

/// A 4 s record at 100 Hz (n = 400) with 20 GPS fixes every 0.2 s from fix_t0 on; sample times
/// and fix times given in S's precision (as the callers had them) then held in double.
template <class S> struct MargRecord {
  static constexpr std::size_t n = 400, m = 20;
  std::vector<S> dt = std::vector<S>(n, S(0.01)), gyr = std::vector<S>(3 * n), acc = std::vector<S>(3 * n),
                 mag = std::vector<S>(3 * n), gv = std::vector<S>(3 * m);
  std::vector<double> t = std::vector<double>(n), gt = std::vector<double>(m);
  MargRecord(unsigned seed, double fix_t0) {
    std::mt19937 g(seed);
    std::normal_distribution<double> nd;
    for (std::size_t k = 0; k < n; ++k) {
      t[k] = S(0.01) * S(k);
      for (int i = 0; i < 3; ++i) {
        gyr[3 * k + i] = S(0.2 * std::sin(0.01 * k + i) + 0.01 * nd(g));
        acc[3 * k + i] = S((i == 2 ? -9.8 : 0.5 * std::cos(0.02 * k + i)) + 0.05 * nd(g));
        mag[3 * k + i] = S((i == 0 ? 20 : i == 2 ? 40 : 3) + 0.2 * nd(g));
      }
    }
    for (std::size_t j = 0; j < m; ++j) {
      gt[j] = S(0.2) * S(j) + S(fix_t0);
      for (int i = 0; i < 3; ++i) gv[3 * j + i] = S(std::sin(0.3 * j + i));
    }
  }
};

template <class S> void expect_split_run_identical() {
  MargRecord<S> r(7, 0.0);
  const std::size_t n = r.n, m = r.m;
  const auto &dt = r.dt, &gyr = r.gyr, &acc = r.acc, &mag = r.mag, &gv = r.gv;
  const auto &t = r.t, &gt = r.gt;
  MargFilterParams<S> p;
  p.bias_gain = S(0.05);
  p.lever_arm_b = Vec3<S>(S(0.5), S(0), S(-0.3));
  std::vector<S> q1(4 * n), q2(4 * n);
  MargFilter<S> a(p), b(p);
  run_marg_batch(a, t.data(), dt.data(), gyr.data(), acc.data(), mag.data(), n, gt.data(), gv.data(), m, q1.data(),
                 (S*)nullptr, (S*)nullptr, (S*)nullptr, (std::uint32_t*)nullptr);
  const std::size_t h = 173, mh = 9;  // gt[8] = 1.6 s <= t[172] = 1.72 s < gt[9]
  run_marg_batch(b, t.data(), dt.data(), gyr.data(), acc.data(), mag.data(), h, gt.data(), gv.data(), mh,
                 q2.data(), (S*)nullptr, (S*)nullptr, (S*)nullptr, (std::uint32_t*)nullptr);
  MargFilter<S> c(p);
  ASSERT_EQ(c.set_state(b.state()), Status::Ok);
  run_marg_batch(c, t.data() + h, dt.data() + h, gyr.data() + 3 * h, acc.data() + 3 * h, mag.data() + 3 * h, n - h,
                 gt.data() + mh, gv.data() + 3 * mh, m - mh, q2.data() + 4 * h, (S*)nullptr, (S*)nullptr,
                 (S*)nullptr, (std::uint32_t*)nullptr);
  EXPECT_EQ(std::memcmp(q1.data(), q2.data(), sizeof(S) * 4 * n), 0);
}

TEST(MargFilter, SplitRunIsIdentical) {
  expect_split_run_identical<double>();
  expect_split_run_identical<float>();
}

TEST(MargFilter, ConstantAccelerationIsRemovedByGps) {
  // Level, no rotation, constant acceleration 2 m/s^2 north: the accelerometer reads a tilted
  // gravity. Uncorrected the filter converges to a pitch of atan(2/g); with GPS velocity fixes
  // it stays level.
  const double a = 2.0, g0 = 9.80665;
  for (bool use_gps : {false, true}) {
    MargFilterParams<double> p;
    p.gain = 2.0;
    p.gps_correction = use_gps;
    MargFilter<double> f(p);
    f.set_mag_dip(std::atan2(0.8, 0.6));  // the test is about eq. (7), not about learning the dip
    ASSERT_EQ(f.initialize(Vec3<double>(0, 0, -g0), Vec3<double>(0.6, 0, 0.8)), Status::Ok);
    const Vec3<double> acc(a, 0, -g0), mag(0.6, 0, 0.8);  // f_b = a_n - g_n, body = NED here
    for (int k = 1; k <= 1000; ++k) {
      if (k % 5 == 0) f.update_gps_velocity(Vec3<double>(a * 0.01 * k, 0, 0), 0.01 * k);
      f.predict(Vec3<double>::Zero(), 0.01);
      f.update_acc_mag(acc, mag);
    }
    const double pitch = quat::to_euler(f.quat())[1];
    if (use_gps) {
      EXPECT_LT(std::abs(pitch), 1e-6);
    } else {
      // The least-squares compromise with the field still tilts the estimate substantially.
      EXPECT_GT(std::abs(pitch), 0.3 * std::atan(a / g0));
    }
  }
}

// GPS fixes on a GPS or Unix clock (1.4e9 s): the times are double whatever S, so a float filter
// differences the fixes as on a clock starting at 0 (a float time resolves 128 s there: every
// fix would share one time and none would be used).
template <class S> void expect_epoch_clock_same_as_zero_clock() {
  // Fixes between two samples (0.005 s after one): the order does not hang on a rounding.
  MargRecord<S> r(3, 0.005);
  const std::size_t n = r.n, m = r.m;
  const auto &dt = r.dt, &gyr = r.gyr, &acc = r.acc, &mag = r.mag, &gv = r.gv;
  const auto &t = r.t, &gt = r.gt;
  std::vector<double> t_epoch(t), gt_epoch(gt);
  for (double& x : t_epoch) x += 1.4e9;
  for (double& x : gt_epoch) x += 1.4e9;
  MargFilterParams<S> p;
  p.lever_arm_b = Vec3<S>(S(0.5), S(0), S(-0.3));
  std::vector<S> q0(4 * n), q1(4 * n), a0(3 * n), a1(3 * n);
  std::vector<std::uint32_t> f0(n), f1(n);
  MargFilter<S> z(p), e(p);
  run_marg_batch(z, t.data(), dt.data(), gyr.data(), acc.data(), mag.data(), n, gt.data(), gv.data(), m, q0.data(),
                 (S*)nullptr, a0.data(), (S*)nullptr, f0.data());
  run_marg_batch(e, t_epoch.data(), dt.data(), gyr.data(), acc.data(), mag.data(), n, gt_epoch.data(), gv.data(), m,
                 q1.data(), (S*)nullptr, a1.data(), (S*)nullptr, f1.data());
  std::size_t corrected = 0;
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(f1[k], f0[k]) << k;
    if (!(f0[k] & flags::kGpsCorrected)) continue;
    ++corrected;
    // The fix intervals differ by the rounding of 1.4e9 + 0.2 j in double (2.4e-7 s).
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a1[3 * k + i], a0[3 * k + i], 1e-4) << k;
  }
  EXPECT_GT(corrected, n / 2);
  for (std::size_t i = 0; i < 4 * n; ++i) EXPECT_NEAR(q1[i], q0[i], 1e-4) << i;
}

TEST(MargFilter, GpsFixesOnAnEpochClock) {
  expect_epoch_clock_same_as_zero_clock<double>();
  expect_epoch_clock_same_as_zero_clock<float>();
}

// The batch is the documented loop: at sample k, every fix with gps_t <= t[k] not yet used, then
// initialize (first sample) or predict + update. Fixes on the sample times and between them
// (5 ms after one): a fix used a sample early or late changes the GPS-corrected attitude.
template <class S> void expect_batch_is_the_step_loop(double fix_t0) {
  MargRecord<S> r(11, fix_t0);
  const std::size_t n = r.n, m = r.m;
  MargFilterParams<S> p;
  p.lever_arm_b = Vec3<S>(S(0.5), S(0), S(-0.3));
  std::vector<S> qb(4 * n);
  std::vector<std::uint32_t> fb(n);
  MargFilter<S> batch(p), steps(p);
  run_marg_batch(batch, r.t.data(), r.dt.data(), r.gyr.data(), r.acc.data(), r.mag.data(), n, r.gt.data(),
                 r.gv.data(), m, qb.data(), (S*)nullptr, (S*)nullptr, (S*)nullptr, fb.data());
  std::size_t j = 0, corrected = 0;
  for (std::size_t k = 0; k < n; ++k) {
    for (; j < m && r.gt[j] <= r.t[k]; ++j) steps.update_gps_velocity(Vec3<S>(Eigen::Map<const Vec3<S>>(&r.gv[3 * j])), r.gt[j]);
    const Vec3<S> a = Eigen::Map<const Vec3<S>>(&r.acc[3 * k]), mg = Eigen::Map<const Vec3<S>>(&r.mag[3 * k]);
    if (k == 0) {
      ASSERT_EQ(steps.initialize(a, mg), Status::Ok);
    } else {
      ASSERT_EQ(steps.predict(Vec3<S>(Eigen::Map<const Vec3<S>>(&r.gyr[3 * k])), r.dt[k]), Status::Ok);
      corrected += steps.update_acc_mag(a, mg).gps_corrected;
    }
    ASSERT_EQ(Vec4<S>(Eigen::Map<const Vec4<S>>(&qb[4 * k])), Vec4<S>(steps.quat())) << "sample " << k << ", fixes at " << fix_t0;
  }
  EXPECT_GT(corrected, n / 2);
}

TEST(MargFilter, BatchIsTheStepLoop) {
  for (double fix_t0 : {0.0, 0.005}) {
    expect_batch_is_the_step_loop<double>(fix_t0);
    expect_batch_is_the_step_loop<float>(fix_t0);
  }
}
