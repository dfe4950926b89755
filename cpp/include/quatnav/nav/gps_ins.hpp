// quatnav: loosely coupled GPS/INS feedback Kalman filter with altimeter and compass (paper 004,
// Lee & Jeong, "Design and Implementation of UAV Navigation System Using Kalman Filter").
//
// Nominal state: the strapdown mechanization of strapdown.hpp (quaternion attitude q_nb, NED
// velocity with Coriolis and transport terms, geodetic position kept in double), fed with the
// IMU corrected by the current bias estimates. Paper 004 integrates Euler angles (eq. 1); the
// quaternion is used instead, so there is no gimbal lock; Euler angles are an output only.
//
// Error state (15), eq. (3)-(7), every error defined as estimate minus truth:
//   dx = [dp_n (N, E, D position error, m), dv_n (m/s), psi (rad), db_a (m/s^2), db_g (rad/s)]
// The attitude error is the phi-angle (nav-frame small rotation): C_nb_est = (I + [psi x]) C_nb.
// Paper 004's state list (eq. 5) repeats V_E and psi_N: the intended states are the 15 above.
//
// Continuous error dynamics (detail::gpsins_F; checked against finite differences of the
// mechanization in tests/python/test_gpsins_jacobian.py; radii taken constant in latitude):
//   dp' = F_pp dp + dv                                           (eq. 9: in metres, the exact
//         linearization of lat' = v_N/(R_M+h), lon' = v_E/((R_N+h) cos L), h' = -v_D)
//   dv' = -[f_n x] psi - C_nb db_a - [(2 w_ie + w_en) x] dv + [v x](2 dw_ie + dw_en) + dg   (eq. 8)
//   psi' = -[w_in x] psi - C_nb db_g - dw_in                     (eq. 10)
//   db' = -db / tau (first-order Gauss-Markov; tau <= 0: random walk)
// Paper slips fixed here: eq. (10) writes only w_ie x Psi; the nav frame turns at
// w_in = w_ie + w_en, and the errors of w_ie (latitude) and w_en (velocity, position) drive psi.
// Eq. (8)'s "f^n Psi" is -[f_n x] psi with the sign of this error definition. Eq. (2)'s V^n lists
// V_E twice (it is [V_N V_E V_D]), its R_m lost the power 3/2 (R_M = R0 (1-e^2) /
// (1 - e^2 sin^2 L)^{3/2}), w_ie lost cos L ([W cos L, 0, -W sin L]) and g^n = [0 0 -g_e] has the
// wrong sign for NED (g_n = [0, 0, +g]): earth.hpp has the corrected forms.
//
// Discretization over one IMU interval dt, with F evaluated before the step:
//   Phi = I + F dt + (F dt)^2 / 2,  Qd = (Phi Qc Phi^T + Qc) dt / 2  (trapezoidal),
//   P <- Phi P Phi^T + Qd.
// Qc: accelerometer white noise on dv, gyro white noise on psi, bias driving noise on db.
//
// Measurements (eq. 11: z = INS minus aid = H dx + noise; the innovation reported is INS minus
// aid), each at its own rate and each gated by a chi-square threshold (0 switches a gate off):
//   GPS position of the antenna (3): the INS antenna position p + C_nb l_b minus the fix,
//     expressed in NED metres; H = [I, 0, -[(C_nb l_b) x], 0, 0].
//   GPS velocity of the antenna (3): v + C_nb (w_ib_b x l_b) minus the fix (Earth rate in the
//     lever-arm term neglected); H = [0, I, -[(C_nb (w x l_b)) x], 0, C_nb [l_b x]].
//   Altimeter height (1): h_INS - (h_baro + offset); the offset ties the altimeter to the GPS
//     height: a running mean of (GPS height - altimeter) over the last baro_offset_fixes fixes,
//     kept outside the Kalman filter (the paper zeroes the altimeter on the ground);
//     R = baro_sigma^2 + gps_pos_sigma_v^2 / n for an offset averaged over n fixes. The offset's
//     error is common to every altimeter sample but enters R as white noise, so with the
//     altimeter the height, v_D and accelerometer-z sigmas are too small (NEES of dp_D about 24
//     on a simulated walk; tests/python/test_gpsins_consistency.py); an offset state would fix it.
//   Altimeter vertical velocity (1), as the paper does: v_D,INS - v_D,baro, where v_D,baro is the
//     derivative of the altimeter over a baseline of at least baro_rate_baseline seconds,
//     R = 2 sigma_h^2 / T^2 + baro_vd_sigma^2 (successive derivatives share an end point, so
//     their noise is correlated by -1/2; the extra term covers that and the lag of a mean rate).
//   Compass heading (1): wrap(yaw_INS - (psi_mag + declination)),
//     H = [0, 0, tan(theta) cos(yaw), tan(theta) sin(yaw), 1, 0...].
// Gate lockout: a chi-square gate alone can reject every fix for good once the INS error has
// outgrown its covariance (seen on a real pedestrian walk with cm-level RTK fixes: after one
// rejection no fix was ever accepted again and the position drifted by hundreds of metres). After
// gps_reset_after consecutive rejected GPS positions (velocities) the next rejected one resets
// the position (velocity) to the fix, less the lever-arm term, with the fix's covariance in its
// block and its cross-covariances zeroed; the update still reports Rejected, the reset is
// counted (counters.resets) and flagged (flags::kGpsReset).
// Feedback (paper Fig. 2): after each accepted correction dx is injected into the nominal state
// (lat -= dp_N / (R_M + h), lon -= dp_E / ((R_N + h) cos L), h += dp_D, v -= dv,
// q_nb <- exp(-psi) * q_nb, b -= db) and dx is reset to zero (the covariance is kept: the reset
// Jacobian I - [psi/2 x] is taken as I, a second-order effect).
//
// Initial alignment (phase machine, also run by gpsins_batch):
//   Aligning: the IMU is assumed at rest; the accelerometer is averaged for align_time seconds.
//   Levelled: roll and pitch from the mean specific force; the attitude is then integrated with
//     the gyro alone while waiting for a heading (compass, or the course of a GPS velocity of at
//     least min_speed_for_heading, assuming the body x axis points along the motion) and a fix.
//   Navigating: position from the first fix (less the lever arm), velocity from its velocity
//     (zero when absent), covariance from the parameters; then the full filter runs.
//
// No heap, no exceptions from any step; a step whose status is not Ok (or Rejected, for an
// update) leaves the state bit-for-bit untouched, with one documented exception: before
// navigation starts an aid that is used for initialization (a compass heading, a GPS course, an
// altimeter height kept for its offset) returns NotInitialized after being recorded. A Rejected
// GPS update changes only the counters, except the gate-lockout reset described above.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "../core/checks.hpp"
#include "../core/commit.hpp"
#include "../core/covariance.hpp"
#include "../core/earth.hpp"
#include "../core/kalman.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"
#include "gps_ins/aids.hpp"
#include "gps_ins/model.hpp"
#include "gps_ins/params.hpp"
#include "strapdown.hpp"

