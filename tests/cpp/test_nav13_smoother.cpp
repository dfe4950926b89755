// NavFilter13's smoother (nav/nav13_smoother.hpp, core/smoother.hpp) for every time update: its
// transition against finite differences, the error-state sigmas never above the forward ones,
// errors below the forward ones on a simulated run with an aid outage, the same bits whatever the
// checkpoint interval, no heap in the backward pass, float against double.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/nav/nav13_smoother.hpp>
#include <random>
#include <vector>

using namespace quatnav;

namespace {

template <class S, TimeUpdate TU> struct Nav13Case {
  using F = NavFilter13<S, TU>;
  int n = 3000;
  std::vector<S> w, f, dt, vel, yaw;
  std::vector<double> t, vel_t, yaw_t;  // times in double, as run_nav13_batch takes them
  std::vector<double> truth_v, truth_q;  // per sample
  F filter;

  explicit Nav13Case(unsigned seed) {
    std::mt19937 g(seed);
    std::normal_distribution<double> nd;
    // A level vehicle turning at 0.2 rad/s at 2 m/s (no Earth rotation: simple truth).
    typename F::Params p;
    p.earth_rotation = false;
    p.acc_noise = S(2e-3);
    p.gyro_noise = S(2e-4);
    p.gps_vel_sigma = S(0.05);
    p.yaw_sigma = S(0.03);
    filter = F(p);
    const double h = 0.01, wz = 0.2, V = 2.0, gmag = 9.80665;
    Quat<double> q = quat::from_euler(0.0, 0.0, 0.3);
    Vec3<double> v = quat::rotate(q, Vec3<double>(V, 0, 0));
    const Vec3<double> ba(0.02, -0.01, 0.03), bg(0.002, -0.001, 0.0015);
    for (int k = 0; k < n; ++k) {
      const Vec3<double> w_b(0, 0, wz);
      const Vec3<double> f_b(0, V * wz, -gmag);  // centripetal to the right (body y), gravity up
      const Quat<double> qn = quat::mul(q, quat::from_rotvec(Vec3<double>(w_b * h)));
      q = qn / qn.norm();
      v = quat::rotate(q, Vec3<double>(V, 0, 0));
      for (int i = 0; i < 3; ++i) {
        w.push_back(S(w_b[i] + bg[i] + 2e-4 / std::sqrt(h) * nd(g)));
        f.push_back(S(f_b[i] + ba[i] + 2e-3 / std::sqrt(h) * nd(g)));
        truth_v.push_back(v[i]);
      }
      for (int i = 0; i < 4; ++i) truth_q.push_back(q[i]);
      t.push_back((k + 1) * h);
      dt.push_back(S(h));
      if (k % 10 == 9 && !(k > 1000 && k < 2000)) {  // 10 Hz aids with a 10 s outage
        vel_t.push_back((k + 1) * h);
        for (int i = 0; i < 3; ++i) vel.push_back(S(v[i] + 0.05 * nd(g)));
        yaw_t.push_back((k + 1) * h);
        yaw.push_back(S(quat::to_euler(q)[2] + 0.03 * nd(g)));
      }
    }
    const Quat<double> q0 = quat::from_euler(0.02, -0.02, 0.35);
    Mat<double, 12, 12> Pe = Mat<double, 12, 12>::Zero();
    Pe.diagonal() << Vec3<double>::Constant(0.01), 0.03 * 0.03, 0.03 * 0.03, 0.06 * 0.06,
        Vec3<double>::Constant(0.05 * 0.05), Vec3<double>::Constant(0.003 * 0.003);
    const Mat<double, 13, 13> P0 = detail::Nav13Block<double>::from_error_covariance(q0, Pe);
    const Vec3<double> v0 = quat::rotate(quat::from_euler(0.0, 0.0, 0.3), Vec3<double>(V, 0, 0)) + Vec3<double>(0.1, -0.1, 0);
    filter.reset(v0.cast<S>(), q0.cast<S>(), Vec3<S>::Zero(), Vec3<S>::Zero(), P0.cast<S>(), 0.6, 2.0, 50.0);
  }

  void run(std::vector<S>& x, std::vector<S>& sig, std::vector<S>& att, std::vector<S>& xs, std::vector<S>& sigs,
           std::vector<S>& atts, std::size_t segment) {
    x.assign(13 * n, 0), sig.assign(13 * n, 0), att.assign(3 * n, 0);
    xs = x, sigs = sig, atts = att;
    std::vector<std::uint32_t> fl(n);
    F fc = filter;
    Nav13RtsModel<F> model(fc, w.data(), f.data(), dt.data());
    RtsSmoother<Nav13RtsModel<F>> sm(model);
    ASSERT_TRUE(sm.reserve(n, vel_t.size() + yaw_t.size() + 1, segment));
    run_nav13_batch<F, S>(fc, w.data(), f.data(), t.data(), dt.data(), n, vel_t.data(), vel.data(), vel_t.size(),
                          yaw_t.data(), yaw.data(), yaw_t.size(), S(0), S(0), x.data(), sig.data(), nullptr, att.data(),
                          fl.data(), nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, true, sm);
    Nav13SmoothedOutput<S> out{xs.data(), sigs.data(), nullptr, atts.data()};
    Eigen::internal::set_is_malloc_allowed(false);
    const auto r = sm.smooth(out);
    Eigen::internal::set_is_malloc_allowed(true);
    ASSERT_EQ(r, RtsSmoother<Nav13RtsModel<F>>::Result::Ok);
  }
};

/// Runs the case; the smoothed errors (after the first 2 s) against the truth, every error-state
/// sigma against the forward one (tolerance `rel`: the float filter's rounding), the last sample.
template <class S, TimeUpdate TU> void nav13_smoother_check(double rel, double velocity_ratio, double attitude_ratio) {
  Nav13Case<S, TU> c(11);
  std::vector<S> x, sig, att, xs, sigs, atts;
  c.run(x, sig, att, xs, sigs, atts, 256);
  double ef = 0, es = 0, eaf = 0, eas = 0;
  int m = 0;
  for (int k = 200; k < c.n; ++k) {
    // The error state's sigmas (not the quaternion components': in the 13-state form they depend
    // on the quaternion itself, and the smoothed one is another).
    for (int i : {0, 1, 2, 7, 8, 9, 10, 11, 12})
      EXPECT_LE(sigs[13 * k + i], sig[13 * k + i] * (1 + rel) + 1e-15) << k << " " << i;
    for (int i = 0; i < 3; ++i) EXPECT_LE(atts[3 * k + i], att[3 * k + i] * (1 + rel) + 1e-15) << k << " " << i;
    const Vec3<double> vt = Eigen::Map<const Vec3<double>>(&c.truth_v[3 * k]);
    const Quat<double> qt = Eigen::Map<const Quat<double>>(&c.truth_q[4 * k]);
    auto vel = [&](const std::vector<S>& a) { return Vec3<double>(Eigen::Map<const Vec3<S>>(&a[13 * k]).template cast<double>()); };
    auto rot = [&](const std::vector<S>& a) {
      const Quat<double> q = Eigen::Map<const Quat<S>>(&a[13 * k + 3]).template cast<double>();
      return quat::to_rotvec(quat::mul(quat::conj(q), qt)).squaredNorm();
    };
    ef += (vel(x) - vt).squaredNorm();
    es += (vel(xs) - vt).squaredNorm();
    eaf += rot(x);
    eas += rot(xs);
    ++m;
  }
  EXPECT_LT(es, velocity_ratio * ef) << "velocity RMSE: smoothed " << std::sqrt(es / m) << " forward " << std::sqrt(ef / m);
  EXPECT_LT(eas, attitude_ratio * eaf) << "attitude RMSE: smoothed " << std::sqrt(eas / m) << " forward "
                                       << std::sqrt(eaf / m);
  // The last sample is the forward estimate; the checkpoint interval does not change a bit.
  for (int i = 0; i < 13; ++i) EXPECT_EQ(xs[13 * (c.n - 1) + i], x[13 * (c.n - 1) + i]);
  std::vector<S> x2, sig2, att2, xs2, sigs2, atts2;
  c.run(x2, sig2, att2, xs2, sigs2, atts2, 7);
  EXPECT_TRUE(xs2 == xs);
  EXPECT_TRUE(sigs2 == sigs);
}

}  // namespace

