// QuaternionEKF (the 6-state error-state form of paper 000's filter): Jacobians against finite
// differences, no heap in any step, bad input leaves the state untouched bit for bit, agreement
// with the 7-state QuaternionEKFPaper on clean data, the startup gyro-bias case, NEES on noisy runs.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>

#include <quatnav/attitude/batch.hpp>
#include <quatnav/attitude/quaternion_ekf.hpp>
#include <quatnav/attitude/quaternion_ekf_paper.hpp>

#include "consistency.hpp"
#include "random_matrix.hpp"
#include "same_fields.hpp"

using namespace quatnav;

template <class S> class Eskf : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Eskf, Scalars);

namespace {

/// A clean three-axis rotation (|w| about 0.2-0.8 rad/s) at 200 Hz with a dipping field.
struct Clean {
  std::vector<Vec4<double>> q;
  std::vector<Vec3<double>> gyr, acc, mag;
  double dt = 0.005;
};

Clean clean_rotation(double seconds, const Vec3<double>& bias) {
  Clean c;
  const int n = int(seconds / c.dt);
  Quat<double> q = quat::from_euler<double>(0.2, -0.1, 0.5);
  const Vec3<double> g_n(0, 0, -9.81), m_n(20, 0, 40);
  for (int k = 0; k < n; ++k) {
    const double t = k * c.dt;
    const Vec3<double> w(0.45 * std::sin(0.7 * t + 0.3), 0.45 * std::cos(0.5 * t), 0.35 * std::sin(0.3 * t + 1.0) + 0.2);
    if (k > 0) q = quat::normalized(quat::mul(q, quat::from_rotvec<double>(Vec3<double>(w * c.dt))));
    c.q.push_back(q);
    c.gyr.push_back(w + bias);
    c.acc.push_back(quat::rotate_inv(q, g_n));
    c.mag.push_back(quat::rotate_inv(q, m_n));
  }
  return c;
}

template <class F> double rmse_second_half_deg(F& f, const Clean& c) {
  using S = typename F::Scalar;
  const int n = int(c.q.size());
  double se = 0;
  int cnt = 0;
  for (int k = 0; k < n; ++k) {
    if (k == 0) {
      f.initialize(c.acc[0].cast<S>(), c.mag[0].cast<S>());
    } else {
      f.predict(c.gyr[k].cast<S>(), S(c.dt));
      f.update_acc(c.acc[k].cast<S>());
      f.update_mag(c.mag[k].cast<S>());
    }
    if (k >= n / 2) {
      const double e = quat::angle_between<double>(f.quat().template cast<double>(), c.q[k]);
      se += e * e;
      ++cnt;
    }
  }
  return std::sqrt(se / cnt) * 180.0 / M_PI;
}

}  // namespace

TEST(EskfJacobian, DirectionModelMatchesFiniteDifferences) {
  const Quat<double> q = quat::from_euler<double>(0.3, -0.4, 1.1);
  const Vec3<double> r(0.4, 0.1, 0.9);
  Vec3<double> h;
  Mat3<double> H;  // the attitude block; h does not depend on the gyro bias
  detail::eskf_direction_model<double>(q, r, h, H);
  const double e = 1e-6;
  for (int j = 0; j < 3; ++j) {
    Vec3<double> d = Vec3<double>::Zero();
    d[j] = e;
    Vec3<double> hp, hm;
    Mat3<double> tmp;
    detail::eskf_direction_model<double>(quat::mul(q, quat::from_rotvec<double>(d)), r, hp, tmp);
    detail::eskf_direction_model<double>(quat::mul(q, quat::from_rotvec<double>(Vec3<double>(-d))), r, hm, tmp);
    EXPECT_LT(((hp - hm) / (2 * e) - H.col(j)).norm(), 1e-8) << j;
  }
}