namespace quatnav {

/// Outcome of an altimeter sample: its height update and (when a baseline was complete) its
/// vertical-velocity update (status NotInitialized when none was made).
template <class S> struct BaroResult {
  UpdateResult<S, 1> height;
  UpdateResult<S, 1> vd;
};

/// Outcome of a GPS fix: position and velocity updates (velocity NotInitialized when absent).
template <class S> struct GpsResult {
  UpdateResult<S, 3> pos;
  UpdateResult<S, 3> vel;
};

/// The 15-state feedback GPS/INS filter.
template <class S_> class GpsInsFilter {
 public:
  using Scalar = S_;
  using S = S_;
  using Params = GpsInsParams<S>;
  using State = GpsInsState<S>;
  using Mat15 = Mat<S, 15, 15>;
  using Vec15 = Vec<S, 15>;
  static constexpr int kStates = 15;

  explicit GpsInsFilter(const Params& params = Params()) : p_(params) {}

  const Params& params() const { return p_; }
  /// Replace the parameters (the state is kept).
  void set_params(const Params& params) { p_ = params; }
  const State& state() const { return s_; }
  /// Restore a state; InvalidArgument (nothing changed) when it is not finite.
  Status set_state(const State& s) {
    // As the filter keeps them: everything finite, |q| = 1, the latitude off the poles
    // (detail::gpsins_nav_ok), P exactly symmetric with a non-negative diagonal.
    if (!detail::gpsins_nav_ok(s) || !std::isfinite(s.t) || !s.omega_b.allFinite() || !s.f_b.allFinite() ||
        !s.align_sum.allFinite() || !std::isfinite(s.align_time) || !std::isfinite(s.baro_offset) ||
        !std::isfinite(s.baro_last) || !std::isfinite(s.baro_ref_h) || !std::isfinite(s.baro_ref_t) ||
        !std::isfinite(s.baro_offset_n) || !detail::acceptable_covariance<S, 15>(s.P) || int(s.phase) > 2)
      return Status::InvalidArgument;
    s_ = s;
    return Status::Ok;
  }
  /// Back to the start of alignment (parameters kept): the filter aligns again from the next
  /// IMU samples.
  void clear() { s_ = State(); }

  GpsInsPhase phase() const { return s_.phase; }
  bool navigating() const { return s_.phase == GpsInsPhase::Navigating; }
  bool levelled() const { return s_.phase != GpsInsPhase::Aligning; }
  const Quat<S>& q_nb() const { return s_.nav.q_nb; }
  Vec3<S> euler() const { return quat::to_euler(s_.nav.q_nb); }
  const Vec3<S>& v_n() const { return s_.nav.v_n; }
  Vec3<double> llh() const { return Vec3<double>(s_.nav.lat, s_.nav.lon, s_.nav.h); }
  const Vec3<S>& acc_bias() const { return s_.acc_bias; }
  const Vec3<S>& gyro_bias() const { return s_.gyro_bias; }
  const Mat15& covariance() const { return s_.P; }
  double time() const { return s_.t; }

  /// Start navigation from a given state (skipping alignment): attitude, velocity, position,
  /// biases and the covariance; as reset() of every filter (initialize() starts a filter from
  /// sensor readings, reset() from a state). InvalidArgument when anything is non-finite or P is
  /// not symmetric.
  Status reset(const Quat<S>& q_nb, const Vec3<S>& v_n, double lat, double lon, double h,
                    const Vec3<S>& acc_bias, const Vec3<S>& gyro_bias, const Mat15& P) {
    if (!q_nb.allFinite() || !v_n.allFinite() || !std::isfinite(lat) || !std::isfinite(lon) || !std::isfinite(h) ||
        !acc_bias.allFinite() || !gyro_bias.allFinite() || !P.allFinite() || !(q_nb.norm() > S(0.5)))
      return Status::InvalidArgument;
    if (!((P - P.transpose()).cwiseAbs().maxCoeff() <= S(1e-6) * (S(1) + P.cwiseAbs().maxCoeff())))
      return Status::InvalidArgument;
    Mat15 Ps = P;
    symmetrize(Ps);
    // A P near the float maximum overflows when symmetrized.
    if (!Ps.allFinite() || !(Ps.diagonal().array() >= S(0)).all()) return Status::InvalidArgument;
    floor_covariance<S, 15>(Ps, p_.cov_floor);
    State s = s_;
    s.nav = StrapdownState<S>();
    s.nav.q_nb = q_nb / q_nb.norm();
    s.nav.v_n = v_n;
    s.nav.lat = lat;
    s.nav.lon = lon;
    s.nav.h = h;
    s.acc_bias = acc_bias;
    s.gyro_bias = gyro_bias;
    s.P = Ps;
    s.phase = GpsInsPhase::Navigating;
    s.heading_known = true;
    // A quaternion whose norm overflows normalizes to zero; a latitude at a pole: refused.
    if (!detail::gpsins_nav_ok(s)) return Status::InvalidArgument;
    s_ = s;
    return Status::Ok;
  }

  /// The covariance that initialization uses for a fix with NED position sigmas pos_sigma (m).
  Mat15 initial_covariance(const Vec3<S>& pos_sigma, S vel_sigma) const {
    Vec15 d;
    d << pos_sigma, Vec3<S>::Constant(vel_sigma), p_.init_level_sigma, p_.init_level_sigma, p_.init_yaw_sigma,
        Vec3<S>::Constant(p_.init_acc_bias_sigma), Vec3<S>::Constant(p_.init_gyro_bias_sigma);
    return d.cwiseAbs2().asDiagonal();
  }

  /// Time update over one IMU interval: mean body rate omega_ib_b (rad/s) and specific force
  /// f_ib_b (m/s^2) over dt (s). Aligning: averages f; Levelled: integrates the attitude only;
  /// Navigating: strapdown (eq. 1-2) with bias-corrected inputs and covariance propagation.
  Status predict(const Vec3<S>& omega_ib_b, const Vec3<S>& f_ib_b, S dt) {
    if (!(std::isfinite(dt) && dt > S(0) && dt <= p_.max_dt)) return Status::InvalidDt;
    if (!omega_ib_b.allFinite() || !f_ib_b.allFinite()) return Status::NonFinite;
    if (detail::saturated(omega_ib_b, p_.gyro_range) || detail::saturated(f_ib_b, p_.acc_range))
      return Status::Saturated;
    State s = s_;
    const Vec3<S> w = omega_ib_b - s.gyro_bias;
    const Vec3<S> f = f_ib_b - s.acc_bias;
    if (s.phase == GpsInsPhase::Aligning) {
      s.align_sum += f_ib_b.template cast<double>() * double(dt);
      s.align_time += double(dt);
      if (!s.align_sum.allFinite()) return Status::NumericalFailure;
      if (s.align_time >= double(p_.align_time)) {
        const Vec3<S> fm = (s.align_sum / s.align_time).template cast<S>();
        const S fn = fm.norm();
        if (!(fn > S(1))) {
          // No gravity in the mean (free fall or a broken sensor): start the average again.
          s.align_sum.setZero();
          s.align_time = 0.0;
          s.t += double(dt);
          s_ = s;
          return Status::Ok;
        }
        // Level: the specific force at rest is -g in NED, f_b = C_nb^T [0, 0, -g].
        S roll, pitch;
        detail::level_from_acc(fm, roll, pitch);
        s.nav.q_nb = quat::from_euler(roll, pitch, S(0));
        s.phase = GpsInsPhase::Levelled;
      }
    } else if (s.phase == GpsInsPhase::Levelled) {
      Quat<S> q = quat::mul(s.nav.q_nb, quat::from_rotvec(Vec3<S>(w * dt)));
      s.nav.q_nb = q / q.norm();
    } else {
      StrapdownParams sp;
      sp.earth_rotation = p_.earth_rotation;
      const Mat15 F = detail::gpsins_F<S>(s.nav, f, p_);
      const Status st = strapdown_step(s.nav, w, f, dt, sp);
      if (st != Status::Ok) return st;
      const Mat15 Fdt = F * dt;
      const Mat15 Phi = Mat15::Identity() + Fdt + S(0.5) * fixed_mul(Fdt, Fdt);
      const Vec15 qc = detail::gpsins_Qc_diag(p_);
      const Mat15 PhiQ = Phi * qc.asDiagonal();
      Mat15 Qd = S(0.5) * dt * fixed_mul(PhiQ, Phi.transpose());
      Qd.diagonal() += S(0.5) * dt * qc;
      Mat15 P = fixed_mul(fixed_mul(Phi, s.P), Phi.transpose()) + Qd;
      symmetrize(P);
      if (p_.acc_bias_tau > S(0)) s.acc_bias *= std::exp(-dt / p_.acc_bias_tau);
      if (p_.gyro_bias_tau > S(0)) s.gyro_bias *= std::exp(-dt / p_.gyro_bias_tau);
      if (!P.allFinite()) return Status::NumericalFailure;
      floor_covariance<S, 15>(P, p_.cov_floor);
      s.P = P;
    }
    if (!detail::gpsins_nav_ok(s) || !w.allFinite() || !f.allFinite()) return Status::NumericalFailure;
    s.omega_b = w;
    s.f_b = f;
    s.t += double(dt);
    s_ = s;
    return Status::Ok;
  }

  /// GPS antenna position: lat, lon (rad), h (m), one-sigma NED (m; NaN entries: parameters).
  /// While Levelled with a heading known, the first fix starts navigation (velocity v0_n, or
  /// zero when non-finite).
  UpdateResult<S, 3> update_gps_position(double lat, double lon, double h, const Vec3<S>& sigma,
                                         const Vec3<S>& v0_n = Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN())) {
    UpdateResult<S, 3> res;
    if (!std::isfinite(lat) || !std::isfinite(lon) || !std::isfinite(h) || std::abs(lat) > 1.5707963267948966) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::GpsPos, res);
    }
    const Vec3<S> sig = gps_pos_sigma(sigma);
    if (!(sig.minCoeff() > S(0)) || !sig.allFinite()) {
      res.status = Status::InvalidArgument;
      return count(GpsInsAid::GpsPos, res);
    }
    if (s_.phase == GpsInsPhase::Aligning) {
      res.status = Status::NotInitialized;
      return res;
    }
    if (s_.phase == GpsInsPhase::Levelled) {
      if (!s_.heading_known) {
        res.status = Status::NotInitialized;
        return res;
      }
      res.status = start(lat, lon, h, sig, v0_n);
      return res;
    }
    const State saved = s_;  // the offset tracking below is undone if the update fails
    const Vec3<S> l_n = quat::to_rotmat(s_.nav.q_nb) * p_.lever_arm_b;
    track_baro_offset(h + double(l_n[2]));  // IMU height from the antenna fix
    const Mat3<S> R = sig.cwiseAbs2().asDiagonal();
    const UpdateResult<S, 3> r = apply(gpsins_aid::GpsPosition<S>{lat, lon, h, sig});
    if (r.status != Status::Ok && r.status != Status::Rejected) restore(saved);
    if (lockout(r.status, s_.gps_pos_reject_run)) {
      // Gate lockout: the IMU position from the fix, its covariance block from the fix's (not
      // done when that position is unusable, e.g. a fix within the pole limit moved past it).
      State s = s_;
      earth::geodetic_add(lat, lon, h, Vec3<double>(-l_n.template cast<double>()));
      s.nav.lat = lat;
      s.nav.lon = lon;
      s.nav.h = h;
      reset_block(s.P, 0, R);
      if (detail::gpsins_nav_ok(s)) {
        s_ = s;
        ++s_.counters.resets[std::size_t(GpsInsAid::GpsPos)];
      }
    }
    return r;
  }

  /// GPS antenna velocity (NED, m/s) with per-axis one-sigma (m/s; NaN: parameters). While
  /// Levelled without a heading, a speed of at least min_speed_for_heading sets the yaw.
  UpdateResult<S, 3> update_gps_velocity(const Vec3<S>& v_n, const Vec3<S>& sigma) {
    UpdateResult<S, 3> res;
    if (!v_n.allFinite()) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::GpsVel, res);
    }
    const Vec3<S> sig = gps_vel_sigma(sigma);
    if (!(sig.minCoeff() > S(0)) || !sig.allFinite()) {
      res.status = Status::InvalidArgument;
      return count(GpsInsAid::GpsVel, res);
    }
    if (s_.phase != GpsInsPhase::Navigating) {
      res.status = Status::NotInitialized;
      if (s_.phase == GpsInsPhase::Levelled && !s_.heading_known && p_.heading_from_gps) {
        const S speed = std::sqrt(v_n[0] * v_n[0] + v_n[1] * v_n[1]);
        if (speed >= p_.min_speed_for_heading) set_yaw(std::atan2(v_n[1], v_n[0]));
      }
      return res;
    }
    const Mat3<S> C = quat::to_rotmat(s_.nav.q_nb);
    const Vec3<S> wl = s_.omega_b.cross(p_.lever_arm_b);
    const Mat3<S> R = sig.cwiseAbs2().asDiagonal();
    const UpdateResult<S, 3> r = apply(gpsins_aid::GpsVelocity<S>{v_n, sig});
    if (lockout(r.status, s_.gps_vel_reject_run)) {
      State s = s_;
      s.nav.v_n = v_n - C * wl;  // gate lockout: the IMU velocity from the fix
      reset_block(s.P, 3, R);
      if (detail::gpsins_nav_ok(s)) {
        s_ = s;
        ++s_.counters.resets[std::size_t(GpsInsAid::GpsVel)];
      }
    }
    return r;
  }

  /// A GPS fix: velocity first (it may give the heading), then position (which may start
  /// navigation), then, when navigation was already running, the velocity update. Non-finite
  /// velocity means "no velocity in this fix".
  GpsResult<S> update_gps(double lat, double lon, double h, const Vec3<S>& v_n, const Vec3<S>& pos_sigma,
                          const Vec3<S>& vel_sigma) {
    GpsResult<S> r;
    const bool have_vel = !std::isnan(v_n[0]) || !std::isnan(v_n[1]) || !std::isnan(v_n[2]);
    if (s_.phase != GpsInsPhase::Navigating) {
      if (have_vel) r.vel = update_gps_velocity(v_n, vel_sigma);
      r.pos = update_gps_position(lat, lon, h, pos_sigma, v_n);
      return r;
    }
    r.pos = update_gps_position(lat, lon, h, pos_sigma);
    if (have_vel) r.vel = update_gps_velocity(v_n, vel_sigma);
    return r;
  }

  /// Altimeter height h_baro (m) at the filter's current time: a height update and, once a
  /// baseline of baro_rate_baseline s is complete, a vertical-velocity update from its derivative.
  BaroResult<S> update_baro(double h_baro) {
    BaroResult<S> r;
    if (!std::isfinite(h_baro)) {
      r.height.status = Status::NonFinite;
      count(GpsInsAid::Baro, r.height);
      return r;
    }
    const State saved = s_;  // restored (but for the counters) when the height update fails
    s_.baro_last = h_baro;
    s_.baro_last_valid = true;
    if (s_.phase != GpsInsPhase::Navigating) {
      r.height.status = Status::NotInitialized;
      return r;
    }
    if (!s_.baro_offset_valid) {
      // First altimeter sample in navigation: tie the altimeter to the INS height.
      s_.baro_offset = s_.nav.h - h_baro;
      s_.baro_offset_valid = true;
      s_.baro_offset_n = 1.0;
    }
    r.height = apply(gpsins_aid::BaroHeight<S>{h_baro});
    if (r.height.status != Status::Ok && r.height.status != Status::Rejected) {
      restore(saved);
      return r;
    }
    if (p_.baro_rate_baseline > S(0)) {
      if (!s_.baro_ref_valid) {
        s_.baro_ref_valid = true;
        s_.baro_ref_h = h_baro;
        s_.baro_ref_t = s_.t;
      } else if (s_.t - s_.baro_ref_t >= double(p_.baro_rate_baseline)) {
        r.vd = apply(gpsins_aid::BaroVerticalVelocity<S>{h_baro, s_.baro_ref_h, s_.t - s_.baro_ref_t});
        if (r.vd.status == Status::Ok || r.vd.status == Status::Rejected) {
          s_.baro_ref_h = h_baro;
          s_.baro_ref_t = s_.t;
        }
      }
    }
    return r;
  }

  /// Compass heading (rad, magnetic; the declination parameter is added). While Levelled it sets
  /// the yaw; afterwards it is a one-row update.
  UpdateResult<S, 1> update_compass(S heading) {
    UpdateResult<S, 1> res;
    if (!std::isfinite(heading)) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::Compass, res);
    }
    if (s_.phase == GpsInsPhase::Aligning) {
      res.status = Status::NotInitialized;
      return res;
    }
    const S yaw_meas = quat::wrap_pi(heading + p_.declination);
    if (s_.phase == GpsInsPhase::Levelled) {
      set_yaw(yaw_meas);
      res.status = Status::NotInitialized;
      return res;
    }
    return apply(gpsins_aid::CompassHeading<S>{yaw_meas});
  }

 private:
  Vec3<S> gps_pos_sigma(const Vec3<S>& s) const {
    return Vec3<S>(std::isnan(s[0]) ? p_.gps_pos_sigma_h : s[0], std::isnan(s[1]) ? p_.gps_pos_sigma_h : s[1],
                   std::isnan(s[2]) ? p_.gps_pos_sigma_v : s[2]);
  }
  Vec3<S> gps_vel_sigma(const Vec3<S>& s) const {
    return Vec3<S>(std::isnan(s[0]) ? p_.gps_vel_sigma : s[0], std::isnan(s[1]) ? p_.gps_vel_sigma : s[1],
                   std::isnan(s[2]) ? p_.gps_vel_sigma : s[2]);
  }

  // The altimeter offset: a running mean of (GPS height of the IMU - latest altimeter height) over
  // the last baro_offset_fixes fixes (the paper zeroes the altimeter on the ground; a fixed offset
  // from one fix would carry that fix's vertical error, several metres, for the whole run).
  void track_baro_offset(double h_imu_gps) {
    if (!(p_.baro_offset_fixes > S(0)) || !s_.baro_last_valid) return;
    const double d = h_imu_gps - s_.baro_last;
    if (!s_.baro_offset_valid) {
      s_.baro_offset = d;
      s_.baro_offset_valid = true;
      s_.baro_offset_n = 1.0;
      return;
    }
    if (s_.baro_offset_n < double(p_.baro_offset_fixes)) s_.baro_offset_n += 1.0;
    s_.baro_offset += (d - s_.baro_offset) / s_.baro_offset_n;
  }

  // Counts consecutive gate rejections in run; true (and run restarted) when a reset is due.
  bool lockout(Status st, std::uint32_t& run) {
    if (st == Status::Ok) {
      run = 0;
      return false;
    }
    if (st != Status::Rejected || !(p_.gps_reset_after > S(0))) return false;
    if (double(++run) < double(p_.gps_reset_after) + 1.0) return false;
    run = 0;
    return true;
  }

  // The 3x3 covariance block at (i, i) set to R, its cross-covariances zeroed.
  static void reset_block(Mat15& P, int i, const Mat3<S>& R) {
    P.template middleRows<3>(i).setZero();
    P.template middleCols<3>(i).setZero();
    P.template block<3, 3>(i, i) = R;
  }

  void set_yaw(S yaw) {
    const Vec3<S> e = quat::to_euler(s_.nav.q_nb);
    s_.nav.q_nb = quat::from_euler(e[0], e[1], yaw);
    s_.heading_known = true;
  }

  /// Put back a saved state, keeping the (diagnostic) counters of what happened since.
  void restore(const State& saved) {
    const GpsInsCounters c = s_.counters;
    s_ = saved;
    s_.counters = c;
  }

  Status start(double lat, double lon, double h, const Vec3<S>& sig, const Vec3<S>& v0_n) {
    State s = s_;
    const Vec3<S> l_n = quat::rotate(s.nav.q_nb, p_.lever_arm_b);
    earth::geodetic_add(lat, lon, h, Vec3<double>(-l_n.template cast<double>()));
    const Quat<S> q = s.nav.q_nb;
    s.nav = StrapdownState<S>();
    s.nav.q_nb = q;
    s.nav.v_n = v0_n.allFinite() ? v0_n : Vec3<S>::Zero();
    s.nav.lat = lat;
    s.nav.lon = lon;
    s.nav.h = h;
    s.P = initial_covariance(sig, p_.init_vel_sigma);
    // A huge sigma (float) or a lever arm that moves the fix past the pole is refused.
    if (!s.P.allFinite() || !detail::gpsins_nav_ok(s)) return Status::NumericalFailure;
    s.phase = GpsInsPhase::Navigating;
    if (s.baro_last_valid) {
      s.baro_offset = h - s.baro_last;
      s.baro_offset_valid = true;
      s.baro_offset_n = 1.0;
    }
    s_ = s;
    return Status::Ok;
  }

  template <int M>
  UpdateResult<S, M> count(GpsInsAid kind, const UpdateResult<S, M>& r) {
    const std::size_t k = std::size_t(kind);
    if (r.status == Status::Ok)
      ++s_.counters.accepted[k];
    else if (r.status == Status::Rejected)
      ++s_.counters.rejected[k];
    else
      ++s_.counters.skipped[k];
    return r;
  }

  /// The one gated correction path of every aid (gpsins_aid pieces): the piece's innovation, H
  /// and R at the current state, the chi-square gate, the Kalman correction (its H nonzero only
  /// in the piece's columns), the injection into the nominal state and the counters.
  template <class Aid> UpdateResult<S, Aid::M> apply(const Aid& aid) {
    constexpr int M = Aid::M;
    AidMeasurement<S, M> m;
    aid.measure(s_, p_, m);
    UpdateResult<S, M> res;
    Mat15 P = s_.P;
    Vec15 dx = Vec15::Zero();
    // kalman_correct refuses an infinite NIS (a finite reading near the float maximum, a height
    // of 1e300 m) with NumericalFailure.
    kalman_correct<S, 15, M>(P, m.H, m.R, m.y, dx, res, Aid::gate(p_));
    inject_and_commit(
        res, P,
        [&] {
          State s = s_;
          detail::gpsins_inject(s, dx);
          return s;
        },
        [](const State& s, const Mat15&) { return detail::gpsins_nav_ok(s); },
        // The floor acts on P alone (the error state has no constraint), so it does not matter
        // that it comes after the injection here.
        [&](State&, Mat15& Pc) {
          floor_covariance<S, 15>(Pc, p_.cov_floor);
          return true;
        },
        [&](State& s, const Mat15& Pc) {
          s.P = Pc;
          s_ = s;
        });
    return count(Aid::kind, res);
  }

  Params p_;
  State s_;
};

