// GpsInsFilter's error-state matrix F (detail::gpsins_F, paper 004 eq. 8-10) against finite
// differences of the continuous-time mechanization (eq. 1-2), in double.
//
// The error is "estimate minus truth" as in gps_ins.hpp: dp = NED metres of (lat, lon, h)_est -
// (lat, lon, h)_true, dv = v_est - v_true, psi with C_nb_est = exp([psi x]) C_nb_true, db =
// b_est - b_true (the estimated IMU is the measurement less b_est). For each error component i the
// estimate is the truth displaced by +-eps along i; both move by the exact derivatives
//     lat' = v_N / (R_M + h),  lon' = v_E / ((R_N + h) cos lat),  h' = -v_D
//     v'   = C_nb f_b + [0, 0, g(lat, h)] - (2 w_ie + w_en) x v
//     C'   = C_nb [w_b x] - [w_in x] C_nb,   b' = -b / tau (0 for a random walk)
// and the central difference of the error's rate is column i of F. F takes the radii of
// curvature as constant in latitude; so does this check (radii at the true latitude).
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/quatnav.hpp>

using namespace quatnav;

namespace {

struct X {
  double lat, lon, h;
  Vec3<double> v;
  Mat3<double> C;
  Vec3<double> ba, bg;
};

struct Case {
  GpsInsParams<double> p;
  X xt;
  Vec3<double> f_m, w_m;
  double lat_frozen;
};

X xdot(const X& x, const Case& c) {
  const earth::Radii<double> r = earth::radii<double>(c.lat_frozen);
  const double Rm = r.R_M + x.h, Rn = r.R_N + x.h;
  const Vec3<double> f_b = c.f_m - x.ba, w_b = c.w_m - x.bg;
  Vec3<double> w_ie = Vec3<double>::Zero(), w_en = Vec3<double>::Zero();
  if (c.p.earth_rotation) {
    w_ie = Vec3<double>(earth::kOmegaIe * std::cos(x.lat), 0.0, -earth::kOmegaIe * std::sin(x.lat));
    w_en = Vec3<double>(x.v[1] / Rn, -x.v[0] / Rm, -x.v[1] * std::tan(x.lat) / Rn);
  }
  X d;
  d.lat = x.v[0] / Rm;
  d.lon = x.v[1] / (Rn * std::cos(x.lat));
  d.h = -x.v[2];
  d.v = x.C * f_b + Vec3<double>(0.0, 0.0, earth::gravity<double>(x.lat, x.h)) - (2.0 * w_ie + w_en).cross(x.v);
  d.C = x.C * quat::skew(w_b) - quat::skew(Vec3<double>(w_ie + w_en)) * x.C;
  d.ba = c.p.acc_bias_tau > 0 ? Vec3<double>(-x.ba / c.p.acc_bias_tau) : Vec3<double>::Zero();
  d.bg = c.p.gyro_bias_tau > 0 ? Vec3<double>(-x.bg / c.p.gyro_bias_tau) : Vec3<double>::Zero();
  return d;
}

X perturb(const X& xt, int i, double eps, const Case& c) {
  X x = xt;
  const earth::Radii<double> r = earth::radii<double>(c.lat_frozen);
  if (i == 0) x.lat += eps / (r.R_M + xt.h);
  else if (i == 1) x.lon += eps / ((r.R_N + xt.h) * std::cos(xt.lat));
  else if (i == 2) x.h -= eps;
  else if (i < 6) x.v[i - 3] += eps;
  else if (i < 9) x.C = quat::to_rotmat(quat::from_rotvec(Vec3<double>(eps * Vec3<double>::Unit(i - 6)))) * xt.C;
  else if (i < 12) x.ba[i - 9] += eps;
  else x.bg[i - 12] += eps;
  return x;
}

Vec<double, 15> error_rate(const X& xe, const X& xt, const Case& c) {
  const X de = xdot(xe, c), dt = xdot(xt, c);
  const earth::Radii<double> r = earth::radii<double>(c.lat_frozen);
  const double L = xt.lat, h = xt.h;
  const double dlat = xe.lat - xt.lat, dlon = xe.lon - xt.lon;
  Vec<double, 15> out;
  out[0] = (de.lat - dt.lat) * (r.R_M + h) + dlat * dt.h;
  out[1] = (de.lon - dt.lon) * (r.R_N + h) * std::cos(L) + dlon * (dt.h * std::cos(L) - (r.R_N + h) * std::sin(L) * dt.lat);
  out[2] = -(de.h - dt.h);
  out.segment<3>(3) = de.v - dt.v;
  // [psi x] = C_e C_t^T - I to first order; its rate is the skew part of the derivative.
  const Mat3<double> Ed = de.C * xt.C.transpose() + xe.C * dt.C.transpose();
  const Mat3<double> Sk = 0.5 * (Ed - Ed.transpose());
  out.segment<3>(6) = Vec3<double>(Sk(2, 1), Sk(0, 2), Sk(1, 0));
  out.segment<3>(9) = de.ba - dt.ba;
  out.segment<3>(12) = de.bg - dt.bg;
  return out;
}

// Steps per error component (m, m/s, rad, m/s^2, rad/s) and the round-off of the differenced rates.
const double kEps[5] = {100.0, 1e-2, 1e-5, 1e-4, 1e-6};

Mat<double, 15, 15> fd_F(const Case& c) {
  Mat<double, 15, 15> F;
  for (int i = 0; i < 15; ++i) {
    const double e = kEps[i / 3];
    F.col(i) = (error_rate(perturb(c.xt, i, e, c), c.xt, c) - error_rate(perturb(c.xt, i, -e, c), c.xt, c)) / (2 * e);
  }
  return F;
}

Case make_case(bool earth_rotation, double tau) {
  Case c;
  c.p.earth_rotation = earth_rotation;
  c.p.acc_bias_tau = tau;
  c.p.gyro_bias_tau = 2 * tau;
  // A fast, climbing vehicle at 50 deg N: the small transport-rate and Coriolis terms are far
  // above the differencing noise.
  const Quat<double> q = quat::from_euler(0.3, -0.4, 2.0);
  c.xt = X{50.0 * M_PI / 180.0, 8.0 * M_PI / 180.0, 800.0, Vec3<double>(150.0, -90.0, 12.0),
           quat::to_rotmat(q), Vec3<double>(0.05, -0.03, 0.08), Vec3<double>(2e-3, -1e-3, 3e-3)};
  c.f_m = Vec3<double>(1.5, -0.8, -9.6) + c.xt.ba;
  c.w_m = Vec3<double>(0.1, -0.2, 0.3) + c.xt.bg;
  c.lat_frozen = c.xt.lat;
  return c;
}

Mat<double, 15, 15> filter_F(const Case& c, Mat<double, 16, 16>* full = nullptr) {
  StrapdownState<double> nav;
  nav.q_nb = quat::from_euler(0.3, -0.4, 2.0);
  nav.v_n = c.xt.v;
  nav.lat = c.xt.lat;
  nav.lon = c.xt.lon;
  nav.h = c.xt.h;
  const Mat<double, 16, 16> F = detail::gpsins_F<double>(nav, Vec3<double>(c.f_m - c.xt.ba), c.p);
  if (full) *full = F;
  return F.topLeftCorner<15, 15>();  // the altimeter offset (a random walk) has no dynamics
}

// Largest violation of |a - b| <= 1e-5 max|b| + 2e-14/eps over each 3x3 block (each block on its
// own scale: they span 1e-12, the Earth-rate position terms, to 10); <= 0 when all pass.
double worst_block_violation(const Mat<double, 15, 15>& F, const Mat<double, 15, 15>& Ffd) {
  double worst = -1.0;
  for (int rb = 0; rb < 5; ++rb)
    for (int cb = 0; cb < 5; ++cb) {
      const Mat3<double> a = F.block<3, 3>(3 * rb, 3 * cb), b = Ffd.block<3, 3>(3 * rb, 3 * cb);
      const double tol = 1e-5 * b.cwiseAbs().maxCoeff() + 2e-14 / kEps[cb];
      worst = std::max(worst, ((a - b).cwiseAbs().array() - tol).maxCoeff());
    }
  return worst;
}

}  // namespace

