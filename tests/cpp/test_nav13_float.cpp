// NavFilter13 in float32 against float64 over a long run: the carried position (double for every
// Scalar) and the unscented time update, whose sigma points come from covariance_factor
// (unscented.hpp: a Cholesky on the correlation scale that repairs accumulated round-off).
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/nav/nav_filter13.hpp>
#include <random>
#include <type_traits>
#include <vector>

#include "random_matrix.hpp"

using namespace quatnav;
using quatnav_test::Randn;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr int kSamples = 4501;  // 45 s at 100 Hz

/// A paper-002-like recording without Earth rotation (so the truth is a flat-Earth kinematic
/// model the filter's mechanization reproduces exactly): level robot at 2 m/s on a straight line,
/// heading 30 deg (the first 30 s of paper 002's run); IMU 100 Hz with the paper's noise and
/// biases (1000 ug, 1 deg/h); NED velocity (0.1 ft/s) and yaw (2 deg) at 10 Hz.
struct Recording {
  std::vector<Vec3<double>> f, w, v_meas, v_true;
  std::vector<double> yaw_meas, yaw_true;
  double dt = 0.01;
  double lat0 = 0.635, lon0 = 2.22, h0 = 50.0, psi0 = 30.0 * kDeg;
  double accel_noise = 2.942e-5, gyro_noise = 1.4544e-7, vel_noise = 0.03048, yaw_noise = 2.0 * kDeg;
};

Recording make_recording(int n, unsigned seed) {
  Recording r;
  std::mt19937 g(seed);
  std::normal_distribution<double> nd;
  const double g0 = earth::gravity<double>(r.lat0, r.h0);
  const Vec3<double> b_a = Vec3<double>::Constant(9.80665e-3), b_g = Vec3<double>::Constant(4.8481e-6);
  const double sa = r.accel_noise / std::sqrt(r.dt), sg = r.gyro_noise / std::sqrt(r.dt);
  const double psi = r.psi0;
  for (int k = 0; k < n; ++k) {
    // body FRD level, constant heading and speed: f_b = (0, 0, -g), omega_ib_b = 0 (no Earth rate)
    r.f.push_back(Vec3<double>(sa * nd(g), sa * nd(g), -g0 + sa * nd(g)) + b_a);
    r.w.push_back(Vec3<double>(sg * nd(g), sg * nd(g), sg * nd(g)) + b_g);
    const Vec3<double> v(2.0 * std::cos(psi), 2.0 * std::sin(psi), 0.0);
    r.v_true.push_back(v);
    r.yaw_true.push_back(psi);
    r.v_meas.push_back(v + r.vel_noise * Vec3<double>(nd(g), nd(g), nd(g)));
    r.yaw_meas.push_back(quat::wrap_pi(psi + r.yaw_noise * nd(g)));
  }
  return r;
}

struct RunResult {
  std::vector<Quat<double>> q;
  std::vector<Vec3<double>> v, llh;
  int predict_refused = 0, update_refused = 0;
};

/// Run filter F from the paper's initial errors (10/10/20 deg, 1 ft/s, biases unknown); aids
/// every 10th sample, velocity then yaw (as run_nav13_batch does).
template <class F> RunResult run(const Recording& r) {
  using S = typename F::Scalar;
  typename F::Params p;
  p.acc_noise = S(r.accel_noise);
  p.gyro_noise = S(r.gyro_noise);
  p.gps_vel_sigma = S(r.vel_noise);
  p.yaw_sigma = S(r.yaw_noise);
  p.earth_rotation = false;
  F f(p);
  const Quat<double> q0 = quat::from_euler(10.0 * kDeg, 10.0 * kDeg, r.psi0 + 20.0 * kDeg);
  Mat<double, 13, 12> Tb = detail::nav13_from_error(q0);
  Mat<double, 12, 12> Pe = Mat<double, 12, 12>::Zero();
  Pe.diagonal() << Vec3<double>::Constant(0.3048 * 0.3048), std::pow(10 * kDeg, 2), std::pow(10 * kDeg, 2),
      std::pow(20 * kDeg, 2), Vec3<double>::Constant(std::pow(0.0196, 2)), Vec3<double>::Constant(1e-10);
  const Mat<double, 13, 13> P0 = Tb * Pe * Tb.transpose();
  const Vec3<double> v0 = r.v_true[0] + Vec3<double>::Constant(0.3048);
  const Status s0 = f.reset(v0.cast<S>(), q0.cast<S>(), Vec3<S>::Zero(), Vec3<S>::Zero(),
                            P0.cast<S>(), r.lat0, r.lon0, r.h0);
  EXPECT_EQ(s0, Status::Ok);
  RunResult out;
  for (std::size_t k = 1; k < r.f.size(); ++k) {
    if (f.predict(r.w[k].cast<S>(), r.f[k].cast<S>(), S(r.dt)) != Status::Ok) ++out.predict_refused;
    if (k % 10 == 0) {
      if (f.update_velocity(r.v_meas[k].cast<S>()).status != Status::Ok) ++out.update_refused;
      if (f.update_yaw(S(r.yaw_meas[k])).status != Status::Ok) ++out.update_refused;
    }
    out.q.push_back(f.state().q_nb.template cast<double>());
    out.v.push_back(f.state().v_n.template cast<double>());
    out.llh.push_back(Vec3<double>(f.state().lat, f.state().lon, f.state().h));
  }
  return out;
}

