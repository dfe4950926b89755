// quatnav: GpsInsFilter's alignment parts (nav/gps_ins.hpp): the rest detector, the TRIAD
// attitude from two vector pairs, and the motion window that aligns from GNSS while moving.
//
// Rest: the gyro and the accelerometer each low-passed (time constant rest_tau); the IMU is
// still while |w - lp(w)| < rest_gyr_th, |f - lp(f)| < rest_acc_th and ||lp(f)| - g| <
// rest_acc_th, and the speed is below rest_speed (before navigation the GNSS speed less three of
// its sigmas, when one is known from the last 2 s; during navigation the INS speed less three of
// its sigmas): an IMU
// alone cannot tell a smooth constant-velocity motion, or a gentle acceleration, from rest. At rest
// once still for rest_time. Static levelling averages the accelerometer only
// over still samples (motion restarts the average); ZUPT and ZARU use the rest state.
//
// Alignment in motion (Lee & Jeong's filter assumes a start at rest; a vehicle already moving
// needs more): a window opens at a GNSS fix; over it the gyro integrates the rotation from the
// body frame at its start, C_b0b, and the specific force the velocity increment in that frame,
// dv_b0 = sum C_b0b f dt. At a later fix T >= align_motion_time seconds on:
//   with GNSS velocity: v2 - v1 = C_nb0 dv_b0 + g_n T (Coriolis left out), and the body x axis
//     points along the horizontal velocity (no sideslip): TRIAD with dv_b0 <-> v2 - v1 - g_n T
//     (primary: it fixes roll and pitch whatever the acceleration) and x_b <-> the course;
//   with positions only: once the fixes are align_course_distance apart, the course between them
//     gives the heading and the mean velocity, and the mean specific force the level (the mean
//     acceleration over the window taken as zero, with the one-sigma align_level_sigma).
// The result says which alignment was used and when (GpsInsAlignment, state().level_t,
// nav_start_t).
#pragma once

#include <algorithm>
#include <cmath>

#include "../../core/lowpass.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"
#include "model.hpp"
#include "params.hpp"