/// Batch run over an IMU record and aiding records, each with its own times (s, strictly
/// increasing). IMU sample k holds the mean rate and specific force over (t[k-1], t[k]]; sample 0
/// only fixes the start time. Aiding samples with times in (t[k-1], t[k]] are applied after the
/// time update of sample k (so an aid is used up to one IMU interval late), in the order compass,
/// altimeter, GPS; aids before t[0] are skipped. A GPS row whose position is NaN is skipped as
/// absent; a NaN velocity means "no velocity".
///
/// Inputs (row-major; aiding pointers may be null with count 0):
///   t (n), gyro (n x 3, rad/s), accel (n x 3, m/s^2);
///   gps_t (ng), gps_llh (ng x 3: lat, lon rad, h m; double), gps_vel (ng x 3, m/s or NaN),
///   gps_pos_sigma (ng x 3, m, NaN: parameters), gps_vel_sigma (ng x 3, m/s, NaN: parameters);
///   baro_t (nb), baro_h (nb, m); compass_t (nc), compass_yaw (nc, rad).
/// Outputs (any may be null): llh (n x 3, double), v_n (n x 3), q_nb (n x 4), acc_bias, gyro_bias (n x 3),
///   sigma (n x 15), flags (n); gps_innov (ng x 6: position then velocity, INS minus GPS),
///   gps_nis (ng x 2), gps_status (ng x 2); baro_innov (nb x 2: height, v_D), baro_nis (nb x 2),
///   baro_status (nb x 2); compass_innov (nc), compass_nis (nc), compass_status (nc). Unused
///   innovation entries are NaN. Statuses are quatnav::Status as uint8.
template <class S> struct GpsInsBatchIo {
  const double* t = nullptr;
  const S* gyro = nullptr;
  const S* accel = nullptr;
  std::size_t n = 0;
  const double* gps_t = nullptr;
  const double* gps_llh = nullptr;
  const S* gps_vel = nullptr;
  const S* gps_pos_sigma = nullptr;
  const S* gps_vel_sigma = nullptr;
  std::size_t ng = 0;
  const double* baro_t = nullptr;
  const double* baro_h = nullptr;
  std::size_t nb = 0;
  const double* compass_t = nullptr;
  const S* compass_yaw = nullptr;
  std::size_t nc = 0;
  double* llh = nullptr;
  S* v_n = nullptr;
  S* q_nb = nullptr;
  S* acc_bias = nullptr;
  S* gyro_bias = nullptr;
  S* sigma = nullptr;
  std::uint32_t* flags = nullptr;
  S* gps_innov = nullptr;
  S* gps_nis = nullptr;
  std::uint8_t* gps_status = nullptr;
  S* baro_innov = nullptr;
  S* baro_nis = nullptr;
  std::uint8_t* baro_status = nullptr;
  S* compass_innov = nullptr;
  S* compass_nis = nullptr;
  std::uint8_t* compass_status = nullptr;
};