// The thresholds bound the ratio of the summed squared errors, smoothed / forward. Measured on
// this run (every time update, double and float alike): velocity RMSE 0.0125 against 0.069 m/s
// (ratio of squares 0.033), attitude 0.00255 against 0.0041 rad (0.385).
TEST(Nav13Smoother, EkfSmoothsBelowForward) { nav13_smoother_check<double, TimeUpdate::Ekf>(1e-9, 0.1, 0.5); }
TEST(Nav13Smoother, SecondOrderSmoothsBelowForward) {
  nav13_smoother_check<double, TimeUpdate::SecondOrder>(1e-9, 0.1, 0.5);
}
TEST(Nav13Smoother, UkfSmoothsBelowForward) { nav13_smoother_check<double, TimeUpdate::Ukf>(1e-9, 0.1, 0.5); }
TEST(Nav13Smoother, FloatEkfSmoothsBelowForward) { nav13_smoother_check<float, TimeUpdate::Ekf>(1e-3, 0.1, 0.5); }
TEST(Nav13Smoother, FloatUkfSmoothsBelowForward) { nav13_smoother_check<float, TimeUpdate::Ukf>(1e-3, 0.1, 0.5); }

TEST(Nav13Smoother, TransitionMatchesFiniteDifferences) {
  // Phi maps an error-state perturbation of the posterior to that of the EKF prior:
  // (f_d(x [+] e) normalized) [-] (f_d(x) normalized) = Phi e + O(e^2).
  using M = Nav13RtsModel<NavFilter13<double, TimeUpdate::Ekf>>;
  std::mt19937 g(3);
  std::normal_distribution<double> nd;
  for (int trial = 0; trial < 10; ++trial) {
    Vec<double, 13> x;
    x << 3 * nd(g), 3 * nd(g), nd(g), quat::from_euler(0.3 * nd(g), 0.3 * nd(g), nd(g)), 0.1 * nd(g), 0.1 * nd(g),
        0.1 * nd(g), 0.01 * nd(g), 0.01 * nd(g), 0.01 * nd(g);
    Nav13Input<double> u;
    u.f_ib_b = Vec3<double>(0.5 * nd(g), 0.5 * nd(g), -9.8);
    u.omega_ib_b = Vec3<double>(0.3 * nd(g), 0.3 * nd(g), 0.3 * nd(g));
    u.dt = 0.05;
    u.omega_ie_n = Vec3<double>(0.05 * nd(g), 0.0, 0.05 * nd(g));
    u.omega_en_n = Vec3<double>(0.02 * nd(g), 0.02 * nd(g), 0.0);
    u.g_n = Vec3<double>(0, 0, 9.8);
    auto step = [&](const Vec<double, 13>& xi) {
      Vec<double, 13> y = detail::nav13_f(xi, u);
      y.segment<4>(3).normalize();
      return y;
    };
    const Vec<double, 13> y0 = step(x);
    const Mat<double, 12, 12> Phi = M::ekf_transition(x, Quat<double>(y0.segment<4>(3)), u);
    Mat<double, 12, 12> Num;
    const double eps = 1e-6;
    for (int j = 0; j < 12; ++j) {
      Vec<double, 12> e = Vec<double, 12>::Zero();
      e[j] = eps;
      const Vec<double, 13> yp = step(detail::Nav13Block<double>::retract(x, e));
      e[j] = -eps;
      const Vec<double, 13> ym = step(detail::Nav13Block<double>::retract(x, e));
      auto loc = [&](const Vec<double, 13>& y) {
        Vec<double, 12> d;
        d.segment<3>(0) = y.segment<3>(0) - y0.segment<3>(0);
        d.segment<3>(3) = quat::to_rotvec(quat::mul(quat::conj(Quat<double>(y0.segment<4>(3))), Quat<double>(y.segment<4>(3))));
        d.segment<6>(6) = y.tail<6>() - y0.tail<6>();
        return d;
      };
      Num.col(j) = (loc(yp) - loc(ym)) / (2 * eps);
    }
    EXPECT_LT((Num - Phi).cwiseAbs().maxCoeff(), 1e-7) << trial;
  }
}
