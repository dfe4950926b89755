// The attitude filters' smoothers (attitude/smoother.hpp): QuaternionEKF and EulerEKF, float and
// double, on a simulated rotation: the smoothed attitude error below the forward one, every
// smoothed sigma at most the forward one, the last sample the forward estimate, the same bits
// whatever the checkpoint interval, no heap in the backward pass.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/attitude/batch.hpp>
#include <quatnav/attitude/smoother.hpp>
#include <random>
#include <type_traits>
#include <vector>

using namespace quatnav;

namespace {

/// A body turning about a slowly moving axis at up to 0.6 rad/s, 100 Hz, with gyro noise and a
/// gyro bias; accelerometer (gravity only) and magnetometer with white noise.
struct Rotation {
  int n = 4000;
  double dt = 0.01;
  std::vector<double> gyr, acc, mag, q_true;
  Rotation() {
    std::mt19937 g(5);
    std::normal_distribution<double> nd;
    const Vec3<double> bias(0.01, -0.008, 0.006), m_n(0.4, 0.0, 0.9);
    Quat<double> q = quat::from_euler(0.1, -0.2, 0.5);
    for (int k = 0; k < n; ++k) {
      const double t = k * dt;
      const Vec3<double> w(0.5 * std::sin(0.3 * t), 0.4 * std::cos(0.21 * t), 0.6 * std::sin(0.13 * t + 1.0));
      if (k > 0) {
        q = quat::mul(q, quat::from_rotvec(Vec3<double>(w * dt)));
        q /= q.norm();
      }
      const Vec3<double> a = quat::rotate_inv(q, Vec3<double>(0, 0, -9.81)), m = quat::rotate_inv(q, m_n);
      for (int i = 0; i < 3; ++i) {
        gyr.push_back(w[i] + bias[i] + 0.003 * nd(g));
        acc.push_back(a[i] + 0.05 * nd(g));
        mag.push_back(m[i] + 0.01 * nd(g));
      }
      for (int i = 0; i < 4; ++i) q_true.push_back(q[i]);
    }
  }
};

template <class Filter> struct Outputs {
  using S = typename Filter::Scalar;
  std::vector<S> quat, bias, sigma, att;
  explicit Outputs(int n) : quat(4 * n), bias(3 * n), sigma(6 * n), att(3 * n) {}
};

template <class Filter>
void run(const Rotation& r, std::size_t segment, Outputs<Filter>& fwd, Outputs<Filter>& sm) {
  using S = typename Filter::Scalar;
  using Model = typename AttitudeRtsModelOf<Filter>::type;
  const std::vector<S> gyr(r.gyr.begin(), r.gyr.end()), acc(r.acc.begin(), r.acc.end()),
      mag(r.mag.begin(), r.mag.end()), dt(r.n, S(r.dt));
  // The paper's plain filters (no rest detection, low-pass or disturbance tests): the simulation
  // has none of what those parts are for, and the smoother's model is the plain filter's.
  typename Filter::Params p = Filter::Params::paper();
  p.gyro_noise = S(0.003 * std::sqrt(r.dt));
  p.gyro_bias_noise = S(1e-6);
  p.acc_sigma = S(0.05 / 9.81);
  p.mag_sigma = S(0.01);
  p.init_gyro_bias_sigma = S(0.02);
  Filter f(p);
  f.set_mag_dip(S(std::atan2(0.9, 0.4)));
  Model model(f, gyr.data(), dt.data());
  RtsSmoother<Model> smoother(model);
  ASSERT_TRUE(smoother.reserve(r.n, r.n, segment));
  std::vector<std::uint32_t> fl(r.n);
  run_attitude_batch(f, gyr.data(), acc.data(), mag.data(), dt.data(), r.n, fwd.quat.data(), fwd.bias.data(),
                     fwd.sigma.data(), fwd.att.data(), fl.data(), smoother);
  AttitudeSmoothedOutput<Model> out{sm.quat.data(), sm.bias.data(), sm.sigma.data(), sm.att.data()};
  Eigen::internal::set_is_malloc_allowed(false);
  const auto res = smoother.smooth(out);
  Eigen::internal::set_is_malloc_allowed(true);
  ASSERT_EQ(res, RtsSmoother<Model>::Result::Ok);
  EXPECT_EQ(smoother.records(), std::size_t(r.n));  // every sample updates with the accelerometer
}

template <class Filter> void check(double rel, double ratio) {
  using S = typename Filter::Scalar;
  const Rotation r;
  Outputs<Filter> fwd(r.n), sm(r.n), fwd2(r.n), sm2(r.n);
  run<Filter>(r, 256, fwd, sm);
  double ef = 0, es = 0;
  for (int k = 300; k < r.n; ++k) {
    const Quat<double> qt = Eigen::Map<const Quat<double>>(&r.q_true[4 * k]);
    auto err = [&](const std::vector<S>& q) {
      const Quat<double> qe = Eigen::Map<const Quat<S>>(&q[4 * k]).template cast<double>();
      return quat::to_rotvec(quat::mul(quat::conj(qe), qt)).squaredNorm();
    };
    ef += err(fwd.quat);
    es += err(sm.quat);
    for (int i = 0; i < 6; ++i) EXPECT_LE(sm.sigma[6 * k + i], fwd.sigma[6 * k + i] * (1 + rel) + 1e-15) << k;
  }
  EXPECT_LT(es, ratio * ef) << "attitude RMSE smoothed " << std::sqrt(es / (r.n - 300)) << " forward "
                            << std::sqrt(ef / (r.n - 300));
  for (int i = 0; i < 4; ++i) EXPECT_EQ(sm.quat[4 * (r.n - 1) + i], fwd.quat[4 * (r.n - 1) + i]);
  run<Filter>(r, 3, fwd2, sm2);
  EXPECT_TRUE(sm2.quat == sm.quat && sm2.sigma == sm.sigma);
}

}  // namespace

// Measured on this rotation (RMS attitude error after 3 s, smoothed against forward; the ratio of
// the summed squares in brackets): QuaternionEKF 0.82 against 1.09 mrad (0.57), EulerEKF 1.98
// against 5.36 mrad (0.14), float and double alike.
TEST(AttitudeSmoother, QuaternionEKF) { check<QuaternionEKF<double>>(1e-9, 0.75); }
TEST(AttitudeSmoother, QuaternionEKFFloat) { check<QuaternionEKF<float>>(1e-4, 0.75); }
TEST(AttitudeSmoother, EulerEKF) { check<EulerEKF<double>>(1e-9, 0.3); }
TEST(AttitudeSmoother, EulerEKFFloat) { check<EulerEKF<float>>(1e-4, 0.3); }