TEST(GpsInsJacobian, MatchesFiniteDifferencesOfTheMechanization) {
  const struct { bool earth_rotation; double tau; } cases[] = {{true, 0.0}, {true, 300.0}, {false, 0.0}};
  for (const auto& k : cases) {
    const Case c = make_case(k.earth_rotation, k.tau);
    Mat<double, 16, 16> full;
    const Mat<double, 15, 15> F = filter_F(c, &full), Ffd = fd_F(c);
    EXPECT_EQ(full.row(15).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(full.col(15).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_LE(worst_block_violation(F, Ffd), 0.0) << "earth_rotation " << k.earth_rotation << " tau " << k.tau
                                                  << "\nF\n" << F << "\nfinite differences\n" << Ffd;
    if (k.earth_rotation) {  // the tiny terms are really exercised
      const double att_pos = Ffd.block<3, 3>(6, 0).cwiseAbs().maxCoeff();
      const double vel_pos = Ffd.block<2, 3>(3, 0).cwiseAbs().maxCoeff();
      EXPECT_GT(att_pos, 1e-12);
      EXPECT_GT(vel_pos, 1e-10);
    }
    if (k.tau > 0) {
      EXPECT_NE(F(9, 9), 0.0);
    }
  }
}

TEST(GpsInsJacobian, TheCheckDetectsAnError) {
  const Case c = make_case(true, 0.0);
  const Mat<double, 15, 15> F = filter_F(c), Ffd = fd_F(c);
  Mat<double, 15, 15> bad = F;  // 2 w_ie -> w_ie (north) in the Coriolis term
  bad.block<3, 3>(3, 3) += quat::skew(Vec3<double>(earth::kOmegaIe * std::cos(c.xt.lat), 0, 0));
  EXPECT_GT(worst_block_violation(bad, Ffd), 0.0);
  bad = F;
  bad(6, 2) *= 1.01;  // 1 % off in an Earth-rate position term (1e-12 1/s/m)
  EXPECT_GT(worst_block_violation(bad, Ffd), 0.0);
}