namespace quatnav {
namespace detail {

/// GNSS-aided: a GNSS position or velocity accepted within the last 2.5 s (the learned
/// non-holonomic constraint's evidence and mounting are gathered then, its lateral row applied
/// otherwise).
template <class S, bool SF> bool gpsins_gnss_aided(const GpsInsState<S, SF>& s) { return s.t - s.gnss_t < 2.5; }

/// The evidence of a wheeled vehicle (nhc_auto), after a navigating time update over dt. While
/// GNSS-aided (an accepted GNSS position or velocity update less than 2.5 s before) and faster
/// than nhc_auto_speed forward (body x): the IMU's mounting, the ratios k = (v_b,y, v_b,z) / v_b,x,
/// is low-passed into s.nhc_ky, s.nhc_kz (from 0, time constants nhc_mount_tau_yaw and
/// nhc_mount_tau_pitch; 0: not learned) while the body yaw rate is within nhc_auto_rate (driving
/// straight, the lateral velocity is the mounting's; in a turn an IMU ahead of the rear axle moves
/// sideways). A heading error looks the same to the constraint as a mounting in yaw (v_b,y =
/// -v psi_d), and the heading is the state the GNSS observes least on a car: k_y is learned
/// slowly, so that it holds the constant mounting and not the heading error of the last
/// seconds; a pitch error is observed by the GNSS through gravity, k_z is learned fast. The squared
/// residual e = (v_b,y - k_y v_b,x)^2 + (v_b,z - k_z v_b,x)^2 is low-passed into s.nhc_ms (time
/// constant nhc_auto_time / 4; the first sample starts it) and the
/// time with s.nhc_ms within nhc_auto_limit^2 accumulates in s.nhc_t; above (2 nhc_auto_limit)^2
/// the evidence is lost (s.nhc_t = 0); in between it is held (a car's sustained tight turn, the
/// IMU ahead of the rear axle, must not undo it). Slow or unaided (a GNSS outage, where the
/// velocity is the constrained INS's own) it is held.
template <class S, bool SF> void gpsins_nhc_evidence(GpsInsState<S, SF>& s, const GpsInsParams<S>& p, S dt) {
  if (!p.nhc_auto || !gpsins_gnss_aided(s)) return;
  const Vec3<S> v_b = quat::rotate_inv(s.nav.q_nb, s.nav.v_n) + s.omega_b.cross(p.nhc_lever_b);  // at the axle
  if (!(std::abs(v_b[0]) > p.nhc_auto_speed)) return;
  if (std::abs(s.omega_b[2]) <= p.nhc_auto_rate) {
    if (p.nhc_mount_tau_yaw > S(0)) lowpass(s.nhc_ky, S(v_b[1] / v_b[0]), dt, p.nhc_mount_tau_yaw);
    if (p.nhc_mount_tau_pitch > S(0)) lowpass(s.nhc_kz, S(v_b[2] / v_b[0]), dt, p.nhc_mount_tau_pitch);
  }
  const S ey = v_b[1] - s.nhc_ky * v_b[0], ez = v_b[2] - s.nhc_kz * v_b[0];
  const S e = ey * ey + ez * ez;
  const S tau = p.nhc_auto_time / S(4);
  if (s.nhc_ms < S(0))
    s.nhc_ms = e;
  else
    lowpass(s.nhc_ms, e, dt, tau);
  const S lim2 = p.nhc_auto_limit * p.nhc_auto_limit;
  if (s.nhc_ms <= lim2)
    s.nhc_t += double(dt);
  else if (!(s.nhc_ms <= S(4) * lim2))
    s.nhc_t = 0.0;
}

/// One step of the rest detector on the bias-corrected rate w and specific force f over dt,
/// with gravity g (m/s^2); `slow`: the speed allows rest (an IMU alone cannot tell a smooth
/// constant-velocity motion from rest). Returns whether the sample is still; updates the
/// low-passes and the time the IMU has been still (s.rest_t).
template <class S, bool SF>
bool gpsins_rest_step(GpsInsState<S, SF>& s, const GpsInsParams<S>& p, const Vec3<S>& w, const Vec3<S>& f, S dt, S g,
                      bool slow) {
  if (!s.rest_init) {
    s.rest_gyr_lp = w;
    s.rest_acc_lp = f;
    s.rest_init = true;
  } else {
    const S a = lowpass_weight(dt, p.rest_tau);
    s.rest_gyr_lp += a * (w - s.rest_gyr_lp);
    s.rest_acc_lp += a * (f - s.rest_acc_lp);
  }
  const bool still = slow && (w - s.rest_gyr_lp).norm() < p.rest_gyr_th && (f - s.rest_acc_lp).norm() < p.rest_acc_th &&
                     std::abs(s.rest_acc_lp.norm() - g) < p.rest_acc_th;
  s.rest_t = still ? s.rest_t + double(dt) : 0.0;
  return still;
}

/// Navigating: whether the speed allows rest. The INS speed, allowed up to 3 sigma more but never
/// more than rest_speed more: an uncertain velocity (a GNSS outage) must not make a vehicle
/// cruising with a quiet IMU look stopped (a false zero-velocity update pins the position where
/// the outage began). `resolved`: 3 sigma within rest_speed; else the speed is the rest test's
/// velocity, without the INS velocity's drift (gpsins_rest_velocity).
template <class S, bool SF> bool gpsins_rest_slow(GpsInsState<S, SF>& s, const GpsInsParams<S>& p, bool& resolved) {
  const S sv = std::sqrt(s.P(gpsins::kVel, gpsins::kVel) + s.P(gpsins::kVel + 1, gpsins::kVel + 1) +
                         s.P(gpsins::kVel + 2, gpsins::kVel + 2));
  resolved = S(3) * sv <= p.rest_speed;
  if (resolved) s.rest_v = s.nav.v_n;
  return s.rest_v.norm() < p.rest_speed + std::min(S(3) * sv, p.rest_speed);
}

/// The rest test's velocity in a GNSS outage. While three sigmas of the INS speed are within
/// rest_speed it is the INS velocity. Beyond that the INS velocity's drift can carry a vehicle
/// moving at a constant speed, whose IMU is as quiet as at rest, below rest_speed, and the
/// zero-velocity updates would then pin it. A stop shows as a deceleration, a drift does not: the
/// rest test's velocity s.rest_v takes the INS velocity change dv of a sample only when the
/// low-passed horizontal acceleration stands out of what the covariance allows without motion
/// (three sigmas of the tilt error times g, the accelerometer bias and the low-passed noise).
template <class S, bool SF>
void gpsins_rest_velocity(GpsInsState<S, SF>& s, const GpsInsParams<S>& p, const Vec3<S>& dv, S g) {
  const Vec3<S> a_n = quat::rotate(s.nav.q_nb, s.rest_acc_lp);  // + g_n: the horizontal part is the acceleration
  const auto& P = s.P;
  const S var = g * g * (P(gpsins::kAtt, gpsins::kAtt) + P(gpsins::kAtt + 1, gpsins::kAtt + 1)) +
                P(gpsins::kBa, gpsins::kBa) + P(gpsins::kBa + 1, gpsins::kBa + 1) + P(gpsins::kBa + 2, gpsins::kBa + 2) +
                p.acc_noise * p.acc_noise / p.rest_tau;  // two axes of white noise low-passed: q^2 / (2 tau) each
  if (a_n[0] * a_n[0] + a_n[1] * a_n[1] > S(9) * var) s.rest_v += dv;
}

/// TRIAD: the rotation C_nb with C_nb a_b = a_n exactly (the primary pair, directions) and
/// C_nb b_b in the plane of a_n and b_n (the secondary). False when a pair is (near) parallel.
template <class S>
bool triad(const Vec3<S>& a_b, const Vec3<S>& b_b, const Vec3<S>& a_n, const Vec3<S>& b_n, Mat3<S>& C_nb) {
  const S tiny = S(1e-6);
  const Vec3<S> cb = a_b.cross(b_b), cn = a_n.cross(b_n);
  if (!(a_b.norm() > tiny && a_n.norm() > tiny && cb.norm() > tiny * a_b.norm() * b_b.norm() &&
        cn.norm() > tiny * a_n.norm() * b_n.norm()))
    return false;
  Mat3<S> Mb, Mn;
  Mb.col(0) = a_b.normalized();
  Mb.col(1) = cb.normalized();
  Mb.col(2) = Mb.col(0).cross(Mb.col(1));
  Mn.col(0) = a_n.normalized();
  Mn.col(1) = cn.normalized();
  Mn.col(2) = Mn.col(0).cross(Mn.col(1));
  C_nb = Mn * Mb.transpose();
  return C_nb.allFinite();
}

/// Restart the motion window at a fix (lat, lon, h; velocity v when has_v).
template <class S, bool SF>
void gpsins_window_start(GpsInsState<S, SF>& s, double lat, double lon, double h, const Vec3<S>& v, bool has_v) {
  s.mot_valid = true;
  s.mot_lat = lat;
  s.mot_lon = lon;
  s.mot_h = h;
  s.mot_has_v = has_v;
  s.mot_v0 = has_v ? v : Vec3<S>::Zero();
  s.mot_q = quat::identity<S>();
  s.mot_dv = Vec3<double>::Zero();
  s.mot_T = 0.0;
}

/// One IMU step of the motion window: the rotation from the window's first body frame and the
/// specific-force velocity increment in that frame (midpoint rotation).
template <class S, bool SF> void gpsins_window_step(GpsInsState<S, SF>& s, const Vec3<S>& w, const Vec3<S>& f, S dt) {
  const Quat<S> half = quat::mul(s.mot_q, quat::from_rotvec(Vec3<S>(w * (dt * S(0.5)))));
  s.mot_dv += (quat::rotate(half, f) * dt).template cast<double>();
  Quat<S> q = quat::mul(s.mot_q, quat::from_rotvec(Vec3<S>(w * dt)));
  s.mot_q = q / q.norm();
  s.mot_T += double(dt);
}

}  // namespace detail
}  // namespace quatnav