namespace detail {
template <class S, int M>
std::uint32_t gpsins_aid_flag(const UpdateResult<S, M>& r, std::uint32_t used, std::uint32_t rejected) {
  switch (r.status) {
    case Status::Ok: return used;
    case Status::Rejected: return rejected;
    case Status::NotInitialized: return 0u;
    default: return flags::kAidSkipped;
  }
}
}  // namespace detail

/// Run the filter over the records of `io` (see GpsInsBatchIo). Allocates nothing.
template <class S> void gpsins_batch(GpsInsFilter<S>& f, const GpsInsBatchIo<S>& io) {
  namespace gf = flags;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  std::size_t ig = 0, ib = 0, ic = 0;
  if (io.n == 0) return;
  const double t0 = io.t[0];
  auto skip_before = [&](const double* tt, std::size_t nn, std::size_t& i, std::uint8_t* st, int cols) {
    while (i < nn && tt[i] <= t0) {
      if (st)
        for (int c = 0; c < cols; ++c) st[cols * i + c] = std::uint8_t(Status::NotInitialized);
      ++i;
    }
  };
  // Prefill aiding outputs.
  for (std::size_t j = 0; j < io.ng; ++j) {
    for (int c = 0; c < 6 && io.gps_innov; ++c) io.gps_innov[6 * j + c] = nan;
    for (int c = 0; c < 2 && io.gps_nis; ++c) io.gps_nis[2 * j + c] = nan;
  }
  for (std::size_t j = 0; j < io.nb; ++j) {
    for (int c = 0; c < 2 && io.baro_innov; ++c) io.baro_innov[2 * j + c] = nan;
    for (int c = 0; c < 2 && io.baro_nis; ++c) io.baro_nis[2 * j + c] = nan;
  }
  for (std::size_t j = 0; j < io.nc; ++j) {
    if (io.compass_innov) io.compass_innov[j] = nan;
    if (io.compass_nis) io.compass_nis[j] = nan;
  }
  skip_before(io.gps_t, io.ng, ig, io.gps_status, 2);
  skip_before(io.baro_t, io.nb, ib, io.baro_status, 2);
  skip_before(io.compass_t, io.nc, ic, io.compass_status, 1);

  for (std::size_t k = 0; k < io.n; ++k) {
    std::uint32_t fl = 0;
    const bool was_nav = f.navigating();
    if (k > 0) {
      const S dt = S(io.t[k] - io.t[k - 1]);
      const Status s = f.predict(Vec3<S>(Eigen::Map<const Vec3<S>>(io.gyro + 3 * k)),
                                 Vec3<S>(Eigen::Map<const Vec3<S>>(io.accel + 3 * k)), dt);
      if (s != Status::Ok) fl |= gf::kPredictSkipped | (s == Status::Saturated ? gf::kSaturated : 0u);
      const double tk = io.t[k];
      while (ic < io.nc && io.compass_t[ic] <= tk) {
        const UpdateResult<S, 1> r = f.update_compass(io.compass_yaw[ic]);
        if (io.compass_innov && r.status != Status::NotInitialized) io.compass_innov[ic] = r.innovation[0];
        if (io.compass_nis && (r.status == Status::Ok || r.status == Status::Rejected)) io.compass_nis[ic] = r.nis;
        if (io.compass_status) io.compass_status[ic] = std::uint8_t(r.status);
        fl |= detail::gpsins_aid_flag(r, gf::kHeadingUsed, gf::kHeadingRejected);
        ++ic;
      }
      while (ib < io.nb && io.baro_t[ib] <= tk) {
        const BaroResult<S> r = f.update_baro(io.baro_h[ib]);
        const UpdateResult<S, 1>* rr[2] = {&r.height, &r.vd};
        for (int c = 0; c < 2; ++c) {
          const bool done = rr[c]->status == Status::Ok || rr[c]->status == Status::Rejected;
          if (io.baro_innov && done) io.baro_innov[2 * ib + c] = rr[c]->innovation[0];
          if (io.baro_nis && done) io.baro_nis[2 * ib + c] = rr[c]->nis;
          if (io.baro_status) io.baro_status[2 * ib + c] = std::uint8_t(rr[c]->status);
        }
        fl |= detail::gpsins_aid_flag(r.height, gf::kBaroUsed, gf::kBaroRejected);
        fl |= detail::gpsins_aid_flag(r.vd, gf::kBaroVdUsed, gf::kBaroVdRejected);
        ++ib;
      }
      while (ig < io.ng && io.gps_t[ig] <= tk) {
        const double* llh = io.gps_llh + 3 * ig;
        GpsResult<S> r;
        const auto& resets = f.state().counters.resets;
        const std::uint32_t resets0 = resets[0] + resets[1];
        r.pos.status = Status::NonFinite;
        if (!(std::isnan(llh[0]) && std::isnan(llh[1]) && std::isnan(llh[2]))) {
          const Vec3<S> vel = io.gps_vel ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_vel + 3 * ig))
                                         : Vec3<S>::Constant(nan);
          const Vec3<S> ps = io.gps_pos_sigma ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_pos_sigma + 3 * ig))
                                              : Vec3<S>::Constant(nan);
          const Vec3<S> vs = io.gps_vel_sigma ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_vel_sigma + 3 * ig))
                                              : Vec3<S>::Constant(nan);
          r = f.update_gps(llh[0], llh[1], llh[2], vel, ps, vs);
          fl |= detail::gpsins_aid_flag(r.pos, gf::kGpsPosUsed, gf::kGpsPosRejected);
          fl |= detail::gpsins_aid_flag(r.vel, gf::kGpsVelUsed, gf::kGpsVelRejected);
          if (resets[0] + resets[1] != resets0) fl |= gf::kGpsReset;
        }
        const UpdateResult<S, 3>* rr[2] = {&r.pos, &r.vel};
        for (int c = 0; c < 2; ++c) {
          const bool done = rr[c]->status == Status::Ok || rr[c]->status == Status::Rejected;
          if (io.gps_innov && done)
            for (int j = 0; j < 3; ++j) io.gps_innov[6 * ig + 3 * c + j] = rr[c]->innovation[j];
          if (io.gps_nis && done) io.gps_nis[2 * ig + c] = rr[c]->nis;
          if (io.gps_status) io.gps_status[2 * ig + c] = std::uint8_t(rr[c]->status);
        }
        ++ig;
      }
    }
    switch (f.phase()) {
      case GpsInsPhase::Aligning: fl |= gf::kAligning; break;
      case GpsInsPhase::Levelled: fl |= gf::kLevelled; break;
      case GpsInsPhase::Navigating: fl |= gf::kNavigating; break;
    }
    if (!was_nav && f.navigating()) fl |= gf::kInitialized;
    const bool nav = f.navigating();
    if (io.llh) {
      const Vec3<double> l = f.llh();
      for (int c = 0; c < 3; ++c) io.llh[3 * k + c] = nav ? l[c] : std::numeric_limits<double>::quiet_NaN();
    }
    if (io.v_n) Eigen::Map<Vec3<S>>(io.v_n + 3 * k) = nav ? f.v_n() : Vec3<S>::Constant(nan);
    if (io.q_nb)
      Eigen::Map<Vec4<S>>(io.q_nb + 4 * k) = f.levelled() ? f.q_nb() : Vec4<S>(Vec4<S>::Constant(nan));
    if (io.acc_bias) Eigen::Map<Vec3<S>>(io.acc_bias + 3 * k) = f.acc_bias();
    if (io.gyro_bias) Eigen::Map<Vec3<S>>(io.gyro_bias + 3 * k) = f.gyro_bias();
    if (io.sigma)
      Eigen::Map<Vec<S, 15>>(io.sigma + 15 * k) =
          nav ? Vec<S, 15>(f.covariance().diagonal().cwiseMax(S(0)).cwiseSqrt()) : Vec<S, 15>::Constant(nan);
    if (io.flags) io.flags[k] = fl;
  }
  // Aids after the last IMU sample are not used.
  for (; ig < io.ng; ++ig)
    if (io.gps_status) io.gps_status[2 * ig] = io.gps_status[2 * ig + 1] = std::uint8_t(Status::NotInitialized);
  for (; ib < io.nb; ++ib)
    if (io.baro_status) io.baro_status[2 * ib] = io.baro_status[2 * ib + 1] = std::uint8_t(Status::NotInitialized);
  for (; ic < io.nc; ++ic)
    if (io.compass_status) io.compass_status[ic] = std::uint8_t(Status::NotInitialized);
}

}  // namespace quatnav
