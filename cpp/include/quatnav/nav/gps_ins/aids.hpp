// quatnav: GpsInsFilter's aids as small pieces of one measurement shape (nav/gps_ins.hpp).
//
// In the spirit of pyins' Measurement.compute_matrices(time, state) -> (z, H, R): each piece
// holds one aiding sample and, at a state, gives its innovation y (INS minus aid, eq. 11), the
// measurement matrix H over the error state and the noise covariance R (AidMeasurement). The
// filter sends every piece through one gated correction path (GpsInsFilter::apply): gate,
// Kalman correction, injection, counters. A new aid is one more piece, not a new path through
// the filter. Each piece also states where its H can be nonzero (columns C0 .. C0 + NC - 1 of
// the error state), which the correction exploits; fixed sizes, no heap, no virtual calls.
#pragma once

#include <cmath>

#include "../../core/earth.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"
#include "params.hpp"

namespace quatnav {

/// One aid sample linearized at a state: y = INS minus aid (M), H (M x 15), R (M x M).
template <class S, int M> struct AidMeasurement {
  Vec<S, M> y = Vec<S, M>::Zero();
  Mat<S, M, 15> H = Mat<S, M, 15>::Zero();
  Mat<S, M, M> R = Mat<S, M, M>::Zero();
};

namespace detail {
/// Yaw-error row of the compass: d yaw / d psi = [tan(theta) cos(yaw), tan(theta) sin(yaw), 1].
template <class S> Vec3<S> compass_row(const Quat<S>& q_nb) {
  const Vec3<S> e = quat::to_euler(q_nb);
  const S tp = std::tan(e[1]);
  return Vec3<S>(tp * std::cos(e[2]), tp * std::sin(e[2]), S(1));
}
}  // namespace detail

/// The pieces. Each has: kind (its counters), M (rows), C0, NC (the columns of the error state
/// where H may be nonzero), gate(params) and measure(state, params, out).
namespace gpsins_aid {

/// GPS antenna position (lat, lon rad; h m) with its NED one-sigma (m): the INS antenna position
/// p + C_nb l_b minus the fix, in NED metres about the fix; H = [I, 0, -[(C_nb l_b) x], 0, 0].
template <class S> struct GpsPosition {
  static constexpr GpsInsAid kind = GpsInsAid::GpsPos;
  static constexpr int M = 3, C0 = 0, NC = 9;
  double lat, lon, h;
  Vec3<S> sigma;
  static S gate(const GpsInsParams<S>& p) { return p.gate_gps_pos; }
  void measure(const GpsInsState<S>& s, const GpsInsParams<S>& p, AidMeasurement<S, M>& m) const {
    const Mat3<S> C = quat::to_rotmat(s.nav.q_nb);
    const Vec3<S> l_n = C * p.lever_arm_b;
    double la = s.nav.lat, lo = s.nav.lon, hh = s.nav.h;
    earth::geodetic_add(la, lo, hh, l_n.template cast<double>());
    m.y = earth::geodetic_diff<S>(la, lo, hh, lat, lon, h);
    m.H.template block<3, 3>(0, 0).setIdentity();
    m.H.template block<3, 3>(0, 6) = -quat::skew<S>(l_n);
    m.R = sigma.cwiseAbs2().asDiagonal();
  }
};

/// GPS antenna velocity (NED, m/s) with its one-sigma per axis: v + C_nb (w_ib_b x l_b) minus the
/// fix (Earth rate in the lever-arm term neglected); H = [0, I, -[(C_nb (w x l_b)) x], 0, C_nb [l_b x]].
template <class S> struct GpsVelocity {
  static constexpr GpsInsAid kind = GpsInsAid::GpsVel;
  static constexpr int M = 3, C0 = 3, NC = 12;
  Vec3<S> v_n;
  Vec3<S> sigma;
  static S gate(const GpsInsParams<S>& p) { return p.gate_gps_vel; }
  void measure(const GpsInsState<S>& s, const GpsInsParams<S>& p, AidMeasurement<S, M>& m) const {
    const Mat3<S> C = quat::to_rotmat(s.nav.q_nb);
    const Vec3<S> wl = s.omega_b.cross(p.lever_arm_b);
    m.y = s.nav.v_n + C * wl - v_n;
    m.H.template block<3, 3>(0, 3).setIdentity();
    m.H.template block<3, 3>(0, 6) = -quat::skew<S>(Vec3<S>(C * wl));
    m.H.template block<3, 3>(0, 12) = C * quat::skew<S>(p.lever_arm_b);
    m.R = sigma.cwiseAbs2().asDiagonal();
  }
};

/// Altimeter height (m): h_INS - (h_baro + offset), H = -1 on dp_D. R adds the offset's own
/// uncertainty (a mean of n GPS heights) to the altimeter noise.
template <class S> struct BaroHeight {
  static constexpr GpsInsAid kind = GpsInsAid::Baro;
  static constexpr int M = 1, C0 = 2, NC = 1;
  double h;
  static S gate(const GpsInsParams<S>& p) { return p.gate_baro; }
  void measure(const GpsInsState<S>& s, const GpsInsParams<S>& p, AidMeasurement<S, M>& m) const {
    m.y[0] = S(s.nav.h - (h + s.baro_offset));
    m.H(0, 2) = S(-1);
    m.R(0, 0) = p.baro_sigma * p.baro_sigma +
                p.gps_pos_sigma_v * p.gps_pos_sigma_v / S(s.baro_offset_n > 1.0 ? s.baro_offset_n : 1.0);
  }
};

/// Altimeter vertical velocity over a baseline of T seconds (paper 004): v_D,INS - v_D,baro with
/// v_D,baro = -(h - h_ref) / T; R = 2 sigma_h^2 / T^2 + baro_vd_sigma^2 (successive derivatives
/// share an end point, so their noise is correlated by -1/2; the extra term covers that and the
/// lag of a mean rate).
template <class S> struct BaroVerticalVelocity {
  static constexpr GpsInsAid kind = GpsInsAid::BaroVd;
  static constexpr int M = 1, C0 = 5, NC = 1;
  double h, h_ref, T;
  static S gate(const GpsInsParams<S>& p) { return p.gate_baro; }
  void measure(const GpsInsState<S>& s, const GpsInsParams<S>& p, AidMeasurement<S, M>& m) const {
    const S vd_baro = S(-(h - h_ref) / T);
    m.y[0] = s.nav.v_n[2] - vd_baro;
    m.H(0, 5) = S(1);
    m.R(0, 0) = S(2) * p.baro_sigma * p.baro_sigma / S(T * T) + p.baro_vd_sigma * p.baro_vd_sigma;
  }
};

/// Compass heading (rad, true: the declination already added): wrap(yaw_INS - yaw),
/// H = [0, 0, tan(theta) cos(yaw), tan(theta) sin(yaw), 1, 0...].
template <class S> struct CompassHeading {
  static constexpr GpsInsAid kind = GpsInsAid::Compass;
  static constexpr int M = 1, C0 = 6, NC = 3;
  S yaw;
  static S gate(const GpsInsParams<S>& p) { return p.gate_compass; }
  void measure(const GpsInsState<S>& s, const GpsInsParams<S>& p, AidMeasurement<S, M>& m) const {
    const Vec3<S> e = quat::to_euler(s.nav.q_nb);
    m.y[0] = quat::wrap_pi(e[2] - yaw);
    m.H.template block<1, 3>(0, 6) = detail::compass_row(s.nav.q_nb).transpose();
    m.R(0, 0) = p.compass_sigma * p.compass_sigma;
  }
};

}  // namespace gpsins_aid
}  // namespace quatnav
