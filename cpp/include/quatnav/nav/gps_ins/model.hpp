// quatnav: GpsInsFilter's error-state model (nav/gps_ins.hpp): the continuous error dynamics F,
// the process noise density, the injection of a correction into the nominal state, and the check
// of a candidate state. The equations and the paper's slips are in the comment of gps_ins.hpp.
#pragma once

#include <cmath>

#include "../../core/earth.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"
#include "../strapdown.hpp"
#include "params.hpp"

namespace quatnav {

/// The error state: [dp (N, E, D, m), dv (m/s), psi (rad), db_a (m/s^2), db_g (rad/s),
/// d_baro_offset (m)]; the index of the first component of each block.
namespace gpsins {
constexpr int kN = 16;
constexpr int kPos = 0, kVel = 3, kAtt = 6, kBa = 9, kBg = 12, kBo = 15;
}  // namespace gpsins

namespace detail {

template <class S> using Mat16 = Mat<S, gpsins::kN, gpsins::kN>;

/// Largest |latitude| (rad) the filter navigates at: the Earth model divides by cos(lat) (about
/// 10 m from the pole). A state, fix or correction beyond it is refused.
constexpr double kGpsInsMaxAbsLat = 1.5707;

/// The nominal navigation state and the biases as the filter keeps them: finite, |q| = 1 to
/// rounding (a quaternion whose norm overflowed normalizes to zero, which this refuses) and the
/// latitude off the poles. Checked on every candidate state before it is committed.
template <class S> bool gpsins_nav_ok(const GpsInsState<S>& s) {
  return s.nav.q_nb.allFinite() && s.nav.v_n.allFinite() && std::isfinite(s.nav.lat) && std::isfinite(s.nav.lon) &&
         std::isfinite(s.nav.h) && std::abs(s.nav.lat) < kGpsInsMaxAbsLat && s.acc_bias.allFinite() &&
         s.gyro_bias.allFinite() && std::isfinite(s.baro_offset) && std::abs(s.nav.q_nb.norm() - S(1)) <= S(1e-3);
}

/// Continuous-time error dynamics matrix F (16 x 16) at a nominal state, for the bias-corrected
/// specific force f_b (m/s^2). Block layout and equations: see the file comment (the altimeter
/// offset is a random walk: its row is zero).
template <class S>
Mat16<S> gpsins_F(const StrapdownState<S>& nav, const Vec3<S>& f_b, const GpsInsParams<S>& p) {
  using std::cos;
  using std::sin;
  using std::tan;
  Mat16<S> F = Mat16<S>::Zero();
  const double L = nav.lat, h = nav.h;
  const earth::Radii<double> r = earth::radii<double>(L);
  const double Rm = r.R_M + h, Rn = r.R_N + h;
  const Vec3<double> v = nav.v_n.template cast<double>();
  const double tL = tan(L), sL = sin(L), cL = cos(L);
  const Mat3<S> C = quat::to_rotmat(nav.q_nb);
  const Vec3<S> f_n = C * f_b;

  // eq. (9): position error (m) from the exact linearization of the geodetic rates.
  Mat3<double> Fpp = Mat3<double>::Zero();
  Fpp(0, 0) = -v[2] / Rm;
  Fpp(0, 2) = v[0] / Rm;
  Fpp(1, 0) = v[1] * tL / Rm;
  Fpp(1, 1) = -v[2] / Rn - v[0] * tL / Rm;
  Fpp(1, 2) = v[1] / Rn;
  F.template block<3, 3>(0, 0) = Fpp.template cast<S>();
  F.template block<3, 3>(0, 3).setIdentity();

  // Gravity error: dg_D = dg/dh dh + dg/dL dL with dh = -dp_D, dL = dp_N / Rm.
  const double s2 = sL * sL;
  const double dg_dh = earth::kG2 + earth::kG3 * s2;
  const double dg_dL = (earth::kG1 + earth::kG3 * h) * 2.0 * sL * cL;
  Mat3<double> Fvp = Mat3<double>::Zero();
  Fvp(2, 2) = -dg_dh;
  Fvp(2, 0) = dg_dL / Rm;

  Mat3<double> Fvv = Mat3<double>::Zero();
  Mat3<double> Fpsi_p = Mat3<double>::Zero();
  Mat3<double> Fpsi_v = Mat3<double>::Zero();
  Vec3<double> w_in = Vec3<double>::Zero();
  if (p.earth_rotation) {
    const Vec3<double> w_ie = earth::earth_rate_n<double>(L);
    const Vec3<double> w_en = earth::transport_rate_n<double>(L, h, v);
    w_in = w_ie + w_en;
    // d w_en / d v
    Mat3<double> Wv = Mat3<double>::Zero();
    Wv(0, 1) = 1.0 / Rn;
    Wv(1, 0) = -1.0 / Rm;
    Wv(2, 1) = -tL / Rn;
    // d w_ie / d p and d w_en / d p (columns N and D; radii taken constant in latitude)
    Mat3<double> Wie_p = Mat3<double>::Zero();
    Wie_p(0, 0) = -earth::kOmegaIe * sL / Rm;
    Wie_p(2, 0) = -earth::kOmegaIe * cL / Rm;
    Mat3<double> Wen_p = Mat3<double>::Zero();
    Wen_p(2, 0) = -v[1] / (Rn * cL * cL * Rm);
    Wen_p(0, 2) = v[1] / (Rn * Rn);
    Wen_p(1, 2) = -v[0] / (Rm * Rm);
    Wen_p(2, 2) = -v[1] * tL / (Rn * Rn);
    const Mat3<double> Vx = quat::skew<double>(v);
    // eq. (8): Coriolis and transport terms.
    Fvv = -quat::skew<double>(2.0 * w_ie + w_en) + Vx * Wv;
    Fvp += Vx * (2.0 * Wie_p + Wen_p);
    // eq. (10) (corrected): -[w_in x] psi - dw_in.
    Fpsi_v = -Wv;
    Fpsi_p = -(Wie_p + Wen_p);
  }
  F.template block<3, 3>(3, 0) = Fvp.template cast<S>();
  F.template block<3, 3>(3, 3) = Fvv.template cast<S>();
  F.template block<3, 3>(3, 6) = -quat::skew<S>(f_n);
  F.template block<3, 3>(3, 9) = -C;
  F.template block<3, 3>(6, 0) = Fpsi_p.template cast<S>();
  F.template block<3, 3>(6, 3) = Fpsi_v.template cast<S>();
  F.template block<3, 3>(6, 6) = -quat::skew<S>(w_in.template cast<S>());
  F.template block<3, 3>(6, 12) = -C;
  if (p.acc_bias_tau > S(0)) F.template block<3, 3>(9, 9) = -Mat3<S>::Identity() / p.acc_bias_tau;
  if (p.gyro_bias_tau > S(0)) F.template block<3, 3>(12, 12) = -Mat3<S>::Identity() / p.gyro_bias_tau;
  return F;
}

/// The discrete error-state transition over one IMU interval dt, with F at the nominal state
/// before the step: Phi = I + F dt + (F dt)^2 / 2 (the time update's and the smoother's).
template <class S>
Mat16<S> gpsins_Phi(const StrapdownState<S>& nav, const Vec3<S>& f_b, S dt, const GpsInsParams<S>& p) {
  const Mat16<S> Fdt = gpsins_F<S>(nav, f_b, p) * dt;
  return Mat16<S>::Identity() + Fdt + S(0.5) * fixed_mul(Fdt, Fdt);
}

/// Continuous process noise spectral density Qc (diagonal, 16 x 16); the IMU terms scaled by the
/// adaptation's q_scale.
template <class S> Vec<S, gpsins::kN> gpsins_Qc_diag(const GpsInsParams<S>& p, S q_scale) {
  Vec<S, gpsins::kN> q = Vec<S, gpsins::kN>::Zero();
  q.template segment<3>(3).setConstant(q_scale * p.acc_noise * p.acc_noise);
  q.template segment<3>(6).setConstant(q_scale * p.gyro_noise * p.gyro_noise);
  q.template segment<3>(9).setConstant(q_scale * p.acc_bias_noise * p.acc_bias_noise);
  q.template segment<3>(12).setConstant(q_scale * p.gyro_bias_noise * p.gyro_bias_noise);
  q[gpsins::kBo] = p.baro_offset_noise * p.baro_offset_noise;
  return q;
}

/// Inject an error estimate into a copy of the state (the feedback of paper Fig. 2).
template <class S> void gpsins_inject(GpsInsState<S>& s, const Vec<S, gpsins::kN>& dx) {
  const Vec3<double> dp = dx.template segment<3>(0).template cast<double>();
  earth::geodetic_add(s.nav.lat, s.nav.lon, s.nav.h, Vec3<double>(-dp));
  s.nav.v_n -= dx.template segment<3>(3);
  Quat<S> q = quat::mul(quat::from_rotvec(Vec3<S>(-dx.template segment<3>(6))), s.nav.q_nb);
  s.nav.q_nb = q / q.norm();
  s.acc_bias -= dx.template segment<3>(9);
  s.gyro_bias -= dx.template segment<3>(12);
  s.baro_offset -= double(dx[gpsins::kBo]);
}

}  // namespace detail

}  // namespace quatnav
