// quatnav: GpsInsFilter's aids as small pieces of one measurement shape (nav/gps_ins.hpp).
//
// In the spirit of pyins' Measurement.compute_matrices(time, state) -> (z, H, R): each piece
// holds one aiding sample and, at a state, gives its innovation y (INS minus aid, eq. 11), the
// measurement matrix H over the error state and the noise covariance R (AidMeasurement). The
// filter sends every piece through one gated correction path (GpsInsFilter::apply: gate, outlier
// isolation, covariance inflation and process-noise adaptation for the GNSS aids, Kalman
// correction, injection, counters). A new aid is one more piece, not a new path through the
// filter. Each piece also states where its H can be nonzero (columns C0 .. C0 + NC - 1 of the
// error state), which the correction exploits; fixed sizes, no heap, no virtual calls.
//
// R holds what the model leaves out, so that the gate judges with an honest covariance: for the
// GNSS aids a floor on the fix's one-sigma, the uncertainty of its time on the IMU clock (times
// the antenna's velocity for a position, its acceleration for a velocity) and the lever arm's.
#pragma once

#include <algorithm>
#include <cmath>

#include "../../core/earth.hpp"
#include "../../core/kalman.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"
#include "model.hpp"
#include "params.hpp"

namespace quatnav {

/// One aid sample linearized at a state: y = INS minus aid (M), H (M x N: 16, or 22 with the
/// scale-factor states, whose columns no aid sees), R (M x M).
template <class S, int M, int N = gpsins::kN> struct AidMeasurement {
  Vec<S, M> y = Vec<S, M>::Zero();
  Mat<S, M, N> H = Mat<S, M, N>::Zero();
  Mat<S, M, M> R = Mat<S, M, M>::Zero();
};

/// The outcome of one aid sample: the update's result (status, innovation, its covariance, NIS:
/// the innovation and NIS before any inflation) and what the filter decided.
template <class S, int M> struct GpsInsUpdate : UpdateResult<S, M> {
  GpsInsDecision decision = GpsInsDecision::None;
  S inflation = S(1);  ///< factor applied to the navigation block of P (Inflated), else 1
};

namespace detail {
/// Yaw-error row of the compass: d yaw / d psi = [tan(theta) cos(yaw), tan(theta) sin(yaw), 1].
template <class S> Vec3<S> compass_row(const Quat<S>& q_nb) {
  const Vec3<S> e = quat::to_euler(q_nb);
  const S tp = std::tan(e[1]);
  return Vec3<S>(tp * std::cos(e[2]), tp * std::sin(e[2]), S(1));
}

/// The antenna's NED velocity v + C_nb (w_ib_b x l_b) (Earth rate in the lever-arm term neglected).
template <class S, bool SF> Vec3<S> antenna_velocity(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, const Mat3<S>& C) {
  return s.nav.v_n + C * s.omega_b.cross(p.lever_arm_b);
}

/// Kinematic acceleration in NED from the last specific force, C_nb f_b + g_n (Coriolis left out).
template <class S, bool SF> Vec3<S> nav_acceleration(const GpsInsState<S, SF>& s, const Mat3<S>& C) {
  return C * s.f_b + Vec3<S>(S(0), S(0), S(earth::gravity<double>(s.nav.lat, s.nav.h)));
}

/// The floor of a GNSS position's one-sigma (m, NED) for the receiver's solution kind: the
/// kind's floor north and east, gps_vertical_floor_ratio times it down.
template <class S> Vec3<S> gnss_sigma_floor(const GpsInsParams<S>& p, GnssSolution kind) {
  S f = p.gps_pos_sigma_min;
  if (kind == GnssSolution::RtkFloat) f = p.gps_float_sigma_min;
  if (kind == GnssSolution::Dgnss) f = p.gps_dgnss_sigma_min;
  if (kind == GnssSolution::Single) f = p.gps_single_sigma_min;
  return Vec3<S>(f, f, p.gps_vertical_floor_ratio * f);
}

/// The one-sigma scale sqrt((1 + rho) / (1 - rho)), rho = exp(-dt / gps_error_tau), of a GNSS
/// position of solution kind `kind` whose error is time-correlated (RTK float, DGNSS, single), dt
/// (s, at least 1 ms) after the last accepted position fix; 1 for RTK fixed, unknown kind, or
/// gps_error_tau = 0.
template <class S> S gnss_correlation_scale(const GpsInsParams<S>& p, GnssSolution kind, double dt) {
  const bool wanders = kind == GnssSolution::RtkFloat || kind == GnssSolution::Dgnss || kind == GnssSolution::Single;
  if (!wanders || !(p.gps_error_tau > S(0))) return S(1);
  const double rho = std::exp(-std::max(dt, 1e-3) / double(p.gps_error_tau));
  return S(std::sqrt((1.0 + rho) / (1.0 - rho)));
}

/// Huber's weights of an innovation y with covariance S: each component z_i = y_i / sqrt(S_ii)
/// beyond k (> 0) gets the weight k / |z_i|, which the correction applies by raising R to
/// D R D with D = diag(sqrt(|z_i| / k)) (1 elsewhere). False when every component is within k.
template <class S, int M> bool huber_scales(const Vec<S, M>& y, const Mat<S, M, M>& Sm, S k, Vec<S, M>& d) {
  bool any = false;
  for (int i = 0; i < M; ++i) {
    const S z = std::abs(y[i]) / std::sqrt(Sm(i, i));
    d[i] = S(1);
    if (z > k) {
      d[i] = std::sqrt(z / k);
      any = true;
    }
  }
  return any;
}

/// The robust weighting of a correction (robust_k > 0): when a component of the innovation lies
/// beyond robust_k sigmas (huber_scales), the correction of P0 is made again into P and dx with R
/// raised to D R D. A correction the gate passed is weighted whatever its weighted NIS; one the
/// gate refused (res.status Rejected) is judged again by the gate on the weighted innovation, so
/// that only a gross outlier, one whose NIS exceeds the gate even down-weighted, stays refused
/// (IGG-III's rejection region; where R dominates the innovation's variance, a single component
/// beyond gate / robust_k sigmas: 7 for the default 3 and the 3-dof gate). res keeps the
/// innovation, its covariance and NIS as the fix came but takes the status of the new correction;
/// P and dx are left as they were when it is not Ok. True when the weighted correction was made.
template <class Aid, class S, int N>
bool gpsins_huber_correct(const Mat<S, N, N>& P0, const AidMeasurement<S, Aid::M, N>& m, S robust_k, S gate,
                          Mat<S, N, N>& P, Vec<S, N>& dx, UpdateResult<S, Aid::M>& res) {
  constexpr int M = Aid::M;
  Vec<S, M> d;
  const bool judged = res.status == Status::Ok || res.status == Status::Rejected;
  if (!judged || !(robust_k > S(0)) || !huber_scales<S, M>(m.y, res.innovation_cov, robust_k, d)) return false;
  const Mat<S, M, M> Rw = d.asDiagonal() * m.R * d.asDiagonal();
  UpdateResult<S, M> rw;
  Mat<S, N, N> Pw = P0;
  Vec<S, N> dxw = Vec<S, N>::Zero();
  kalman_correct<S, N, M, Aid::C0, Aid::NC>(Pw, m.H, Rw, m.y, dxw, rw, res.status == Status::Rejected ? gate : S(0));
  res.status = rw.status;
  if (rw.status != Status::Ok) return false;
  P = Pw;
  dx = dxw;
  return true;
}

/// After a reset of the 3 states from K0 to a fix: their covariance block is the fix's R and their
/// cross terms with every other state are zero.
template <int K0, class S, bool SF> void reset_block(GpsInsState<S, SF>& s, const Mat3<S>& R) {
  s.P.template middleRows<3>(K0).setZero();
  s.P.template middleCols<3>(K0).setZero();
  s.P.template block<3, 3>(K0, K0) = R;
}

/// The altimeter offset state from one altimeter sample h_baro and the INS height: its error is the
/// INS height error (dp_D) plus the sample's noise (baro_sigma, m). False, s untouched, when the
/// offset or its variance overflows (a height or an INS height near the double or float maximum).
template <class S, bool SF> bool gpsins_init_baro_offset(GpsInsState<S, SF>& s, double h_baro, S baro_sigma) {
  constexpr int D = gpsins::kPos + 2, B = gpsins::kBo;
  const double offset = h_baro - s.nav.h;
  const S var = s.P(D, D) + baro_sigma * baro_sigma;
  if (!std::isfinite(offset) || !std::isfinite(var)) return false;
  s.baro_offset = offset;
  s.P.row(B) = s.P.row(D);
  s.P.col(B) = s.P.col(D);
  s.P(B, B) = var;
  s.baro_offset_valid = true;
  return true;
}
}  // namespace detail

/// The pieces. Each has: kind (its counters), M (rows), C0, NC (the columns of the error state
/// where H may be nonzero), kAdaptive (a GNSS aid: inflation, reset and the process-noise
/// adaptation apply), gate(params) and measure(state, params, out); an adaptive piece also has
/// reset(state, params, R), which puts the state on the fix.
namespace gpsins_aid {

/// GPS antenna position (lat, lon rad; h m) with its NED one-sigma (m) and the floor of that
/// one-sigma (detail::gnss_sigma_floor of the fix's solution kind), valid `age` seconds before
/// the filter's time: the INS antenna position p + C_nb l_b, taken back by age with the antenna
/// velocity v_ant = v + C_nb (w x l_b), minus the fix, in NED metres about the fix;
/// H = [I, -age I, -[(C_nb l_b) x] + age [(C_nb (w x l_b)) x], 0, -age C_nb [l_b x], 0].
template <class S> struct GpsPosition {
  static constexpr GpsInsAid kind = GpsInsAid::GpsPos;
  static constexpr int M = 3, C0 = 0, NC = 15;
  static constexpr bool kAdaptive = true;
  double lat, lon, h;
  Vec3<S> sigma;
  S age;
  Vec3<S> floor = Vec3<S>::Zero();
  static S gate(const GpsInsParams<S>& p) { return p.gate_gps_pos; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    const Mat3<S> C = quat::to_rotmat(s.nav.q_nb);
    const Vec3<S> l_n = C * p.lever_arm_b;
    const Vec3<S> v_ant = detail::antenna_velocity(s, p, C);
    double la = s.nav.lat, lo = s.nav.lon, hh = s.nav.h;
    earth::geodetic_add(la, lo, hh, Vec3<double>((l_n - v_ant * age).template cast<double>()));
    m.y = earth::geodetic_diff<S>(la, lo, hh, lat, lon, h);
    m.H.template block<3, 3>(0, gpsins::kPos).setIdentity();
    m.H.template block<3, 3>(0, gpsins::kVel) = -age * Mat3<S>::Identity();
    m.H.template block<3, 3>(0, gpsins::kAtt) = -quat::skew<S>(l_n) + age * quat::skew<S>(Vec3<S>(v_ant - s.nav.v_n));
    m.H.template block<3, 3>(0, gpsins::kBg) = -age * C * quat::skew<S>(p.lever_arm_b);
    m.R = sigma.cwiseMax(floor).cwiseAbs2().asDiagonal();
    m.R += (p.gps_time_sigma * p.gps_time_sigma) * v_ant * v_ant.transpose();
    m.R.diagonal().array() += p.lever_arm_sigma * p.lever_arm_sigma;  // C diag(s^2) C^T = s^2 I
  }
  /// The IMU position from the fix (less the lever arm), its covariance block R, cross terms 0.
  template <bool SF> bool reset(GpsInsState<S, SF>& s, const GpsInsParams<S>& p, const Mat<S, M, M>& R) const {
    const Vec3<S> l_n = quat::to_rotmat(s.nav.q_nb) * p.lever_arm_b;
    double la = lat, lo = lon, hh = h;
    earth::geodetic_add(la, lo, hh, Vec3<double>(-l_n.template cast<double>()));
    s.nav.lat = la;
    s.nav.lon = lo;
    s.nav.h = hh;
    detail::reset_block<gpsins::kPos>(s, R);
    return true;
  }
};

/// GPS antenna velocity (NED, m/s) with its one-sigma per axis, valid `age` seconds before the
/// filter's time: v + C_nb (w_ib_b x l_b), taken back by age with the acceleration
/// a_n = C_nb f_b + g_n, minus the fix;
/// H = [0, I, -[(C_nb (w x l_b)) x] + age [(C_nb f_b) x], age C_nb, C_nb [l_b x], 0].
template <class S> struct GpsVelocity {
  static constexpr GpsInsAid kind = GpsInsAid::GpsVel;
  static constexpr int M = 3, C0 = 3, NC = 12;
  static constexpr bool kAdaptive = true;
  Vec3<S> v_n;
  Vec3<S> sigma;
  S age;
  static S gate(const GpsInsParams<S>& p) { return p.gate_gps_vel; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    const Mat3<S> C = quat::to_rotmat(s.nav.q_nb);
    const Mat3<S> CW = C * quat::skew<S>(s.omega_b);
    const Vec3<S> wl = C * s.omega_b.cross(p.lever_arm_b);
    const Vec3<S> a_n = detail::nav_acceleration(s, C);
    m.y = s.nav.v_n + wl - a_n * age - v_n;
    m.H.template block<3, 3>(0, gpsins::kVel).setIdentity();
    m.H.template block<3, 3>(0, gpsins::kAtt) = -quat::skew<S>(wl) + age * quat::skew<S>(Vec3<S>(C * s.f_b));
    m.H.template block<3, 3>(0, gpsins::kBa) = age * C;
    m.H.template block<3, 3>(0, gpsins::kBg) = C * quat::skew<S>(p.lever_arm_b);
    m.R = sigma.cwiseMax(p.gps_vel_sigma_min).cwiseAbs2().asDiagonal();
    m.R += (p.gps_time_sigma * p.gps_time_sigma) * a_n * a_n.transpose();
    m.R += (p.lever_arm_sigma * p.lever_arm_sigma) * CW * CW.transpose();
  }
  /// The IMU velocity from the fix (less the lever-arm term), its covariance block R, cross terms 0.
  template <bool SF> bool reset(GpsInsState<S, SF>& s, const GpsInsParams<S>& p, const Mat<S, M, M>& R) const {
    s.nav.v_n = v_n - quat::to_rotmat(s.nav.q_nb) * s.omega_b.cross(p.lever_arm_b);
    detail::reset_block<gpsins::kVel>(s, R);
    return true;
  }
};

/// Altimeter height h (m): the altimeter reads the ellipsoidal height plus its offset (the 16th
/// state), so y = h_INS + offset - h; H = -1 on dp_D (the down error), +1 on the offset.
template <class S> struct BaroHeight {
  static constexpr GpsInsAid kind = GpsInsAid::Baro;
  static constexpr int M = 1, C0 = 2, NC = 14;
  static constexpr bool kAdaptive = false;
  double h;
  static S gate(const GpsInsParams<S>& p) { return p.gate_baro; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    m.y[0] = S(s.nav.h + s.baro_offset - h);
    m.H(0, gpsins::kPos + 2) = S(-1);
    m.H(0, gpsins::kBo) = S(1);
    m.R(0, 0) = p.baro_sigma * p.baro_sigma;
  }
};

/// Altimeter vertical velocity over a baseline of T seconds (paper 004): v_D,INS - v_D,baro with
/// v_D,baro = -(h - h_ref) / T; R = 2 sigma_h^2 / T^2 + baro_vd_sigma^2 (successive derivatives
/// share an end point, so their noise is correlated by -1/2; the extra term covers that and the
/// lag of a mean rate).
template <class S> struct BaroVerticalVelocity {
  static constexpr GpsInsAid kind = GpsInsAid::BaroVd;
  static constexpr int M = 1, C0 = 5, NC = 1;
  static constexpr bool kAdaptive = false;
  double h, h_ref, T;
  static S gate(const GpsInsParams<S>& p) { return p.gate_baro; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    const S vd_baro = S(-(h - h_ref) / T);
    m.y[0] = s.nav.v_n[2] - vd_baro;
    m.H(0, gpsins::kVel + 2) = S(1);
    m.R(0, 0) = S(2) * p.baro_sigma * p.baro_sigma / S(T * T) + p.baro_vd_sigma * p.baro_vd_sigma;
  }
};

/// Compass heading (rad, true: the declination already added): wrap(yaw_INS - yaw),
/// H = [0, 0, tan(theta) cos(yaw), tan(theta) sin(yaw), 1, 0...].
template <class S> struct CompassHeading {
  static constexpr GpsInsAid kind = GpsInsAid::Compass;
  static constexpr int M = 1, C0 = 6, NC = 3;
  static constexpr bool kAdaptive = false;
  S yaw;
  static S gate(const GpsInsParams<S>& p) { return p.gate_compass; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    const Vec3<S> e = quat::to_euler(s.nav.q_nb);
    m.y[0] = quat::wrap_pi(e[2] - yaw);
    m.H.template block<1, 3>(0, gpsins::kAtt) = detail::compass_row(s.nav.q_nb).transpose();
    m.R(0, 0) = p.compass_sigma * p.compass_sigma;
  }
};

/// Raw magnetometer m_b (body axes, any unit): the angle of the field in the navigation frame as
/// the filter sees it, m_n = C_nb m_b, minus the declination: y = wrap(atan2(m_E, m_N) - decl),
/// the heading error tilt-compensated with the filter's own attitude. From m_n <- m_n + psi x m_n:
/// H = [-tan(dip) cos(a), -tan(dip) sin(a), 1] on psi (a = atan2(m_E, m_N), tan(dip) = m_D / m_h).
/// With mag_heading_only (the default) the tilt terms leave H and enter R as h P_tilt h^T: the
/// magnetometer then corrects the heading only. With the full row, a field the filter does not
/// know exactly (a hard iron not calibrated out, a wrong declination: the usual raw log) pulls
/// the tilt by its heading error over tan(dip) whenever another aid holds the heading (measured
/// on the simulated car with a 10 uT hard iron and GNSS velocity: 12 deg of inclination error).
template <class S> struct MagHeading {
  static constexpr GpsInsAid kind = GpsInsAid::Mag;
  static constexpr int M = 1, C0 = 6, NC = 3;
  static constexpr bool kAdaptive = false;
  Vec3<S> m_b;
  static S gate(const GpsInsParams<S>& p) { return p.gate_mag; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    const Vec3<S> m_n = quat::rotate(s.nav.q_nb, m_b);
    const S mh2 = m_n[0] * m_n[0] + m_n[1] * m_n[1];
    m.y[0] = quat::wrap_pi(std::atan2(m_n[1], m_n[0]) - p.declination);
    const Vec3<S> h(-m_n[0] * m_n[2] / mh2, -m_n[1] * m_n[2] / mh2, S(1));
    m.R(0, 0) = p.mag_heading_sigma * p.mag_heading_sigma;
    if (p.mag_heading_only) {
      const Vec2<S> ht = h.template head<2>();
      m.R(0, 0) += ht.dot(s.P.template block<2, 2>(gpsins::kAtt, gpsins::kAtt) * ht);
      m.H(0, gpsins::kAtt + 2) = S(1);
    } else {
      m.H.template block<1, 3>(0, gpsins::kAtt) = h.transpose();
    }
  }
};

namespace detail_body {
/// The body-frame velocity at the IMU, C_nb^T v_n, and its rows of H: C_nb^T on dv and
/// C_nb^T [v_n x] on psi (from C_nb <- (I + [psi x]) C_nb).
template <class S, int M, bool SF, int N>
void body_velocity_rows(const GpsInsState<S, SF>& s, const int (&rows)[M], Vec<S, M>& v, Mat<S, M, N>& H) {
  const Mat3<S> Ct = quat::to_rotmat(s.nav.q_nb).transpose();
  const Vec3<S> v_b = Ct * s.nav.v_n;
  const Mat3<S> Hpsi = Ct * quat::skew<S>(s.nav.v_n);
  for (int i = 0; i < M; ++i) {
    v[i] = v_b[rows[i]];
    H.template block<1, 3>(i, gpsins::kVel) = Ct.row(rows[i]);
    H.template block<1, 3>(i, gpsins::kAtt) = Hpsi.row(rows[i]);
  }
}
}  // namespace detail_body

/// Zero velocity at rest (ZUPT): y = v_n, H = I on dv.
template <class S> struct ZeroVelocity {
  static constexpr GpsInsAid kind = GpsInsAid::Zupt;
  static constexpr int M = 3, C0 = 3, NC = 3;
  static constexpr bool kAdaptive = false;
  static S gate(const GpsInsParams<S>& p) { return p.gate_zupt; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    m.y = s.nav.v_n;
    m.H.template block<3, 3>(0, gpsins::kVel).setIdentity();
    m.R.diagonal().setConstant(p.zupt_sigma * p.zupt_sigma);
  }
};

/// Zero angular rate at rest (ZARU): the bias-corrected rate of the last interval (dt) is the
/// Earth rate, y = (w_m - b_g) - C_nb^T w_ie; H = -I on db_g; R = gyro_noise^2 / dt + zaru_sigma^2.
template <class S> struct ZeroRate {
  static constexpr GpsInsAid kind = GpsInsAid::Zaru;
  static constexpr int M = 3, C0 = 6, NC = 9;
  static constexpr bool kAdaptive = false;
  static S gate(const GpsInsParams<S>& p) { return p.gate_zupt; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    const Vec3<S> w_ie = p.earth_rotation ? Vec3<S>(earth::earth_rate_n<double>(s.nav.lat).template cast<S>())
                                          : Vec3<S>::Zero();
    const Mat3<S> Ct = quat::to_rotmat(s.nav.q_nb).transpose();
    m.y = s.omega_b - Ct * w_ie;
    // C_nb <- (I + [psi x]) C_nb turns the Earth rate seen in the body: -C^T [w_ie x] on psi
    m.H.template block<3, 3>(0, gpsins::kAtt) = -Ct * quat::skew<S>(w_ie);
    m.H.template block<3, 3>(0, gpsins::kBg) = -Mat3<S>::Identity();
    const S dt = s.dt_last > 0.0 ? S(s.dt_last) : S(1);
    m.R.diagonal().setConstant(p.gyro_noise * p.gyro_noise / dt + p.zaru_sigma * p.zaru_sigma);
  }
};

/// Non-holonomic constraint of a wheeled vehicle: no lateral or vertical velocity of the vehicle
/// at the IMU; with the IMU's mounting k = (k_y, k_z) (the lateral and vertical body velocity per
/// forward speed, learned by detail::gpsins_nhc_evidence; 0: the body axes are the vehicle's),
/// y = (v_b,y - k_y v_b,x, v_b,z - k_z v_b,x) with v_b = C_nb^T v_n, H the same combination of the
/// rows of v_b's (side slip is in nhc_sigma). Without k a mounting off by a degree is a constraint
/// off by 0.4 m/s at 25 m/s, a bias that the updates at 10 Hz turn into a pitch or yaw error.
/// `var`: the variance of each row (0: nhc_sigma^2). The lateral row's variance gains
/// (w_z nhc_arm)^2, w_z the corrected body yaw rate: an IMU a distance L ahead of or behind the
/// non-slipping axle moves sideways at w_z L in a turn (1.2 m at 14 deg/s: 0.29 m/s against
/// nhc_sigma's 0.1), which the row would otherwise force to zero through the tilt and heading.
/// With nhc_lever_b the rows hold the velocity at the non-slipping point, v_b + w x nhc_lever_b;
/// the lever term's dependence on the gyro bias (1 mm/s per mrad/s at 1 m) is left out of H.
/// Without `lateral` the lateral row is left out (its residual and H zero: it carries no information).
template <class S> struct NonHolonomic {
  static constexpr GpsInsAid kind = GpsInsAid::Nhc;
  static constexpr int M = 2, C0 = 3, NC = 6;
  static constexpr bool kAdaptive = false;
  S var = S(0);
  S ky = S(0), kz = S(0);
  bool lateral = true;
  static S gate(const GpsInsParams<S>& p) { return p.gate_nhc; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    static constexpr int rows[3] = {0, 1, 2};
    Vec3<S> v;
    Mat<S, 3, N> H = Mat<S, 3, N>::Zero();
    detail_body::body_velocity_rows<S, 3>(s, rows, v, H);
    v += s.omega_b.cross(p.nhc_lever_b);
    m.y << v[1] - ky * v[0], v[2] - kz * v[0];
    m.H.row(0) = H.row(1) - ky * H.row(0);
    m.H.row(1) = H.row(2) - kz * H.row(0);
    m.R.diagonal().setConstant(var > S(0) ? var : p.nhc_sigma * p.nhc_sigma);
    if (p.nhc_arm > S(0)) {
      const S u = s.omega_b[2] * p.nhc_arm;
      m.R(0, 0) += u * u;
    }
    if (!lateral) {
      m.y[0] = S(0);
      m.H.row(0).setZero();
    }
  }
};

/// Odometer forward speed (m/s): y = (C_nb^T v_n)_x - speed.
template <class S> struct OdometerSpeed {
  static constexpr GpsInsAid kind = GpsInsAid::Odometer;
  static constexpr int M = 1, C0 = 3, NC = 6;
  static constexpr bool kAdaptive = false;
  S speed;
  static S gate(const GpsInsParams<S>& p) { return p.gate_odometer; }
  template <bool SF, int N>
  void measure(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, AidMeasurement<S, M, N>& m) const {
    static constexpr int rows[1] = {0};
    detail_body::body_velocity_rows<S, 1>(s, rows, m.y, m.H);
    m.y[0] -= speed;
    m.R(0, 0) = p.odometer_sigma * p.odometer_sigma;
  }
};

}  // namespace gpsins_aid

namespace detail {
/// The position piece of a fix of solution kind `kind` valid `age` s before the filter's time,
/// its one-sigma and floor raised by gnss_correlation_scale since the last position used.
template <class S, bool SF>
gpsins_aid::GpsPosition<S> gnss_position(const GpsInsState<S, SF>& s, const GpsInsParams<S>& p, double lat, double lon,
                                         double h, const Vec3<S>& sig, S age, const Vec3<S>& floor, GnssSolution kind) {
  const S k = gnss_correlation_scale(p, kind, s.t - double(age) - s.gps_pos_t);
  return gpsins_aid::GpsPosition<S>{lat, lon, h, Vec3<S>(k * sig), age, Vec3<S>(k * floor)};
}

/// The result r of a position fix valid `age` s before the filter's time: when the fix was used
/// (accepted, or the state reset to it) its time of validity is kept (gps_pos_t).
template <class S, bool SF>
GpsInsUpdate<S, 3> position_used(GpsInsState<S, SF>& s, const GpsInsUpdate<S, 3>& r, S age) {
  if (r.status == Status::Ok || r.decision == GpsInsDecision::Reset) s.gps_pos_t = s.t - double(age);
  return r;
}
}  // namespace detail
}  // namespace quatnav