double angle_deg(const Quat<double>& a, const Quat<double>& b) {
  return 2.0 * std::acos(std::min(1.0, std::abs(a.dot(b)) / (a.norm() * b.norm()))) / kDeg;
}

/// Largest difference of two runs: attitude (deg), velocity (m/s), horizontal position (m).
struct Diff {
  double att = 0, vel = 0, pos = 0;
};
Diff compare(const RunResult& a, const RunResult& b, const Recording& r) {
  Diff d;
  const earth::Radii<double> R = earth::radii<double>(r.lat0);
  for (std::size_t k = 0; k < a.q.size(); ++k) {
    d.att = std::max(d.att, angle_deg(a.q[k], b.q[k]));
    d.vel = std::max(d.vel, (a.v[k] - b.v[k]).norm());
    const double dn = (a.llh[k][0] - b.llh[k][0]) * (R.R_M + r.h0);
    const double de = (a.llh[k][1] - b.llh[k][1]) * (R.R_N + r.h0) * std::cos(r.lat0);
    d.pos = std::max(d.pos, std::hypot(dn, de));
  }
  return d;
}

}  // namespace

TEST(Nav13Float, PositionIsDoubleForEveryScalar) {
  static_assert(std::is_same<decltype(NavFilter13State<float>::lat), double>::value, "lat is double");
  static_assert(std::is_same<decltype(NavFilter13State<float>::lon), double>::value, "lon is double");
  static_assert(std::is_same<decltype(NavFilter13State<float>::h), double>::value, "h is double");
  // A float latitude (0.635 rad) resolves 0.38 m: 1 cm northward must still move the position.
  NavFilter13<float> f;
  ASSERT_EQ(f.reset(Vec3<float>(0.01f, 0.f, 0.f), Quat<float>(1, 0, 0, 0), Vec3<float>::Zero(), Vec3<float>::Zero(),
                    Mat<float, 13, 13>::Identity() * 1e-4f, 0.635, 2.22, 50.0),
            Status::Ok);
  const double lat0 = f.state().lat;
  ASSERT_EQ(f.predict(Vec3<float>::Zero(), Vec3<float>(0, 0, -9.7995f), 0.01f), Status::Ok);
  const double dn = (f.state().lat - lat0) * (earth::radii<double>(0.635).R_M + 50.0);
  EXPECT_NEAR(dn, 1e-4, 1e-6);  // 0.01 m/s for 0.01 s
  EXPECT_EQ(f.set_position(0.6350000001, 2.2200000001, 50.0), Status::Ok);
  EXPECT_EQ(f.state().lat, 0.6350000001);
  EXPECT_EQ(f.state().lon, 2.2200000001);
}

// 45 s at 2 m/s: float32 and float64 carry the same position (millimetres; a float latitude
// stays put at walking speed and ends tens of metres off), for every time update.
template <class F32, class F64> void expect_float_close(int n_refused_max, double att_deg, double vel_ms,
                                                        double pos_m) {
  const Recording r = make_recording(kSamples, 7);
  const RunResult a = run<F32>(r), b = run<F64>(r);
  EXPECT_EQ(b.predict_refused, 0);
  EXPECT_EQ(b.update_refused, 0);
  EXPECT_LE(a.predict_refused, n_refused_max);
  EXPECT_EQ(a.update_refused, 0);
  const Diff d = compare(a, b, r);
  EXPECT_LT(d.att, att_deg);
  EXPECT_LT(d.vel, vel_ms);
  EXPECT_LT(d.pos, pos_m);
  // the position moved: 45 s at 2 m/s on a heading of 30 deg, 78 m north
  const earth::Radii<double> R = earth::radii<double>(r.lat0);
  const double dn = (a.llh.back()[0] - r.lat0) * (R.R_M + r.h0);
  EXPECT_GT(std::abs(dn), 20.0);
  std::printf("float32 vs float64 over 45 s: attitude %.3g deg, velocity %.3g m/s, position %.3g m; "
              "refused time updates %d\n", d.att, d.vel, d.pos, a.predict_refused);
}

TEST(Nav13Float, EkfFloatTracksDouble) {
  expect_float_close<NavFilter13<float, TimeUpdate::Ekf>, NavFilter13<double, TimeUpdate::Ekf>>(0, 0.01, 1e-3, 0.05);
}

// The unscented time update factorizes the 12x12 error covariance at every step; in float32 a
// plain Cholesky of it (Eigen::LLT, before covariance_factor) was refused from about 32 s of this
// input on (1280 of 4500 time updates); see covariance_factor's comment.
TEST(Nav13Float, UkfFloatRunsEveryTimeUpdateAndTracksDouble) {
  expect_float_close<NavFilter13<float, TimeUpdate::Ukf>, NavFilter13<double, TimeUpdate::Ukf>>(0, 0.01, 1e-3, 0.05);
}