TEST(EskfJacobian, HeadingModelMatchesFiniteDifferences) {
  const Quat<double> q = quat::from_euler<double>(0.2, 0.3, -2.0);
  const Vec3<double> m = Vec3<double>(0.3, -0.5, 0.8).normalized();
  double h, h2;
  Vec3<double> u, vt;
  ASSERT_TRUE(detail::eskf_heading_model<double>(q, m, h, h2, u, vt));
  const Vec3<double> full = u + vt;  // dh/ddtheta: the yaw part u^T plus the tilt part
  const double e = 1e-6;
  for (int j = 0; j < 3; ++j) {
    Vec3<double> d = Vec3<double>::Zero();
    d[j] = e;
    double hp, hm, t;
    Vec3<double> a, b;
    detail::eskf_heading_model<double>(quat::mul(q, quat::from_rotvec<double>(d)), m, hp, t, a, b);
    detail::eskf_heading_model<double>(quat::mul(q, quat::from_rotvec<double>(Vec3<double>(-d))), m, hm, t, a, b);
    EXPECT_NEAR(quat::wrap_pi(hp - hm) / (2 * e), full[j], 1e-7) << j;
  }
}

TEST(EskfJacobian, TransitionMatchesFiniteDifferences) {
  // dtheta+ = F dtheta - dt db to first order: perturb the true state and compare errors.
  const Quat<double> q = quat::from_euler<double>(0.1, 0.2, 0.3);
  const Vec3<double> b(0.01, -0.02, 0.03), w(0.5, -0.7, 0.4);
  const double dt = 0.01, e = 1e-6;
  Quat<double> q1;
  Mat3<double> F;
  detail::eskf_propagate<double>(q, b, w, dt, q1, F);
  for (int j = 0; j < 6; ++j) {
    Vec<double, 6> dx = Vec<double, 6>::Zero();
    dx[j] = e;
    const Quat<double> qt = quat::mul(q, quat::from_rotvec<double>(Vec3<double>(dx.head<3>())));
    Quat<double> qt1;
    Mat3<double> Ft;
    detail::eskf_propagate<double>(qt, Vec3<double>(b + dx.tail<3>()), w, dt, qt1, Ft);
    const Vec3<double> err = quat::to_rotvec<double>(quat::mul(quat::conj(q1), qt1)) / e;
    Vec3<double> expect = j < 3 ? Vec3<double>(F.col(j)) : Vec3<double>(-dt * Vec3<double>::Unit(j - 3));
    // the bias column is -dt J_r(w~ dt) = -dt (I - [w~ dt x]/2 + ...): -dt I up to |w~| dt^2 / 2
    EXPECT_LT((err - expect).norm(), j < 3 ? 1e-8 : 0.6 * (w - b).norm() * dt * dt) << j;
  }
}

TYPED_TEST(Eskf, PredictCovarianceMatchesDenseProduct) {
  using S = TypeParam;
  Mat<S, 6, 6> P;
  P << 4, 1, 0, 1, 0, 0, 1, 3, 1, 0, 1, 0, 0, 1, 2, 0, 0, 1, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0, 2;
  P *= S(0.01);
  const Mat3<S> F = quat::to_rotmat(quat::from_rotvec<S>(Vec3<S>(S(0.01), S(-0.02), S(0.005)))).transpose();
  const S dt = S(0.01), qa = S(1e-6), qb = S(1e-9);
  Mat<S, 6, 6> Phi = Mat<S, 6, 6>::Identity();
  Phi.template topLeftCorner<3, 3>() = F;
  Phi.template topRightCorner<3, 3>() = -dt * Mat3<S>::Identity();
  Mat<S, 6, 6> Qn = Mat<S, 6, 6>::Zero();
  Qn.diagonal() << qa, qa, qa, qb, qb, qb;
  const Mat<S, 6, 6> dense = Phi * P * Phi.transpose() + Qn;
  Mat<S, 6, 6> Pb = P;
  detail::eskf_predict_covariance<S>(Pb, F, dt, qa, qb);
  EXPECT_LT((Pb - dense).norm(), sizeof(S) == 4 ? 1e-7 : 1e-15);
  EXPECT_EQ(Pb, Pb.transpose());
  Mat<S, 6, 6> Po;  // out of place (what predict() runs): the same bits
  detail::eskf_predict_covariance<S>(P, F, dt, qa, qb, Po);
  EXPECT_EQ(Po, Pb);
}