TEST(Unscented, CovarianceFactorReproducesDefiniteMatrices) {
  Randn rnd(3);
  const Mat<double, 6, 6> A = rnd.matrix<Mat<double, 6, 6>>().transpose();  // drawn row by row
  // scales over ten orders of magnitude, as in the navigation filters
  const Vec<double, 6> s = (Vec<double, 6>() << 1.0, 1e-2, 1e-3, 1e-4, 1e-5, 1e-5).finished();
  const Mat<double, 6, 6> P = s.asDiagonal() * (A * A.transpose()) * s.asDiagonal();
  Mat<double, 6, 6> L;
  ASSERT_TRUE((covariance_factor<double, 6>(P, L)));
  EXPECT_TRUE(L.isLowerTriangular());
  const Mat<double, 6, 6> scale = P.diagonal().cwiseSqrt() * P.diagonal().cwiseSqrt().transpose();
  EXPECT_LT((L * L.transpose() - P).cwiseQuotient(scale).cwiseAbs().maxCoeff(), 1e-13);
  // the same in float32: a float Cholesky of P itself (Eigen::LLT) works here too
  Mat<float, 6, 6> Lf;
  ASSERT_TRUE((covariance_factor<float, 6>(Mat<float, 6, 6>(P.cast<float>()), Lf)));
  EXPECT_LT((Lf.cast<double>() * Lf.cast<double>().transpose() - P).cwiseQuotient(scale).cwiseAbs().maxCoeff(), 1e-5);
}

// A semidefinite P rounded to float32 is indefinite by round-off: the factor exists and adds a
// little variance, only in the direction that lost it (L L^T - P >= 0 up to round-off).
TEST(Unscented, CovarianceFactorRepairsRoundOffOfASemidefiniteMatrix) {
  Randn rnd(5);
  Mat<double, 12, 11> B = rnd.matrix<Mat<double, 11, 12>>().transpose();  // drawn row by row
  B.row(7) = -B.row(3);  // x7 = -x3 (scaled): a tilt and the accelerometer bias that mimics it
  const Vec<double, 12> s = (Vec<double, 12>() << 0.005, 0.005, 0.004, 2e-3, 2e-3, 2e-3, 0.02, 0.02, 2e-4, 5e-6,
                             5e-6, 1e-5).finished();
  const Mat<double, 12, 12> P = s.asDiagonal() * (B * B.transpose()) * s.asDiagonal();
  const Mat<float, 12, 12> Pf = P.cast<float>();
  Mat<float, 12, 12> L;
  ASSERT_TRUE((covariance_factor<float, 12>(Pf, L)));
  const Mat<double, 12, 12> E = L.cast<double>() * L.cast<double>().transpose() - Pf.cast<double>();
  const Vec<double, 12> d = P.diagonal().cwiseSqrt();
  const Mat<double, 12, 12> Ec = d.cwiseInverse().asDiagonal() * E * d.cwiseInverse().asDiagonal();
  EXPECT_LT(Ec.cwiseAbs().maxCoeff(), 1e-4);  // about 64 float eps on the correlation scale
  Vec<double, 12> lam;
  detail::symmetric_eigen<double, 12>(Ec, lam);
  EXPECT_GT(lam.minCoeff(), -1e-6);  // added variance, not removed
}

TEST(Unscented, CovarianceFactorRefusesIndefiniteAndNonFinite) {
  Mat<double, 3, 3> P;
  P << 1.0, 0.9, 0.0, 0.9, 1.0, 0.0, 0.0, 0.0, 1.0;
  Mat<double, 3, 3> L = Mat<double, 3, 3>::Constant(7.0), L0 = L;
  ASSERT_TRUE((covariance_factor<double, 3>(P, L)));
  P(0, 1) = P(1, 0) = 1.1;  // correlation above one: indefinite
  L = L0;
  EXPECT_FALSE((covariance_factor<double, 3>(P, L)));
  EXPECT_EQ(L, L0);  // untouched
  Mat<float, 3, 3> Pf = P.cast<float>(), Lf = Mat<float, 3, 3>::Constant(7.f);
  EXPECT_FALSE((covariance_factor<float, 3>(Pf, Lf)));
  P(0, 1) = P(1, 0) = 0.0;
  P(2, 2) = -1e-30;
  EXPECT_FALSE((covariance_factor<double, 3>(P, L)));
  P(2, 2) = std::nan("");
  EXPECT_FALSE((covariance_factor<double, 3>(P, L)));
  EXPECT_EQ(L, L0);
  Mat<double, 3, 7> off = Mat<double, 3, 7>::Constant(5.0);
  EXPECT_FALSE((sigma_offsets<double, 3>(P, 1.0, off)));
  EXPECT_EQ(off, (Mat<double, 3, 7>::Constant(5.0)));
}