TYPED_TEST(Eskf, NoHeapInAnyStepAndBatch) {
  using S = TypeParam;
  const Clean c = clean_rotation(3.0, Vec3<double>(0.01, -0.02, 0.015));
  const int n = int(c.q.size());
  std::vector<S> gyr(3 * n), acc(3 * n), mag(3 * n), dt(n, S(c.dt)), qo(4 * n), so(6 * n), ao(3 * n);
  std::vector<std::uint32_t> fl(n);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i) {
      gyr[3 * k + i] = S(c.gyr[k][i]);
      acc[3 * k + i] = S(c.acc[k][i]);
      mag[3 * k + i] = S(c.mag[k][i]);
    }
  QuaternionEKF<S> f;
  Eigen::internal::set_is_malloc_allowed(false);
  run_attitude_batch(f, gyr.data(), acc.data(), mag.data(), dt.data(), std::size_t(n), qo.data(),
                     static_cast<S*>(nullptr), so.data(), ao.data(), fl.data());
  f.update_acc_mag(Vec3<S>(Eigen::Map<const Vec3<S>>(acc.data())), Vec3<S>(Eigen::Map<const Vec3<S>>(mag.data())));
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(f.quat().allFinite());
}

TYPED_TEST(Eskf, BadInputLeavesStateUntouched) {
  using S = TypeParam;
  auto p = QuaternionEKFParams<S>();
  p.acc.acc_reject = S(2);
  p.mag.mag_settle_time = S(0.2);
  QuaternionEKF<S> f(p);
  const Clean c = clean_rotation(1.0, Vec3<double>(0.01, -0.02, 0.015));
  f.initialize(c.acc[0].cast<S>(), c.mag[0].cast<S>());
  for (int k = 1; k < int(c.q.size()); ++k) {
    f.predict(c.gyr[k].cast<S>(), S(c.dt));
    f.update_acc(c.acc[k].cast<S>());
    f.update_mag(c.mag[k].cast<S>());
  }
  const auto before = f.state();
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  EXPECT_EQ(f.predict(Vec3<S>(nan, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(Vec3<S>(inf, S(0), S(0)), S(0.01)), Status::NonFinite);
  EXPECT_EQ(f.predict(Vec3<S>::Zero(), S(-1)), Status::InvalidDt);
  EXPECT_EQ(f.predict(Vec3<S>::Zero(), S(0)), Status::InvalidDt);
  EXPECT_EQ(f.update_acc(Vec3<S>(S(0), nan, S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_acc(Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_mag(Vec3<S>(nan, S(0), S(0))).status, Status::NonFinite);
  EXPECT_EQ(f.update_mag(Vec3<S>::Zero()).status, Status::ZeroNorm);
  EXPECT_EQ(f.update_acc_mag(Vec3<S>::Zero(), Vec3<S>::UnitX()).status, Status::ZeroNorm);
  Mat<S, 6, 6> bad = Mat<S, 6, 6>::Identity();
  bad(0, 0) = nan;
  EXPECT_EQ(f.reset(quat::identity<S>(), Vec3<S>::Zero(), bad), Status::NonFinite);
  const auto after = f.state();
  EXPECT_TRUE(quatnav_test::same_fields(before, after));
}

// Covariance health (the top of quaternion_ekf.hpp): after every time update P - cov_floor I is
// positive definite, whether the filter proved it or tested it; a covariance from outside
// (set_state, reset) that is indefinite is floored by the next time update; and a filter restored
// from state() (which tests where the original proved) gives the same bits.
TYPED_TEST(Eskf, CovarianceHealthyAfterEveryTimeUpdate) {
  using S = TypeParam;
  const Clean c = clean_rotation(20.0, Vec3<double>(0.01, -0.02, 0.015));
  const int n = int(c.q.size());
  std::mt19937 g(5);
  std::normal_distribution<double> nd;
  const auto noisy = [&](const Vec3<double>& v, double sd) { return Vec3<double>(v + sd * Vec3<double>(nd(g), nd(g), nd(g))); };
  std::vector<Vec3<double>> gyr(n), acc(n), mag(n);
  for (int k = 0; k < n; ++k) {
    gyr[k] = noisy(c.gyr[k], 0.01);
    acc[k] = noisy(c.acc[k], 0.05);
    mag[k] = noisy(c.mag[k], 0.2);
  }
  for (const double sigma : {0.4, 0.005}) {  // the default and a strong accelerometer and magnetometer
    auto p = QuaternionEKFParams<S>();
    p.acc_sigma = S(sigma);
    p.mag_sigma = S(sigma);
    QuaternionEKF<S> f(p), restored(p);
    const auto healthy = [&](const QuaternionEKF<S>& x) {
      Mat<S, 6, 6> shifted = x.covariance();
      shifted.diagonal().array() -= p.cov_floor;
      return detail::has_cholesky<S, 6>(shifted);
    };
    int unhealthy = 0, provable = 0;
    const S qa = S(c.dt) * p.gyro_noise * p.gyro_noise, qb = S(c.dt) * p.gyro_bias_noise * p.gyro_bias_noise;
    f.initialize(acc[0].cast<S>(), mag[0].cast<S>());
    for (int k = 1; k < n; ++k) {
      if (k == n / 4 || k == n / 2) {  // an indefinite covariance from outside: |P01| > sqrt(P00 P11)
        auto st = f.state();
        st.P(0, 1) = st.P(1, 0) = S(1.5) * std::sqrt(st.P(0, 0) * st.P(1, 1));
        if (k == n / 4) {
          ASSERT_EQ(f.set_state(st), Status::Ok);
        } else {
          ASSERT_EQ(f.reset(st.q_nb, st.gyro_bias, st.P), Status::Ok);
        }
        ASSERT_FALSE(healthy(f));
      }
      if (k == 3 * n / 4) ASSERT_EQ(restored.set_state(f.state()), Status::Ok);
      for (QuaternionEKF<S>* x : {&f, &restored}) {
        if (k < 3 * n / 4 && x == &restored) continue;
        ASSERT_EQ(x->predict(gyr[k].cast<S>(), S(c.dt)), Status::Ok);
        unhealthy += x == &f && !healthy(*x);
        provable += x == &f && detail::eskf_floor_implied<S, 6>(x->covariance(), qa, qb, p.cov_floor);
        x->update_acc(acc[k].cast<S>());
        x->update_mag(mag[k].cast<S>());
      }
      if (k >= 3 * n / 4) ASSERT_TRUE(quatnav_test::same_fields(f.state(), restored.state())) << "sample " << k;
    }
    EXPECT_EQ(unhealthy, 0) << "sigma " << sigma;
    // The proof is what runs in float64 (so the tests above exercise it); float32's rounding bound
    // exceeds the margin of the defaults, and the LDL^T test runs every sample.
    if (sizeof(S) == 8) {
      EXPECT_GT(provable, n * 9 / 10) << "sigma " << sigma;
    } else {
      EXPECT_EQ(provable, 0) << "sigma " << sigma;
    }
  }
}

TYPED_TEST(Eskf, HeadingOnlyMagnetometerNeverTilts) {
  using S = TypeParam;
  auto p = QuaternionEKFParams<S>::paper();
  p.mag_heading_only = true;
  QuaternionEKF<S> f(p);
  const Quat<S> q = quat::from_euler<S>(S(0.3), S(-0.2), S(1.0));
  const Vec3<S> acc = quat::rotate_inv(q, Vec3<S>(S(0), S(0), S(-9.81)));
  const Vec3<S> mag = quat::rotate_inv(q, Vec3<S>(S(20), S(0), S(40)));
  ASSERT_EQ(f.initialize(acc, mag), Status::Ok);
  const Vec3<S> down = quat::rotate_inv(f.quat(), Vec3<S>(S(0), S(0), S(1)));
  const Vec3<S> bad = quat::rotate(quat::from_rotvec<S>(Vec3<S>(S(0.2), S(0.3), S(0.1))), mag);
  const auto r = f.update_mag(bad);
  ASSERT_EQ(r.status, Status::Ok);
  EXPECT_GT(std::abs(r.innovation[0]), S(0.05));
  const Vec3<S> down2 = quat::rotate_inv(f.quat(), Vec3<S>(S(0), S(0), S(1)));
  EXPECT_LT((down2 - down).norm(), sizeof(S) == 4 ? 1e-5 : 1e-12);
}

TYPED_TEST(Eskf, AccelerometerTurnsNeitherHeadingNorVerticalBias) {
  // A 6D run (no heading aid) leaves P with strong heading-bias correlations; an accelerometer
  // sample whose direction is off by 3 deg then corrects the tilt and the horizontal bias, but
  // neither the heading nor the earth-vertical bias (the Schmidt-Kalman update of the top of
  // quaternion_ekf.hpp), and its NIS and innovation covariance are the optimal update's.
  using S = TypeParam;
  const Clean c = clean_rotation(20.0, Vec3<double>(0.01, -0.02, 0.015));
  auto p = QuaternionEKFParams<S>::paper();  // no low-pass: the sample is used as it is
  p.acc_tilt_only = true;
  QuaternionEKF<S> f(p);
  ASSERT_EQ(f.initialize(c.acc[0].cast<S>()), Status::Ok);
  for (std::size_t k = 1; k < c.q.size(); ++k) {
    f.predict(c.gyr[k].cast<S>(), S(c.dt));
    f.update_acc(c.acc[k].cast<S>());
  }
  p.acc_tilt_only = false;  // the same state with the paper's optimal gain
  QuaternionEKF<S> optimal(p);
  ASSERT_EQ(optimal.set_state(f.state()), Status::Ok);
  const Quat<S> q0 = f.quat();
  const Vec3<S> b0 = f.bias();
  const Mat<S, 6, 6> P0 = f.covariance();
  const Vec3<S> u = quat::rotate_inv(q0, Vec3<S>(S(0), S(0), S(1)));  // the vertical, body frame
  ASSERT_GT(std::abs(P0.template block<3, 3>(0, 3).row(2).norm()), S(0));
  const Vec3<S> acc = quat::rotate_inv(quat::mul(quat::from_rotvec<S>(Vec3<S>(S(0.04), S(-0.03), S(0))), q0),
                                       Vec3<S>(S(0), S(0), S(-9.81)));
  const auto r = f.update_acc(acc);
  ASSERT_EQ(r.status, Status::Ok);
  const Quat<S> e = quat::mul(f.quat(), quat::conj(q0));  // the correction, navigation frame
  const double tol = sizeof(S) == 4 ? 2e-6 : 1e-13;
  EXPECT_GT(std::hypot(double(e[1]), double(e[2])), 5e-5);   // the tilt moved
  EXPECT_LT(std::abs(double(e[3] / e[0])), tol);               // the heading did not
  EXPECT_LT(std::abs(double(u.dot(f.bias() - b0))), tol * 1e-2);  // nor the vertical bias
  EXPECT_GT((f.bias() - b0).norm(), S(1e-7));                  // the horizontal one did
  const auto ro = optimal.update_acc(acc);
  ASSERT_EQ(ro.status, Status::Ok);
  const Quat<S> eo = quat::mul(optimal.quat(), quat::conj(q0));
  EXPECT_GT(std::abs(double(eo[3] / eo[0])), 100 * tol + 1e-6);  // acc_tilt_only = false: it turns
  EXPECT_NEAR(double(ro.nis), double(r.nis), sizeof(S) == 4 ? 1e-4 : 1e-12);  // with the same NIS
  // NIS and S as the optimal joint update of the same rows (dense, in double)
  Vec3<double> h = quat::rotate_inv(Quat<double>(q0.template cast<double>()), Vec3<double>(0, 0, -1));
  Mat<double, 3, 6> H = Mat<double, 3, 6>::Zero();
  H.template leftCols<3>() = quat::skew<double>(h);
  // the accelerometer part low-passes the sample; its innovation is what the update used
  const Vec3<double> y = r.innovation.template cast<double>();
  const double sig = f.params().acc_sigma;
  const Mat3<double> Sd = H * P0.template cast<double>() * H.transpose() + sig * sig * Mat3<double>::Identity();
  EXPECT_NEAR(double(r.nis), y.dot(Sd.ldlt().solve(y)), sizeof(S) == 4 ? 1e-3 : 1e-9);
  EXPECT_LT((r.innovation_cov.template cast<double>() - Sd).norm(), sizeof(S) == 4 ? 1e-4 : 1e-12);
}

TYPED_TEST(Eskf, PaperParametersAgreeWithSevenStateFilter) {
  using S = TypeParam;
  const Clean c = clean_rotation(10.0, Vec3<double>(0.01, -0.02, 0.015));
  QuaternionEKF<S> e(QuaternionEKFParams<S>::paper());
  QuaternionEKFPaper<S> f(QuaternionEKFParams<S>::paper());
  const double re = rmse_second_half_deg(e, c), rf = rmse_second_half_deg(f, c);
  EXPECT_LT(re, 0.2);
  EXPECT_LT(std::abs(re - rf), 0.05);
  EXPECT_LT((e.bias() - f.bias()).norm(), 1e-3);
}

TYPED_TEST(Eskf, StartupBiasWithDefaults) {
  // 30 s clean rotation with a constant gyro bias: below 0.5 deg over the second half.
  using S = TypeParam;
  const Clean c = clean_rotation(30.0, Vec3<double>(0.01, -0.02, 0.015));
  QuaternionEKF<S> e;
  EXPECT_LT(rmse_second_half_deg(e, c), 0.5);
  EXPECT_LT((e.bias().template cast<double>() - Vec3<double>(0.01, -0.02, 0.015)).norm(), 1e-3);
}

namespace {

/// Per-run means of the NEES per dof of [dtheta, db] (6 dof) over the second half of each run:
/// the paper's plain filter (no robustness parts) on a rotation whose gyro noise and bias random
/// walk and whose accelerometer and magnetometer noise are the filter's model (the true noise);
/// the filter is told Q, R and P0 times quatnav_test::variance_scale().
std::vector<double> eskf_nees_per_run(int runs) {
  const auto truth = QuaternionEKFParams<double>::paper();
  auto p = truth;
  p.mag_heading_only = false;
  p.gyro_noise = quatnav_test::scaled_sigma(truth.gyro_noise);
  p.gyro_bias_noise = quatnav_test::scaled_sigma(truth.gyro_bias_noise);
  p.acc_sigma = quatnav_test::scaled_sigma(truth.acc_sigma);
  p.mag_sigma = quatnav_test::scaled_sigma(truth.mag_sigma);
  const double c = quatnav_test::variance_scale();
  const int n = 2000;
  const double dt = 0.01;
  std::vector<double> out;
  for (int r = 0; r < runs; ++r) {
    std::mt19937 rng(100 + r);
    std::normal_distribution<double> nd(0.0, 1.0);
    auto randn3 = [&] { return Vec3<double>(nd(rng), nd(rng), nd(rng)); };
    Quat<double> q = quat::from_euler<double>(0.1, -0.2, 0.3);
    Vec3<double> b = truth.init_gyro_bias_sigma * randn3();
    QuaternionEKF<double> f(p);
    const Vec3<double> g_n(0, 0, -1), m_n = Vec3<double>(0.5, 0, 0.8).normalized();
    // start from the truth perturbed by the initial covariance
    Mat<double, 6, 6> P0 = Mat<double, 6, 6>::Zero();
    P0.diagonal() << Vec3<double>::Constant(c * truth.init_att_sigma * truth.init_att_sigma),
        Vec3<double>::Constant(c * truth.init_gyro_bias_sigma * truth.init_gyro_bias_sigma);
    f.reset(quat::mul(q, quat::from_rotvec<double>(Vec3<double>(truth.init_att_sigma * randn3()))),
            Vec3<double>::Zero(), P0);
    f.set_mag_dip(std::atan2(m_n[2], m_n[0]));
    double nees = 0;
    int cnt = 0;
    for (int k = 1; k < n; ++k) {
      const double t = k * dt;
      const Vec3<double> w(0.5 * std::sin(0.5 * t), 0.4 * std::cos(0.3 * t), 0.3);
      q = quat::normalized(quat::mul(q, quat::from_rotvec<double>(Vec3<double>(w * dt))));
      const Vec3<double> gyr = w + b + truth.gyro_noise / std::sqrt(dt) * randn3();
      b += truth.gyro_bias_noise * std::sqrt(dt) * randn3();
      f.predict(gyr, dt);
      f.update_acc(Vec3<double>(quat::rotate_inv(q, g_n) + truth.acc_sigma * randn3()));
      f.update_mag(Vec3<double>(quat::rotate_inv(q, m_n) + truth.mag_sigma * randn3()));
      if (k > n / 2) {
        Vec<double, 6> e;
        e << quat::to_rotvec<double>(quat::mul(quat::conj(f.quat()), q)), b - f.bias();
        nees += e.dot(f.covariance().ldlt().solve(e)) / 6.0;
        ++cnt;
      }
    }
    out.push_back(nees / cnt);
  }
  return out;
}

}  // namespace

TEST(EskfConsistency, NeesWithinChiSquareBounds) {
  // The mean over runs and the second half of each run (1000 samples) of the NEES per dof within
  // the two-sided 99 % interval of runs * 6 * kMeff dof (tests/cpp/consistency.hpp), sized to
  // reject 1.5x over- or under-confidence with probability >= 99 %. kMeff, the independent
  // samples a run is worth, is measured (MeasureIndependentSamplesPerRun: with 400 runs the
  // per-run means vary as 1.7 independent 6-dof samples would, their mean 1.000); kMeff = 1.4
  // (80 % of it, for the estimate's 7 % standard error): 40 x 6 x 1.4 = 336 dof, [0.81, 1.21].
  constexpr int kRuns = 40;
  constexpr double kMeff = 1.4;
  const std::vector<double> r = eskf_nees_per_run(kRuns);
  double nees = 0;
  for (double x : r) nees += x / kRuns;
  const auto iv = quatnav_test::chi2_interval_99(kRuns * 6 * kMeff);
  ASSERT_TRUE(iv.powerful) << "too few runs for the power against 1.5x";
  EXPECT_GT(nees, iv.lo);
  EXPECT_LT(nees, iv.hi);
  std::printf("ESKF NEES / dof (%d runs, variance scale %g): %.3f, interval [%.3f, %.3f]\n", kRuns,
              quatnav_test::variance_scale(), nees, iv.lo, iv.hi);
}

// The measurement behind kMeff (disabled: --gtest_also_run_disabled_tests --gtest_filter=*Measure*).
TEST(EskfConsistency, DISABLED_MeasureIndependentSamplesPerRun) {
  const std::vector<double> r = eskf_nees_per_run(400);
  double m = 0, v = 0;
  for (double x : r) m += x / double(r.size());
  for (double x : r) v += (x - m) * (x - m) / double(r.size() - 1);
  std::printf("independent 6-dof samples per run: %.1f (mean NEES / dof %.3f)\n", 2.0 / (6.0 * v), m);
}

// The block Joseph update for any gain (here a random, non-optimal one) against the dense
// Joseph form (I - K H) P (I - K H)^T + K R K^T of joseph_update (core/kalman.hpp), for a dense
// H; exactly symmetric. Odd and even N (columns that start above their diagonal), float and double.
template <class S, int N, int M> void expect_block_joseph_is_joseph(unsigned seed, double tol) {
  quatnav_test::Randn rnd(seed);
  const Mat<double, N, N> Pd = rnd.spd<Mat<double, N, N>>(0.5);
  const Mat<double, M, N> Hd = rnd.matrix<Mat<double, M, N>>();
  const Mat<double, N, M> Kd = rnd.matrix<Mat<double, N, M>>() * 0.3;
  const Mat<double, M, M> Rd = rnd.spd<Mat<double, M, M>>(0.2);
  Mat<double, N, N> ref;
  joseph_update<double, N, M, 0, N>(Pd, Kd, Hd, Rd, ref);
  const Mat<S, N, M> A = (Pd * Hd.transpose()).template cast<S>();
  const Mat<S, M, M> Sm = (Hd * Pd * Hd.transpose() + Rd).template cast<S>();
  Mat<S, N, N> P = Pd.template cast<S>();
  detail::joseph_update_block<S, N, M>(P, Mat<S, N, M>(Kd.template cast<S>()), A, Sm);
  EXPECT_LT((P.template cast<double>() - ref).norm(), tol * ref.norm()) << "N = " << N << ", M = " << M;
  EXPECT_TRUE(P == P.transpose());
}

TEST(EskfGravity, BlockJosephIsTheJosephForm) {
  expect_block_joseph_is_joseph<double, 6, 2>(11, 1e-13);
  expect_block_joseph_is_joseph<double, 7, 3>(12, 1e-13);
  expect_block_joseph_is_joseph<double, 15, 2>(13, 1e-13);
  expect_block_joseph_is_joseph<float, 6, 2>(14, 1e-5);
  expect_block_joseph_is_joseph<float, 9, 3>(15, 1e-5);
}

// The accelerometer's three gravity rows as two rows in the tangent plane of h (one 2-row
// block) give what the three sequential scalar rows give: the same corrected covariance,
// correction, NIS and body-axes innovation covariance, with the heading-free (Schmidt) gain
// and with the optimal one, for random covariances, attitudes and readings (h near an axis
// too, where the basis changes axis). A gated reading is refused before P is touched.
TEST(EskfGravity, TangentPlaneRowsAreTheThreeRows) {
  quatnav_test::Randn rnd(21);
  for (int trial = 0; trial < 60; ++trial) {
    const Mat<double, 6, 6> P0 = rnd.spd<Mat<double, 6, 6>>(0.05) * 1e-3;
    Vec3<double> h = rnd.matrix<Vec3<double>>();
    if (trial % 4 == 0) h = Vec3<double>(1e-3 * h[0], 2e-3 * h[1], -1.0);  // nearly level
    h.normalize();
    const Vec3<double> u = -h;
    Vec3<double> v = h + 0.05 * rnd.matrix<Vec3<double>>();
    v.normalize();
    const Vec3<double> y = v - h;
    const double r = 0.02 * (1 + trial % 3);
    Mat3<double> W = Mat3<double>::Identity() - u * u.transpose();
    if (trial % 2) W *= 0.5;
    for (int rows : {3, 0}) {  // heading-free (acc_tilt_only), optimal
      const detail::HeadingFreeRows<double> gain{u, W, rows};
      Mat<double, 6, 6> P_ref = P0;
      Vec<double, 6> dx_ref;
      UpdateResult<double, 3> res_ref;
      kalman_correct_diagonal_in_place<double, 6, 3, 0, 3, RowShape::Cross>(
          P_ref, Mat3<double>(quat::skew(h)), Vec3<double>::Constant(r), y, dx_ref, res_ref, 0.0, gain);
      ASSERT_EQ(res_ref.status, Status::Ok);
      Mat<double, 6, 6> P = P0;
      Vec<double, 6> dx;
      UpdateResult<double, 3> res;
      ASSERT_EQ(detail::eskf_gravity_correct<double>(P, h, y, r, dx, res, 0.0, gain), Status::Ok);
      EXPECT_LT((P - P_ref).norm(), 1e-12 * P_ref.norm()) << trial << " " << rows;
      EXPECT_TRUE(P == P.transpose());
      EXPECT_LT((dx - dx_ref).norm(), 1e-12 * dx_ref.norm() + 1e-18) << trial << " " << rows;
      EXPECT_NEAR(res.nis, res_ref.nis, 1e-11 * res_ref.nis) << trial;
      EXPECT_LT((res.innovation_cov - res_ref.innovation_cov).norm(), 1e-12 * res_ref.innovation_cov.norm());
      EXPECT_TRUE(res.innovation == y);
      if (rows) EXPECT_NEAR(u.dot(dx.head<3>()), 0.0, 1e-15);  // no heading correction
      // Gated below its NIS: refused, P untouched bit for bit.
      Mat<double, 6, 6> Pg = P0;
      UpdateResult<double, 3> rg;
      EXPECT_EQ(detail::eskf_gravity_correct<double>(Pg, h, y, r, dx, rg, 0.5 * res.nis, gain), Status::Rejected);
      EXPECT_EQ(std::memcmp(Pg.data(), P0.data(), sizeof(P0)), 0);
    }
  }
}
