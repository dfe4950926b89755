// quatnav: loosely coupled GPS/INS feedback Kalman filter with altimeter and compass (paper 004,
// Lee & Jeong, "Design and Implementation of UAV Navigation System Using Kalman Filter").
//
// Nominal state: the strapdown mechanization of strapdown.hpp (quaternion attitude q_nb, NED
// velocity with Coriolis and transport terms, geodetic position kept in double), fed with the
// IMU corrected by the current bias estimates. Paper 004 integrates Euler angles (eq. 1); the
// quaternion is used instead, so there is no gimbal lock; Euler angles are an output only.
//
// Error state (16), eq. (3)-(7) and the altimeter offset, every error defined as estimate minus
// truth (gps_ins/model.hpp):
//   dx = [dp_n (N, E, D position error, m), dv_n (m/s), psi (rad), db_a (m/s^2), db_g (rad/s),
//         d_baro_offset (m)]
// The attitude error is the phi-angle (nav-frame small rotation): C_nb_est = (I + [psi x]) C_nb.
// Paper 004's state list (eq. 5) repeats V_E and psi_N: the intended states are the first 15.
// The 16th, the altimeter's offset (its reading minus the ellipsoidal height), is not in the
// paper, which zeroes the altimeter on the ground: a random walk (baro_offset_noise),
// initialized from the INS height by the first altimeter sample in navigation.
//
// Scale factors (optional, GpsInsFilter<S, true>: 22 error states): [ds_a, ds_g] after the 16,
// the sensor reading (1 + s) x + b per body axis, the inputs corrected as (m - b) / (1 + s); their
// columns of F are -C D diag(f) on dv and -C D_g diag(w) on psi, and the bias columns become
// -C D, -C D_g (D = diag(1 / (1 + s)); detail::gpsins_F_scale in gps_ins/model.hpp). Random walks.
// No aid's H has scale-factor columns: the aids that use the corrected IMU (the zero-rate update,
// the lever-arm and age terms of the GNSS aids) take it as given, an error of order s times terms
// that are themselves small (the Earth rate at rest, a lever arm's rotation).
//
// Continuous error dynamics (detail::gpsins_F; checked against finite differences of the
// mechanization in tests/python/test_gpsins_jacobian.py; radii taken constant in latitude):
//   dp' = F_pp dp + dv                                           (eq. 9: in metres, the exact
//         linearization of lat' = v_N/(R_M+h), lon' = v_E/((R_N+h) cos L), h' = -v_D)
//   dv' = -[f_n x] psi - C_nb db_a - [(2 w_ie + w_en) x] dv + [v x](2 dw_ie + dw_en) + dg   (eq. 8)
//   psi' = -[w_in x] psi - C_nb db_g - dw_in                     (eq. 10)
//   db' = -db / tau (first-order Gauss-Markov; tau <= 0: random walk);  d_baro_offset' = 0 (+ noise)
// Paper slips fixed here: eq. (10) writes only w_ie x Psi; the nav frame turns at
// w_in = w_ie + w_en, and the errors of w_ie (latitude) and w_en (velocity, position) drive psi.
// Eq. (8)'s "f^n Psi" is -[f_n x] psi with the sign of this error definition. Eq. (2)'s V^n lists
// V_E twice (it is [V_N V_E V_D]), its R_m lost the power 3/2 (R_M = R0 (1-e^2) /
// (1 - e^2 sin^2 L)^{3/2}), w_ie lost cos L ([W cos L, 0, -W sin L]) and g^n = [0 0 -g_e] has the
// wrong sign for NED (g_n = [0, 0, +g]): earth.hpp has the corrected forms.
//
// Discretization over one IMU interval dt, with F evaluated before the step:
//   Phi = I + F dt + (F dt)^2 / 2,  Qd = (Phi Qc Phi^T + Qc) dt / 2  (trapezoidal),
//   P <- Phi P Phi^T + Qd,
// evaluated by blocks, with only the nonzero blocks of F and Phi, as Phi (P + Qc dt / 2) Phi^T +
// Qc dt / 2 (detail::gpsins_Phi_blocks, detail::gpsins_propagate in gps_ins/model.hpp).
// Qc: accelerometer white noise on dv, gyro white noise on psi, bias driving noise on db (all
// scaled by the adaptation's q_scale, see below), the offset's random walk.
//
// Measurements (eq. 11: z = INS minus aid = H dx + noise; the innovation reported is INS minus
// aid), each at its own rate, each one piece of one measurement shape (gps_ins/aids.hpp, where
// every H and R is written out): GPS antenna position and velocity (lever arm; taken back by the
// fix's age on the IMU clock), altimeter height (h_INS + offset - h_baro) and vertical velocity
// (paper 004: the derivative of the altimeter over baro_rate_baseline), compass heading.
// The innovation covariance holds what the model leaves out: a floor on the GNSS one-sigma, the
// uncertainty of the GNSS time on the IMU clock and of the lever arm.
//
// One gated correction path (GpsInsFilter::apply) for every aid: the chi-square gate of the aid
// (0 switches it off), then for the GNSS aids:
//   outlier isolation: a fix that fails its gate after one that passed is rejected;
//   inflation: a fix that fails its gate after inflate_after failures in a row says that the
//     INS, not the fix, is off (seen on a real walk with cm-level RTK fixes: with a gate alone,
//     after one rejection no fix was ever accepted again and the position drifted by hundreds
//     of metres). The position, velocity and attitude block of P is multiplied by the smallest
//     a >= 1 that brings the fix's NIS down to its number of rows and the fix is applied
//     (decision Inflated); when even inflate_max is not enough, the position (velocity) is reset
//     to the fix, its covariance block to the fix's, its cross-covariances zeroed (Reset; the
//     update reports Rejected);
//   adaptation: the process noise (IMU and bias densities) is scaled by q_scale, whose log moves
//     by adapt_gain (ln r - ln 3) after every applied GNSS update whose NIS per row r exceeds 3,
//     by adapt_gain (ln r + ln 3) when r is below 1/3, within [1, adapt_q_max]: a consistent
//     filter stays at 1, a process noise set too small recovers instead of locking out.
// Every decision is reported per sample (GpsInsUpdate: status, innovation, NIS, decision,
// inflation) and counted (state().counters).
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
// update) leaves the state bit-for-bit untouched, with one documented exception: an aid that is
// used for initialization (a compass heading or a GPS course before navigation, an altimeter
// height kept for the offset) returns NotInitialized after being recorded. A Rejected update
// changes only the counters and the rejection run, except the reset described above.
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
#include "gps_ins/alignment.hpp"
#include "gps_ins/model.hpp"
#include "gps_ins/params.hpp"
#include "strapdown.hpp"

namespace quatnav {

/// Outcome of an altimeter sample: its height update and (when a baseline was complete) its
/// vertical-velocity update (status NotInitialized when none was made).
template <class S> struct BaroResult {
  GpsInsUpdate<S, 1> height;
  GpsInsUpdate<S, 1> vd;
};

/// Outcome of a GPS fix: position and velocity updates (velocity NotInitialized when absent).
template <class S> struct GpsResult {
  GpsInsUpdate<S, 3> pos;
  GpsInsUpdate<S, 3> vel;
};

/// Outcome of the pseudo-measurements after a time update (each NotInitialized when not made):
/// zero velocity and zero angular rate at rest, the non-holonomic constraint while moving.
template <class S> struct ConstraintResult {
  GpsInsUpdate<S, 3> zupt;
  GpsInsUpdate<S, 3> zaru;
  GpsInsUpdate<S, 2> nhc;
};

/// The 16-state feedback GPS/INS filter.
template <class S_, bool SF_ = false> class GpsInsFilter {
 public:
  using Scalar = S_;
  using S = S_;
  using Params = GpsInsParams<S>;
  using State = GpsInsState<S, SF_>;
  /// With the gyro and accelerometer scale-factor states (22 error states instead of 16).
  static constexpr bool kScaleFactors = SF_;
  static constexpr int kStates = gpsins::kStates<SF_>;
  using Mat16 = Mat<S, kStates, kStates>;
  using Vec16 = Vec<S, kStates>;

  explicit GpsInsFilter(const Params& params = Params()) : params_(params) {}

  const Params& params() const { return params_; }
  /// Replace the parameters (the state is kept).
  void set_params(const Params& params) { params_ = params; }
  const State& state() const { return st_; }
  /// Restore a state; InvalidArgument (nothing changed) when it is not finite.
  Status set_state(const State& s) {
    // As the filter keeps them: everything finite, |q| = 1, the latitude off the poles
    // (detail::gpsins_nav_ok), P exactly symmetric with a non-negative diagonal.
    if (!detail::gpsins_nav_ok(s) || !std::isfinite(s.t) || !s.omega_b.allFinite() || !s.f_b.allFinite() ||
        !s.align_sum.allFinite() || !std::isfinite(s.align_time) || !std::isfinite(s.baro_last) ||
        !std::isfinite(s.baro_ref_h) || !std::isfinite(s.baro_ref_t) || !(s.q_scale >= S(1)) ||
        !std::isfinite(s.q_scale) || !detail::acceptable_covariance<S, kStates>(s.P) || int(s.phase) > 2 ||
        !std::isfinite(s.dt_last) || !s.rest_gyr_lp.allFinite() || !s.rest_acc_lp.allFinite() ||
        !std::isfinite(s.rest_t) || !std::isfinite(s.pseudo_t) || !s.mot_q.allFinite() || !s.mot_dv.allFinite() ||
        !std::isfinite(s.mot_T) || !s.mot_v0.allFinite() || !std::isfinite(s.mot_lat) || !std::isfinite(s.mot_lon) ||
        !std::isfinite(s.mot_h) || !s.init_v.allFinite() || !std::isfinite(s.mag_ref_norm) ||
        !std::isfinite(s.mag_ref_dip) || !std::isfinite(s.gnss_speed) || !std::isfinite(s.gnss_speed_t) ||
        int(s.align_method) > 4 || int(s.heading_source) > 5)
      return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }
  /// Back to the start of alignment (parameters kept): the filter aligns again from the next
  /// IMU samples.
  void clear() { st_ = State(); }

  GpsInsPhase phase() const { return st_.phase; }
  bool navigating() const { return st_.phase == GpsInsPhase::Navigating; }
  bool levelled() const { return st_.phase != GpsInsPhase::Aligning; }
  const Quat<S>& q_nb() const { return st_.nav.q_nb; }
  Vec3<S> euler() const { return quat::to_euler(st_.nav.q_nb); }
  const Vec3<S>& v_n() const { return st_.nav.v_n; }
  Vec3<double> llh() const { return Vec3<double>(st_.nav.lat, st_.nav.lon, st_.nav.h); }
  const Vec3<S>& acc_bias() const { return st_.acc_bias; }
  const Vec3<S>& gyro_bias() const { return st_.gyro_bias; }
  /// The scale-factor estimates (zero without the scale-factor states).
  const Vec3<S>& acc_scale() const { return st_.acc_scale; }
  const Vec3<S>& gyro_scale() const { return st_.gyro_scale; }
  double baro_offset() const { return st_.baro_offset; }
  /// At rest: the IMU has been still for rest_time (gps_ins/alignment.hpp).
  bool at_rest() const { return params_.rest_time > S(0) && st_.rest_t >= double(params_.rest_time); }
  GpsInsAlignment align_method() const { return st_.align_method; }
  GpsInsHeading heading_source() const { return st_.heading_source; }
  S q_scale() const { return st_.q_scale; }
  const Mat16& covariance() const { return st_.P; }
  double time() const { return st_.t; }

  /// Start navigation from a given state (skipping alignment): attitude, velocity, position,
  /// biases and the covariance; as reset() of every filter (initialize() starts a filter from
  /// sensor readings, reset() from a state). InvalidArgument when anything is non-finite or P is
  /// not symmetric. The altimeter offset is initialized by the next altimeter sample; the
  /// scale-factor estimates start at zero (set_state() restores them).
  Status reset(const Quat<S>& q_nb, const Vec3<S>& v_n, double lat, double lon, double h,
               const Vec3<S>& acc_bias, const Vec3<S>& gyro_bias, const Mat16& P) {
    if (!q_nb.allFinite() || !v_n.allFinite() || !std::isfinite(lat) || !std::isfinite(lon) || !std::isfinite(h) ||
        !acc_bias.allFinite() || !gyro_bias.allFinite() || !P.allFinite() || !(q_nb.norm() > S(0.5)))
      return Status::InvalidArgument;
    if (!((P - P.transpose()).cwiseAbs().maxCoeff() <= S(1e-6) * (S(1) + P.cwiseAbs().maxCoeff())))
      return Status::InvalidArgument;
    Mat16 Ps = P;
    symmetrize(Ps);
    // A P near the float maximum overflows when symmetrized.
    if (!Ps.allFinite() || !(Ps.diagonal().array() >= S(0)).all()) return Status::InvalidArgument;
    floor_covariance<S, kStates>(Ps, params_.cov_floor);
    State s = st_;
    s.nav = StrapdownState<S>();
    s.nav.q_nb = q_nb / q_nb.norm();
    s.nav.v_n = v_n;
    s.nav.lat = lat;
    s.nav.lon = lon;
    s.nav.h = h;
    s.acc_bias = acc_bias;
    s.gyro_bias = gyro_bias;
    s.acc_scale.setZero();
    s.gyro_scale.setZero();
    s.P = Ps;
    s.phase = GpsInsPhase::Navigating;
    s.heading_known = true;
    s.baro_offset_valid = false;
    s.align_method = GpsInsAlignment::Given;
    s.heading_source = GpsInsHeading::Given;
    s.level_t = s.nav_start_t = s.t;
    // A quaternion whose norm overflows normalizes to zero; a latitude at a pole: refused.
    if (!detail::gpsins_nav_ok(s)) return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// A given initial attitude (and, with v_valid, velocity) and biases, for a start without the
  /// alignment (a vehicle already moving, an attitude known from elsewhere): the filter waits
  /// levelled with its heading for the first GNSS fix, which gives the position (and the
  /// velocity when not given here). The initial sigmas are the parameters'. Before navigation
  /// only; InvalidArgument when anything is non-finite, NotInitialized when navigating.
  Status set_initial(const Quat<S>& q_nb, const Vec3<S>& v_n, bool v_valid, const Vec3<S>& acc_bias,
                     const Vec3<S>& gyro_bias) {
    if (st_.phase == GpsInsPhase::Navigating) return Status::NotInitialized;
    if (!q_nb.allFinite() || !(q_nb.norm() > S(0.5)) || (v_valid && !v_n.allFinite()) || !acc_bias.allFinite() ||
        !gyro_bias.allFinite())
      return Status::InvalidArgument;
    State s = st_;
    s.nav.q_nb = q_nb / q_nb.norm();
    s.acc_bias = acc_bias;
    s.gyro_bias = gyro_bias;
    s.init_v_valid = v_valid;
    s.init_v = v_valid ? v_n : Vec3<S>::Zero();
    s.phase = GpsInsPhase::Levelled;
    s.heading_known = true;
    s.align_method = GpsInsAlignment::Given;
    s.heading_source = GpsInsHeading::Given;
    s.level_t = s.t;
    if (!detail::gpsins_nav_ok(s)) return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// The covariance that initialization uses for a fix with NED position sigmas pos_sigma (m)
  /// (the altimeter offset's block stays zero until its first sample).
  Mat16 initial_covariance(const Vec3<S>& pos_sigma, S vel_sigma) const {
    return initial_sigmas(pos_sigma, vel_sigma, params_.init_level_sigma, params_.init_yaw_sigma)
        .cwiseAbs2()
        .asDiagonal();
  }

  /// Time update over one IMU interval: mean rate omega_ib_b (rad/s) and specific force f_ib_b
  /// (m/s^2) over dt (s), in the IMU's axes (rotated into the body by imu_rotation). The rest
  /// detector runs in every phase. Aligning: averages f while still (static levelling) and
  /// integrates the motion window (alignment in motion); Levelled: integrates the attitude;
  /// Navigating: strapdown (eq. 1-2) with bias-corrected inputs and covariance propagation.
  Status predict(const Vec3<S>& omega_ib_b, const Vec3<S>& f_ib_b, S dt) {
    if (!(std::isfinite(dt) && dt > S(0) && dt <= params_.max_dt)) return Status::InvalidDt;
    if (!omega_ib_b.allFinite() || !f_ib_b.allFinite()) return Status::NonFinite;
    if (detail::saturated(omega_ib_b, params_.gyro_range) || detail::saturated(f_ib_b, params_.acc_range))
      return Status::Saturated;
    State s = st_;
    const Vec3<S> w_m = imu_to_body(omega_ib_b);
    const Vec3<S> f_m = imu_to_body(f_ib_b);
    const Vec3<S> w = detail::gpsins_correct<S, SF_>(w_m, s.gyro_bias, s.gyro_scale);
    const Vec3<S> f = detail::gpsins_correct<S, SF_>(f_m, s.acc_bias, s.acc_scale);
    const S g = s.phase == GpsInsPhase::Navigating ? S(earth::gravity<double>(s.nav.lat, s.nav.h))
                                                   : S(earth::kStandardGravity);
    bool slow;
    if (s.phase == GpsInsPhase::Navigating) {
      const S sv = std::sqrt(s.P(gpsins::kVel, gpsins::kVel) + s.P(gpsins::kVel + 1, gpsins::kVel + 1) +
                             s.P(gpsins::kVel + 2, gpsins::kVel + 2));
      // The INS speed, allowed up to 3 sigma more but never more than rest_speed more: an
      // uncertain velocity (a GNSS outage) must not make a vehicle cruising with a quiet IMU look
      // stopped (a false zero-velocity update pins the position where the outage began).
      slow = s.nav.v_n.norm() < params_.rest_speed + std::min(S(3) * sv, params_.rest_speed);
    } else {
      slow = !(s.gnss_speed >= S(0) && s.t - s.gnss_speed_t < 2.0 && s.gnss_speed > params_.rest_speed);
    }
    const bool still = detail::gpsins_rest_step(s, params_, w, f, dt, g, slow);
    if (s.phase != GpsInsPhase::Navigating) detail::gpsins_window_step(s, w, f, dt);
    if (s.phase == GpsInsPhase::Aligning) {
      if (!still) {  // motion: the static levelling starts again
        s.align_sum.setZero();
        s.align_time = 0.0;
      }
      s.align_sum += f_m.template cast<double>() * double(dt);
      s.align_time += double(dt);
      if (!s.align_sum.allFinite()) return Status::NumericalFailure;
      if (s.align_time >= double(params_.align_time)) {
        const Vec3<S> fm = (s.align_sum / s.align_time).template cast<S>();
        const S fn = fm.norm();
        if (!(fn > S(1))) {
          // No gravity in the mean (free fall or a broken sensor): start the average again.
          s.align_sum.setZero();
          s.align_time = 0.0;
          s.t += double(dt);
          st_ = s;
          return Status::Ok;
        }
        // Level: the specific force at rest is -g in NED, f_b = C_nb^T [0, 0, -g].
        S roll, pitch;
        detail::level_from_acc(fm, roll, pitch);
        s.nav.q_nb = quat::from_euler(roll, pitch, S(0));
        s.phase = GpsInsPhase::Levelled;
        s.align_method = GpsInsAlignment::Static;
        s.level_t = s.t + double(dt);
      }
    } else if (s.phase == GpsInsPhase::Levelled) {
      Quat<S> q = quat::mul(s.nav.q_nb, quat::from_rotvec(Vec3<S>(w * dt)));
      s.nav.q_nb = q / q.norm();
    } else {
      StrapdownParams sp;
      sp.earth_rotation = params_.earth_rotation;
      const detail::GpsInsPhi<S, SF_> Phi = detail::gpsins_Phi_state<S, SF_>(s, f, w, dt, params_);
      const Status st = strapdown_step(s.nav, w, f, dt, sp);
      if (st != Status::Ok) return st;
      Mat16 P = detail::gpsins_propagate<S, SF_>(Phi, s.P, detail::gpsins_Qc_diag<S, SF_>(params_, s.q_scale), dt);
      symmetrize(P);
      if (params_.acc_bias_tau > S(0)) s.acc_bias *= std::exp(-dt / params_.acc_bias_tau);
      if (params_.gyro_bias_tau > S(0)) s.gyro_bias *= std::exp(-dt / params_.gyro_bias_tau);
      if (!P.allFinite()) return Status::NumericalFailure;
      floor_covariance<S, kStates>(P, params_.cov_floor);
      s.P = P;
    }
    if (s.phase == GpsInsPhase::Navigating) detail::gpsins_nhc_evidence(s, params_, dt);
    if (!detail::gpsins_nav_ok(s) || !w.allFinite() || !f.allFinite() || !s.rest_acc_lp.allFinite() ||
        !s.mot_dv.allFinite())
      return Status::NumericalFailure;
    s.omega_b = w;
    s.f_b = f;
    s.dt_last = double(dt);
    s.t += double(dt);
    st_ = s;
    return Status::Ok;
  }

  /// The pseudo-measurements after a time update, at most every pseudo_interval seconds: at rest
  /// (and zupt) zero velocity and zero angular rate; while moving (and nhc) the non-holonomic
  /// constraint. Navigating only.
  ConstraintResult<S> update_constraints() {
    ConstraintResult<S> r;
    if (st_.phase != GpsInsPhase::Navigating || st_.t - st_.pseudo_t < double(params_.pseudo_interval) * (1.0 - 1e-9))
      return r;
    const bool rest = at_rest();
    if (rest && params_.zupt) {
      r.zupt = apply(gpsins_aid::ZeroVelocity<S>{});
      r.zaru = apply(gpsins_aid::ZeroRate<S>{});
      st_.pseudo_t = st_.t;
    } else if (!rest && nhc_active()) {
      // Forced (nhc): nhc_sigma; by evidence: no less than the motion showed.
      const S r0 = params_.nhc_sigma * params_.nhc_sigma;
      r.nhc = apply(gpsins_aid::NonHolonomic<S>{params_.nhc ? r0 : std::max(r0, st_.nhc_ms)});
      st_.pseudo_t = st_.t;
    }
    return r;
  }

  /// The non-holonomic constraint applies while moving: forced (nhc), or by the evidence of a
  /// wheeled vehicle (nhc_auto: detail::gpsins_nhc_evidence in gps_ins/alignment.hpp).
  bool nhc_active() const { return params_.nhc || (params_.nhc_auto && st_.nhc_t >= double(params_.nhc_auto_time)); }

  /// Odometer forward speed (m/s, along the body x axis). Navigating only.
  GpsInsUpdate<S, 1> update_odometer(S speed) {
    GpsInsUpdate<S, 1> res;
    if (!std::isfinite(speed)) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::Odometer, res);
    }
    if (st_.phase != GpsInsPhase::Navigating) {
      res.status = Status::NotInitialized;
      return res;
    }
    return apply(gpsins_aid::OdometerSpeed<S>{speed});
  }

  /// Raw 3-axis magnetometer (IMU axes, rotated by imu_rotation; any unit). Its heading is
  /// tilt-compensated with the filter's attitude (gpsins_aid::MagHeading). Disturbance tests: the
  /// norm and the dip against a reference averaged over the first mag_ref_samples samples (a
  /// sample failing one is Rejected, its NIS NaN). While Levelled without a heading it sets the
  /// yaw; then a one-row update.
  GpsInsUpdate<S, 1> update_mag(const Vec3<S>& m_imu) {
    GpsInsUpdate<S, 1> res;
    if (!m_imu.allFinite()) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::Mag, res);
    }
    const bool rotated = !(params_.imu_rotation.array() == Mat3<S>::Identity().array()).all();
    const Vec3<S> m_b = rotated ? Vec3<S>(params_.imu_rotation * m_imu) : m_imu;
    const S norm = m_b.norm();
    if (!(norm > S(0)) || !std::isfinite(norm)) {
      res.status = Status::ZeroNorm;
      return count(GpsInsAid::Mag, res);
    }
    if (st_.phase == GpsInsPhase::Aligning) {
      res.status = Status::NotInitialized;
      return res;
    }
    const Vec3<S> m_n = quat::rotate(st_.nav.q_nb, m_b);
    const S dip = std::atan2(m_n[2], std::sqrt(m_n[0] * m_n[0] + m_n[1] * m_n[1]));
    if (st_.mag_ref_n < std::uint32_t(params_.mag_ref_samples > 0 ? params_.mag_ref_samples : 0)) {
      // Learning the reference: every sample counts (no test yet).
      const S n1 = S(st_.mag_ref_n + 1);
      st_.mag_ref_norm += (norm - st_.mag_ref_norm) / n1;
      st_.mag_ref_dip += (dip - st_.mag_ref_dip) / n1;
      ++st_.mag_ref_n;
    } else if ((params_.mag_norm_tol > S(0) && std::abs(norm / st_.mag_ref_norm - S(1)) > params_.mag_norm_tol) ||
               (params_.mag_dip_tol > S(0) && std::abs(dip - st_.mag_ref_dip) > params_.mag_dip_tol)) {
      res.status = Status::Rejected;
      res.innovation[0] = quat::wrap_pi(std::atan2(m_n[1], m_n[0]) - params_.declination);
      res.nis = std::numeric_limits<S>::quiet_NaN();
      return count(GpsInsAid::Mag, res);
    }
    if (st_.phase == GpsInsPhase::Levelled) {
      if (!st_.heading_known) {
        set_yaw(quat::wrap_pi(quat::to_euler(st_.nav.q_nb)[2] - (std::atan2(m_n[1], m_n[0]) - params_.declination)));
        st_.heading_source = GpsInsHeading::Magnetometer;
        res.decision = GpsInsDecision::Aligned;
      }
      res.status = Status::NotInitialized;
      return res;
    }
    return apply(gpsins_aid::MagHeading<S>{m_b});
  }

  /// GPS antenna position: lat, lon (rad), h (m), one-sigma NED (m; NaN entries: parameters),
  /// valid `age` seconds before the filter's time (0: now). While Levelled with a heading known,
  /// the first fix starts navigation (at zero velocity; update_gps starts with the fix's velocity).
  GpsInsUpdate<S, 3> update_gps_position(double lat, double lon, double h, const Vec3<S>& sigma, S age = S(0)) {
    const Vec3<S> nan3 = Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN());
    return position_update(lat, lon, h, sigma, age, nan3, nan3);
  }

  /// GPS antenna velocity (NED, m/s) with per-axis one-sigma (m/s; NaN: parameters), valid `age`
  /// seconds before the filter's time. While Levelled without a heading, a speed of at least
  /// min_speed_for_heading sets the yaw.
  GpsInsUpdate<S, 3> update_gps_velocity(const Vec3<S>& v_n, const Vec3<S>& sigma, S age = S(0)) {
    GpsInsUpdate<S, 3> res;
    if (!v_n.allFinite() || !std::isfinite(age)) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::GpsVel, res);
    }
    const Vec3<S> sig = gps_vel_sigma(sigma);
    if (!(sig.minCoeff() > S(0)) || !sig.allFinite()) {
      res.status = Status::InvalidArgument;
      return count(GpsInsAid::GpsVel, res);
    }
    if (st_.phase != GpsInsPhase::Navigating) {
      res.status = Status::NotInitialized;
      const S speed = std::sqrt(v_n[0] * v_n[0] + v_n[1] * v_n[1]);
      // The speed less three of its sigmas: the noise of a fix at rest does not make it move.
      const S moving = speed - S(3) * std::sqrt(sig[0] * sig[0] + sig[1] * sig[1]);
      st_.gnss_speed = moving > S(0) ? moving : S(0);
      st_.gnss_speed_t = st_.t;
      if (st_.phase == GpsInsPhase::Levelled && !st_.heading_known && params_.heading_from_gps) {
        if (speed >= params_.min_speed_for_heading) {
          set_yaw(std::atan2(v_n[1], v_n[0]));
          st_.heading_source = GpsInsHeading::GnssVelocity;
          res.decision = GpsInsDecision::Aligned;
        }
      }
      return res;
    }
    return apply(gpsins_aid::GpsVelocity<S>{v_n, sig, age});
  }

  /// A GPS fix: velocity first (it may give the heading), then position (which may start
  /// navigation), then, when navigation was already running, the velocity update. Non-finite
  /// velocity means "no velocity in this fix". `age`: as update_gps_position.
  GpsResult<S> update_gps(double lat, double lon, double h, const Vec3<S>& v_n, const Vec3<S>& pos_sigma,
                          const Vec3<S>& vel_sigma, S age = S(0)) {
    GpsResult<S> r;
    const bool have_vel = !std::isnan(v_n[0]) || !std::isnan(v_n[1]) || !std::isnan(v_n[2]);
    if (st_.phase != GpsInsPhase::Navigating) {
      if (have_vel) r.vel = update_gps_velocity(v_n, vel_sigma, age);
      r.pos = position_update(lat, lon, h, pos_sigma, age, v_n, vel_sigma);
      return r;
    }
    r.pos = position_update(lat, lon, h, pos_sigma, age, v_n, vel_sigma);
    if (have_vel) r.vel = update_gps_velocity(v_n, vel_sigma, age);
    return r;
  }

  /// Altimeter height h_baro (m) at the filter's current time: a height update (the altimeter
  /// reads the ellipsoidal height plus its offset, a state initialized from the INS height by the
  /// first sample in navigation) and, once a baseline of baro_rate_baseline s is complete, a
  /// vertical-velocity update from its derivative.
  BaroResult<S> update_baro(double h_baro) {
    BaroResult<S> r;
    if (!std::isfinite(h_baro)) {
      r.height.status = Status::NonFinite;
      count(GpsInsAid::Baro, r.height);
      return r;
    }
    const State saved = st_;  // restored (but for the counters) when the height update fails
    st_.baro_last = h_baro;
    st_.baro_last_valid = true;
    if (st_.phase != GpsInsPhase::Navigating) {
      r.height.status = Status::NotInitialized;
      return r;
    }
    if (!st_.baro_offset_valid) {
      // First altimeter sample in navigation: the offset state from the INS height (the sample is
      // used: Ok, decision Aligned, innovation and NIS zero).
      init_baro_offset(st_, h_baro);
      r.height.status = Status::Ok;
      r.height.decision = GpsInsDecision::Aligned;
    } else {
      r.height = apply(gpsins_aid::BaroHeight<S>{h_baro});
      if (r.height.status != Status::Ok && r.height.status != Status::Rejected) {
        restore(saved);
        return r;
      }
    }
    if (params_.baro_rate_baseline > S(0)) {
      if (!st_.baro_ref_valid) {
        st_.baro_ref_valid = true;
        st_.baro_ref_h = h_baro;
        st_.baro_ref_t = st_.t;
      } else if (st_.t - st_.baro_ref_t >= double(params_.baro_rate_baseline)) {
        r.vd = apply(gpsins_aid::BaroVerticalVelocity<S>{h_baro, st_.baro_ref_h, st_.t - st_.baro_ref_t});
        if (r.vd.status == Status::Ok || r.vd.status == Status::Rejected) {
          st_.baro_ref_h = h_baro;
          st_.baro_ref_t = st_.t;
        }
      }
    }
    return r;
  }

  /// Compass heading (rad, magnetic; the declination parameter is added). While Levelled it sets
  /// the yaw; afterwards it is a one-row update.
  GpsInsUpdate<S, 1> update_compass(S heading) {
    GpsInsUpdate<S, 1> res;
    if (!std::isfinite(heading)) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::Compass, res);
    }
    if (st_.phase == GpsInsPhase::Aligning) {
      res.status = Status::NotInitialized;
      return res;
    }
    const S yaw_meas = quat::wrap_pi(heading + params_.declination);
    if (st_.phase == GpsInsPhase::Levelled) {
      if (st_.heading_source != GpsInsHeading::Given) {
        set_yaw(yaw_meas);
        st_.heading_source = GpsInsHeading::Compass;
        res.decision = GpsInsDecision::Aligned;
      }
      res.status = Status::NotInitialized;
      return res;
    }
    return apply(gpsins_aid::CompassHeading<S>{yaw_meas});
  }

  /// The error-state transition Phi that a navigating time update with rate omega_ib_b and
  /// specific force f_ib_b (IMU axes) over dt makes from the current state (the smoother's,
  /// nav/gps_ins/smoother.hpp; the rate enters only the scale-factor columns).
  Mat16 transition(const Vec3<S>& omega_ib_b, const Vec3<S>& f_ib_b, S dt) const {
    const Vec3<S> w = detail::gpsins_correct<S, SF_>(imu_to_body(omega_ib_b), st_.gyro_bias, st_.gyro_scale);
    const Vec3<S> f = detail::gpsins_correct<S, SF_>(imu_to_body(f_ib_b), st_.acc_bias, st_.acc_scale);
    return detail::gpsins_Phi_state<S, SF_>(st_, f, w, dt, params_).dense();
  }

 private:
  Vec3<S> imu_to_body(const Vec3<S>& v) const {
    const bool rotated = !(params_.imu_rotation.array() == Mat3<S>::Identity().array()).all();
    return rotated ? Vec3<S>(params_.imu_rotation * v) : v;
  }
  Vec3<S> gps_pos_sigma(const Vec3<S>& s) const {
    return Vec3<S>(std::isnan(s[0]) ? params_.gps_pos_sigma_h : s[0], std::isnan(s[1]) ? params_.gps_pos_sigma_h : s[1],
                   std::isnan(s[2]) ? params_.gps_pos_sigma_v : s[2]);
  }
  Vec3<S> gps_vel_sigma(const Vec3<S>& s) const {
    return Vec3<S>(std::isnan(s[0]) ? params_.gps_vel_sigma : s[0], std::isnan(s[1]) ? params_.gps_vel_sigma : s[1],
                   std::isnan(s[2]) ? params_.gps_vel_sigma : s[2]);
  }

  GpsInsUpdate<S, 3> position_update(double lat, double lon, double h, const Vec3<S>& sigma, S age,
                                     const Vec3<S>& v0_n, const Vec3<S>& vel_sigma) {
    GpsInsUpdate<S, 3> res;
    if (!std::isfinite(lat) || !std::isfinite(lon) || !std::isfinite(h) || !std::isfinite(age) ||
        std::abs(lat) > 1.5707963267948966) {
      res.status = Status::NonFinite;
      return count(GpsInsAid::GpsPos, res);
    }
    const Vec3<S> sig = gps_pos_sigma(sigma);
    if (!(sig.minCoeff() > S(0)) || !sig.allFinite()) {
      res.status = Status::InvalidArgument;
      return count(GpsInsAid::GpsPos, res);
    }
    const Vec3<S> psig = sig.cwiseMax(params_.gps_pos_sigma_min);
    if (st_.phase == GpsInsPhase::Aligning) {
      res.status = align_in_motion(lat, lon, h, psig, v0_n, gps_vel_sigma(vel_sigma));
      if (res.status == Status::Ok) res.decision = GpsInsDecision::Aligned;
      return res;
    }
    if (st_.phase == GpsInsPhase::Levelled) {
      res.status = Status::NotInitialized;
      if (!st_.heading_known) {
        // Levelled at rest, no heading yet: the course between position fixes once moving.
        Quat<S> q;
        Vec3<S> v;
        S vs, ys, ls;
        if (!window_course(lat, lon, h, psig, false, q, v, vs, ys, ls)) return res;
        res.status = start(lat, lon, h, psig, q, v, vs, params_.init_level_sigma, ys, st_.align_method,
                           GpsInsHeading::GnssCourse);
      } else {
        const Vec3<S> v0 = st_.init_v_valid ? st_.init_v : (v0_n.allFinite() ? v0_n : Vec3<S>::Zero());
        res.status = start(lat, lon, h, psig, st_.nav.q_nb, v0, params_.init_vel_sigma, params_.init_level_sigma,
                           params_.init_yaw_sigma, st_.align_method, st_.heading_source);
      }
      if (res.status == Status::Ok) res.decision = GpsInsDecision::Aligned;
      return res;
    }
    return apply(gpsins_aid::GpsPosition<S>{lat, lon, h, sig, age});
  }

  // Alignment in motion at a fix (gps_ins/alignment.hpp): NotInitialized while the window
  // collects, Ok when navigation starts here.
  Status align_in_motion(double lat, double lon, double h, const Vec3<S>& psig, const Vec3<S>& v2,
                         const Vec3<S>& vsig) {
    const bool have_v = v2.allFinite();
    if (!st_.mot_valid) {
      detail::gpsins_window_start(st_, lat, lon, h, v2, have_v);
      return Status::NotInitialized;
    }
    const double T = st_.mot_T;
    if (T >= double(params_.align_motion_time)) {
      const S g = S(earth::gravity<double>(lat, h));
      // The window's velocity increment in the current body frame.
      const Vec3<S> dv_b = quat::rotate_inv(st_.mot_q, Vec3<S>(st_.mot_dv.template cast<S>()));
      const Vec3<S> x_b(S(1), S(0), S(0));
      if (have_v && st_.mot_has_v) {
        const S speed = std::sqrt(v2[0] * v2[0] + v2[1] * v2[1]);
        Mat3<S> C;
        if (speed >= params_.min_speed_for_heading &&
            detail::triad<S>(dv_b, x_b, Vec3<S>(v2 - st_.mot_v0 - Vec3<S>(S(0), S(0), g * S(T))),
                             Vec3<S>(v2[0], v2[1], S(0)), C)) {
          // Level: the velocity noise of both ends over g T, and the initial level sigma.
          // Level: the velocity noise of both ends over g T, the rotation an unknown gyro bias
          // adds over the window, and the initial level sigma.
          const S e = std::sqrt(S(2)) * vsig.maxCoeff() / (g * S(T));
          const S b = params_.init_gyro_bias_sigma * S(T);
          const Status st = start(lat, lon, h, psig, quat::from_rotmat(C), v2, params_.init_vel_sigma,
                                  std::sqrt(params_.init_level_sigma * params_.init_level_sigma + e * e + b * b),
                                  params_.init_yaw_sigma,
                                  GpsInsAlignment::GnssVelocity, GpsInsHeading::GnssVelocity);
          if (st == Status::Ok) st_.level_t = st_.t;
          return st;
        }
      } else if (!have_v) {
        Quat<S> q;
        Vec3<S> v;
        S vs, ys, ls;
        if (window_course(lat, lon, h, psig, true, q, v, vs, ys, ls)) {
          const Status st = start(lat, lon, h, psig, q, v, vs, ls, ys, GpsInsAlignment::GnssCourse,
                                  GpsInsHeading::GnssCourse);
          if (st == Status::Ok) st_.level_t = st_.t;
          return st;
        }
      }
    }
    if (T > double(params_.align_motion_max)) detail::gpsins_window_start(st_, lat, lon, h, v2, have_v);
    return Status::NotInitialized;
  }

  // The course between the fix that opened the motion window and this one, once they are
  // align_course_distance (and four position sigmas) apart: the attitude (with `level`, from the
  // window's mean specific force, the mean acceleration taken as zero, and only when the norm of
  // that force is within rest_acc_th of gravity; else the current roll and pitch), the mean
  // velocity and the sigmas of the velocity, the yaw and the level (an acceleration a changes the
  // norm by about a^2 / 2g: the level sigma covers the a / g that the norm allows, and the
  // rotation an unknown gyro bias adds over the window). False while too close; a window longer
  // than align_motion_max restarts here.
  bool window_course(double lat, double lon, double h, const Vec3<S>& psig, bool level, Quat<S>& q, Vec3<S>& v,
                     S& vel_sigma, S& yaw_sigma, S& level_sigma) {
    if (!st_.mot_valid) {
      detail::gpsins_window_start(st_, lat, lon, h, Vec3<S>(Vec3<S>::Zero()), false);
      return false;
    }
    const Vec3<S> d = earth::geodetic_diff<S>(lat, lon, h, st_.mot_lat, st_.mot_lon, st_.mot_h);
    const S dist = std::sqrt(d[0] * d[0] + d[1] * d[1]);
    const S sh = std::sqrt(psig[0] * psig[0] + psig[1] * psig[1]);
    const double T = st_.mot_T;
    if (T > 0.0 && S(2) * sh / S(T) < S(0.5) * params_.rest_speed) {  // the window tells rest from motion
      st_.gnss_speed = dist / S(T);
      st_.gnss_speed_t = st_.t;
    }
    const S need = params_.align_course_distance > S(4) * sh ? params_.align_course_distance : S(4) * sh;
    if (!(dist >= need) || !(T > 0.0)) {
      if (T > double(params_.align_motion_max)) detail::gpsins_window_start(st_, lat, lon, h, Vec3<S>(Vec3<S>::Zero()), false);
      return false;
    }
    const S course = std::atan2(d[1], d[0]);
    S a = S(0);  // the acceleration the window may hide
    level_sigma = params_.init_level_sigma;
    if (level) {
      const Vec3<S> dv_b = quat::rotate_inv(st_.mot_q, Vec3<S>(st_.mot_dv.template cast<S>()));
      const S g = S(earth::gravity<double>(lat, h));
      const S dev = std::abs(dv_b.norm() / S(T) - g);
      if (!(dev < params_.rest_acc_th)) {  // accelerating: wait
        if (T > double(params_.align_motion_max)) detail::gpsins_window_start(st_, lat, lon, h, Vec3<S>(Vec3<S>::Zero()), false);
        return false;
      }
      Mat3<S> C;
      if (!detail::triad<S>(dv_b, Vec3<S>(S(1), S(0), S(0)), Vec3<S>(S(0), S(0), S(-1)),
                            Vec3<S>(std::cos(course), std::sin(course), S(0)), C))
        return false;
      q = quat::from_rotmat(C);
      a = std::sqrt(S(2) * g * dev);
      const S b = params_.init_gyro_bias_sigma * S(T);
      const S l0 = std::max(params_.align_level_sigma, params_.init_level_sigma);
      level_sigma = std::sqrt(l0 * l0 + (a / g) * (a / g) + b * b);
    } else {
      const Vec3<S> e = quat::to_euler(st_.nav.q_nb);
      q = quat::from_euler(e[0], e[1], course);
    }
    v = Vec3<S>(d[0] / S(T), d[1] / S(T), S(0));
    const S sv = S(2) * sh / S(T) + a * S(T) / S(2);
    vel_sigma = sv > params_.init_vel_sigma ? sv : params_.init_vel_sigma;
    const S sy = S(2) * sh / dist;
    yaw_sigma = sy > params_.init_yaw_sigma ? sy : params_.init_yaw_sigma;
    return true;
  }

  // The altimeter offset state from one altimeter sample h_baro and the INS height: its error is
  // the INS height error (dp_D) plus the sample's noise.
  void init_baro_offset(State& s, double h_baro) const {
    constexpr int D = gpsins::kPos + 2, B = gpsins::kBo;
    s.baro_offset = h_baro - s.nav.h;
    s.P.row(B) = s.P.row(D);
    s.P.col(B) = s.P.col(D);
    s.P(B, B) = s.P(D, D) + params_.baro_sigma * params_.baro_sigma;
    s.baro_offset_valid = true;
  }

  void set_yaw(S yaw) {
    const Vec3<S> e = quat::to_euler(st_.nav.q_nb);
    st_.nav.q_nb = quat::from_euler(e[0], e[1], yaw);
    st_.heading_known = true;
  }

  /// Put back a saved state, keeping the (diagnostic) counters of what happened since.
  void restore(const State& saved) {
    const GpsInsCounters c = st_.counters;
    st_ = saved;
    st_.counters = c;
  }

  // Navigation from a fix (the antenna, less the lever arm) with attitude q, velocity v0 and the
  // initial sigmas given.
  Status start(double lat, double lon, double h, const Vec3<S>& sig, const Quat<S>& q, const Vec3<S>& v0,
               S vel_sigma, S level_sigma, S yaw_sigma, GpsInsAlignment method, GpsInsHeading heading) {
    State s = st_;
    const Vec3<S> l_n = quat::rotate(q, params_.lever_arm_b);
    earth::geodetic_add(lat, lon, h, Vec3<double>(-l_n.template cast<double>()));
    s.nav = StrapdownState<S>();
    s.nav.q_nb = q / q.norm();
    s.nav.v_n = v0;
    s.nav.lat = lat;
    s.nav.lon = lon;
    s.nav.h = h;
    s.P = initial_sigmas(sig, vel_sigma, level_sigma, yaw_sigma).cwiseAbs2().asDiagonal();
    // A huge sigma (float) or a lever arm that moves the fix past the pole is refused.
    if (!s.P.allFinite() || !v0.allFinite() || !detail::gpsins_nav_ok(s)) return Status::NumericalFailure;
    s.phase = GpsInsPhase::Navigating;
    s.heading_known = true;
    s.align_method = method;
    s.heading_source = heading;
    s.nav_start_t = s.t;
    s.mot_valid = false;
    s.baro_offset_valid = false;
    if (s.baro_last_valid) init_baro_offset(s, s.baro_last);
    st_ = s;
    return Status::Ok;
  }

  // The one-sigmas of the covariance at the start of navigation (the altimeter offset's 0 until
  // its first sample).
  Vec16 initial_sigmas(const Vec3<S>& pos_sigma, S vel_sigma, S level_sigma, S yaw_sigma) const {
    Vec16 d;
    d.template head<gpsins::kN>() << pos_sigma, Vec3<S>::Constant(vel_sigma), level_sigma, level_sigma, yaw_sigma,
        Vec3<S>::Constant(params_.init_acc_bias_sigma), Vec3<S>::Constant(params_.init_gyro_bias_sigma), S(0);
    if constexpr (SF_)
      d.template tail<6>() << Vec3<S>::Constant(params_.init_acc_scale_sigma),
          Vec3<S>::Constant(params_.init_gyro_scale_sigma);
    return d;
  }

  template <class R> R count(GpsInsAid kind, R r) {
    const std::size_t k = std::size_t(kind);
    if (r.status == Status::Ok) {
      ++st_.counters.accepted[k];
      if (kind == GpsInsAid::GpsPos || kind == GpsInsAid::GpsVel) st_.gnss_t = st_.t;
      if (r.decision == GpsInsDecision::None) r.decision = GpsInsDecision::Accepted;
    } else if (r.status == Status::Rejected) {
      ++st_.counters.rejected[k];
      if (r.decision == GpsInsDecision::None) r.decision = GpsInsDecision::Rejected;
    } else {
      ++st_.counters.skipped[k];
      r.decision = GpsInsDecision::Skipped;
    }
    if (r.decision == GpsInsDecision::Inflated) ++st_.counters.inflated[k];
    if (r.decision == GpsInsDecision::Reset) ++st_.counters.resets[k];
    return r;
  }

  /// The Kalman correction of an aid with the covariance P (its H nonzero only in the piece's
  /// columns), injected into the nominal state and committed; the status says what happened.
  template <class Aid>
  Status correct_and_commit(const Mat16& P0, const AidMeasurement<S, Aid::M, kStates>& m, S gate,
                            UpdateResult<S, Aid::M>& res) {
    Mat16 P = P0;
    Vec16 dx = Vec16::Zero();
    // kalman_correct refuses an infinite NIS (a finite reading near the float maximum, a height
    // of 1e300 m) with NumericalFailure.
    kalman_correct<S, kStates, Aid::M, Aid::C0, Aid::NC>(P, m.H, m.R, m.y, dx, res, gate);
    return inject_and_commit(
        res, P,
        [&] {
          State s = st_;
          detail::gpsins_inject(s, dx);
          return s;
        },
        [](const State& s, const Mat16&) { return detail::gpsins_nav_ok(s); },
        // The floor acts on P alone (the error state has no constraint), so it does not matter
        // that it comes after the injection here.
        [&](State&, Mat16& Pc) {
          floor_covariance<S, kStates>(Pc, params_.cov_floor);
          return true;
        },
        [&](State& s, const Mat16& Pc) {
          s.P = Pc;
          st_ = s;
        });
  }

  /// The one gated correction path of every aid (gpsins_aid pieces): the piece's innovation, H
  /// and R at the current state; the chi-square gate; for a GNSS aid (kAdaptive) the isolation of
  /// an outlier (a fix failing its gate after one that passed is rejected), the inflation of the
  /// navigation block of P when fixes keep failing (the INS is off, not the fix: P_nav <- a P_nav
  /// with the smallest a >= 1 that makes the fix's NIS equal its rows, up to inflate_max, beyond
  /// which the state is reset to the fix) and the innovation-based adaptation of the process
  /// noise; then the Kalman correction, the injection into the nominal state and the counters.
  template <class Aid> GpsInsUpdate<S, Aid::M> apply(const Aid& aid) {
    constexpr int M = Aid::M;
    AidMeasurement<S, M, kStates> m;
    aid.measure(st_, params_, m);
    GpsInsUpdate<S, M> res;
    std::uint32_t& run = st_.reject_run[std::size_t(Aid::kind)];
    const Status st = correct_and_commit<Aid>(st_.P, m, Aid::gate(params_), res);
    if (st == Status::Ok) {
      run = 0;
      if constexpr (Aid::kAdaptive) adapt(res.nis / S(M));
      return count(Aid::kind, res);
    }
    if (st != Status::Rejected) return count(Aid::kind, res);
    if constexpr (Aid::kAdaptive) {
      if (params_.inflate_after > S(0) && double(run) >= double(params_.inflate_after)) {
        // Fixes keep failing their gate: the INS has drifted beyond its covariance.
        const UpdateResult<S, M> gated = res;  // the innovation and NIS the gate saw
        const S a = inflation<M>(m, gated);
        if (a <= params_.inflate_max) {
          Mat16 P = st_.P;
          P.template topLeftCorner<9, 9>() *= a;
          UpdateResult<S, M> r2;
          if (correct_and_commit<Aid>(P, m, S(0), r2) == Status::Ok) {
            static_cast<UpdateResult<S, M>&>(res) = gated;
            res.status = Status::Ok;
            res.decision = GpsInsDecision::Inflated;
            res.inflation = a;
            run = 0;
            adapt(gated.nis / S(M));
            return count(Aid::kind, res);
          }
        } else {
          State s = st_;
          // R holds outer products (the GNSS time's and the lever arm's terms) that need not be
          // symmetric to the last bit: the covariance block it becomes must be.
          const Mat<S, M, M> R = S(0.5) * (m.R + m.R.transpose());
          if (aid.reset(s, params_, R) && detail::gpsins_nav_ok(s)) {
            st_ = s;
            res.decision = GpsInsDecision::Reset;
            run = 0;
            return count(Aid::kind, res);
          }
        }
      }
    }
    ++run;
    return count(Aid::kind, res);
  }

  /// The smallest a in [1, inflate_max] with y^T (S + (a - 1) H_n P_nn H_n^T)^-1 y <= M (H_n, P_nn:
  /// the position, velocity and attitude columns and block), by bisection on log a; a value above
  /// inflate_max when even that is not enough.
  template <int M> S inflation(const AidMeasurement<S, M, kStates>& m, const UpdateResult<S, M>& gated) const {
    const Mat<S, M, 9> Hn = m.H.template leftCols<9>();
    const Mat<S, 9, 9> Pn = st_.P.template topLeftCorner<9, 9>();
    const Mat<S, M, M> B = fixed_mul(fixed_mul(Hn, Pn), Hn.transpose());
    auto nis = [&](S a) {
      Mat<S, M, M> Sa = gated.innovation_cov + (a - S(1)) * B;
      Mat<S, M, M> L;
      Vec<S, M> inv_d;
      if (!detail::cholesky_small<S, M>(Sa, L, inv_d)) return std::numeric_limits<S>::infinity();
      Mat<S, 1, M> w;
      detail::solve_right_lower_transposed<S, M, 1>(L, inv_d, Mat<S, 1, M>(gated.innovation.transpose()), w);
      return w.squaredNorm();
    };
    const S target = S(M);
    const S amax = params_.inflate_max > S(1) ? params_.inflate_max : S(1);
    if (!(nis(amax) <= target)) return amax * S(2);
    S lo = S(0), hi = std::log(amax);
    for (int i = 0; i < 40; ++i) {
      const S mid = S(0.5) * (lo + hi);
      if (nis(std::exp(mid)) <= target)
        hi = mid;
      else
        lo = mid;
    }
    return std::exp(hi);
  }

  /// Innovation-based adaptation of the process noise from one GNSS update's NIS per row r: the
  /// natural log of q_scale moves by adapt_gain * (ln r - ln 3) while r > 3 and by
  /// adapt_gain * (ln r + ln 3) while r < 1/3, within [1, adapt_q_max]. A consistent filter (r
  /// about 1) leaves it at 1; a process noise too small raises it until the GNSS NIS is back.
  void adapt(S r) {
    if (!(params_.adapt_q_max > S(1)) || !(r > S(0)) || !std::isfinite(r)) return;
    const S l3 = std::log(S(3));
    const S lr = std::log(r > S(1e3) ? S(1e3) : r);
    S step = S(0);
    if (lr > l3)
      step = params_.adapt_gain * (lr - l3);
    else if (lr < -l3)
      step = params_.adapt_gain * (lr + l3);
    if (step == S(0)) return;
    S l = std::log(st_.q_scale) + step;
    const S lmax = std::log(params_.adapt_q_max);
    l = l < S(0) ? S(0) : (l > lmax ? lmax : l);
    st_.q_scale = std::exp(l);
  }

  Params params_;
  State st_;
};

/// Where the batch run writes the per-sample report of one aiding record (any pointer may be
/// null): each row (aiding sample) holds `cols` updates (a GPS fix: position, velocity; an
/// altimeter sample: height, vertical velocity; others one) of `m` rows each.
template <class S> struct GpsInsAidOut {
  S* innovation = nullptr;           ///< (rows, cols * m): INS minus aid; NaN where no update was made
  S* nis = nullptr;                  ///< (rows, cols): NIS the gate saw; NaN where no update was made
  std::uint8_t* status = nullptr;    ///< (rows, cols): quatnav::Status
  std::uint8_t* decision = nullptr;  ///< (rows, cols): GpsInsDecision
  S* inflation = nullptr;            ///< (rows, cols): covariance inflation (1 unless Inflated)
};

/// Batch run over an IMU record and aiding records, each with its own times (s, strictly
/// increasing). IMU sample k holds the mean rate and specific force over (t[k-1], t[k]] (or, with
/// `increments`, the angle and velocity increments over it); sample 0 only fixes the start time.
/// An interval longer than max_dt but at most max_coast is coasted: propagated in equal steps of
/// at most max_dt with sample k (flags::kCoasted). After the time update of sample k: the
/// pseudo-measurements (update_constraints), the magnetometer sample of row k (NaN: none), then
/// the aiding samples with times in (t[k-1], t[k]], in the order compass, odometer, altimeter,
/// GPS; aids at or before t[0] are skipped. GNSS times are put on the IMU clock with the
/// parameter gps_time_offset, and each fix is applied with its age t[k] - (gps_t + offset) (the
/// filter takes the INS back by it). A GPS row whose position is NaN is skipped as absent; a NaN
/// velocity means "no velocity".
///
/// Inputs (row-major; aiding pointers may be null with count 0):
///   t (n), gyro (n x 3, rad/s or rad), accel (n x 3, m/s^2 or m/s), mag (n x 3, any unit, or null);
///   gps_t (ng), gps_llh (ng x 3: lat, lon rad, h m; double), gps_vel (ng x 3, m/s or NaN),
///   gps_pos_sigma (ng x 3, m, NaN: parameters), gps_vel_sigma (ng x 3, m/s, NaN: parameters);
///   baro_t (nb), baro_h (nb, m); compass_t (nc), compass_yaw (nc, rad); odo_t (no), odo_speed (no, m/s).
/// Outputs (any may be null): llh (n x 3, double), v_n (n x 3), q_nb (n x 4), acc_bias,
///   gyro_bias (n x 3), acc_scale, gyro_scale (n x 3; scale-factor states only), sigma (n x 16, or
///   n x 22 with the scale-factor states), baro_offset (n), q_scale (n), flags (n); the reports of
///   the aids: gps (2 updates of 3 rows: position, velocity), baro (2 of 1: height, vertical
///   velocity), compass, odometer (1 of 1), and per IMU sample mag (1 of 1), zupt, zaru (1 of 3),
///   nhc (1 of 2). Statuses are quatnav::Status as uint8.
template <class S> struct GpsInsBatchIo {
  const double* t = nullptr;
  const S* gyro = nullptr;
  const S* accel = nullptr;
  const S* mag = nullptr;
  std::size_t n = 0;
  bool increments = false;
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
  const double* odo_t = nullptr;
  const S* odo_speed = nullptr;
  std::size_t no = 0;
  double* llh = nullptr;
  S* v_n = nullptr;
  S* q_nb = nullptr;
  S* acc_bias = nullptr;
  S* gyro_bias = nullptr;
  S* acc_scale = nullptr;
  S* gyro_scale = nullptr;
  S* sigma = nullptr;
  double* baro_offset = nullptr;
  S* q_scale = nullptr;
  std::uint32_t* flags = nullptr;
  /// The reports of the aids.
  struct Reports {
    GpsInsAidOut<S> gps, baro, compass, odometer, mag, zupt, zaru, nhc;
  } report;
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

/// The flags of one aid update: used / rejected / skipped, and the adaptation's.
template <class S, int M>
std::uint32_t gpsins_update_flags(const GpsInsUpdate<S, M>& r, std::uint32_t used, std::uint32_t rejected) {
  std::uint32_t fl = gpsins_aid_flag(r, used, rejected);
  if (r.decision == GpsInsDecision::Inflated) fl |= flags::kAdapted;
  if (r.decision == GpsInsDecision::Reset) fl |= flags::kGpsReset;
  return fl;
}

/// The time update of batch sample k >= 1: the mean rate w and specific force a over
/// (t[k-1], t[k]] (increments divided by the interval), in m equal steps of dt; a gap longer than
/// max_dt (up to max_coast) is coasted in steps of at most max_dt (m > 1).
template <class S> struct GpsInsSampleStep {
  Vec3<S> w, a;
  long m;
  S dt;
};
template <class S>
GpsInsSampleStep<S> gpsins_sample_step(const GpsInsParams<S>& p, const double* t, const S* gyro, const S* accel,
                                       bool increments, std::size_t k) {
  GpsInsSampleStep<S> u;
  const double step = t[k] - t[k - 1];
  u.w = Eigen::Map<const Vec3<S>>(gyro + 3 * k);
  u.a = Eigen::Map<const Vec3<S>>(accel + 3 * k);
  if (increments) {  // angle and velocity increments over the interval: their means
    u.w /= S(step);
    u.a /= S(step);
  }
  const double max_dt = double(p.max_dt);
  u.m = 1;
  if (step > max_dt && step <= double(p.max_coast) && max_dt > 0.0) u.m = long(std::ceil(step / (max_dt * (1.0 - 1e-9))));
  u.dt = S(step / double(u.m));
  return u;
}

/// Prefill an aid's report: NaN innovations and NIS, NotInitialized, decision None, inflation 1.
template <class S> void gpsins_out_init(const GpsInsAidOut<S>& o, std::size_t rows, int cols, int m) {
  const S nan = std::numeric_limits<S>::quiet_NaN();
  for (std::size_t j = 0; j < rows * std::size_t(cols); ++j) {
    for (int i = 0; i < m && o.innovation; ++i) o.innovation[j * std::size_t(m) + std::size_t(i)] = nan;
    if (o.nis) o.nis[j] = nan;
    if (o.status) o.status[j] = std::uint8_t(Status::NotInitialized);
    if (o.decision) o.decision[j] = std::uint8_t(GpsInsDecision::None);
    if (o.inflation) o.inflation[j] = S(1);
  }
}

/// Write update r as column `col` of row `row` of an aid's report (`cols` updates per row).
template <class S, int M>
void gpsins_out_write(const GpsInsAidOut<S>& o, std::size_t row, int cols, int col, const GpsInsUpdate<S, M>& r) {
  const std::size_t j = row * std::size_t(cols) + std::size_t(col);
  const bool done = r.status == Status::Ok || r.status == Status::Rejected;
  if (o.innovation && done)
    for (int i = 0; i < M; ++i) o.innovation[j * M + std::size_t(i)] = r.innovation[i];
  if (o.nis && done) o.nis[j] = r.nis;
  if (o.status) o.status[j] = std::uint8_t(r.status);
  if (o.decision) o.decision[j] = std::uint8_t(r.decision);
  if (o.inflation) o.inflation[j] = r.inflation;
}
}  // namespace detail

/// Run the filter over the records of `io` (see GpsInsBatchIo). Allocates nothing. Every sample
/// is reported to `obs` (core/checks.hpp's NoBatchObserver; the smoother's record): after the
/// time update of sample k (all its coasting steps), and after all its steps.
template <class S, bool SF, class Observer = NoBatchObserver>
void gpsins_batch(GpsInsFilter<S, SF>& f, const GpsInsBatchIo<S>& io, Observer&& obs = Observer{}) {
  namespace gf = flags;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  detail::gpsins_out_init(io.report.gps, io.ng, 2, 3);
  detail::gpsins_out_init(io.report.baro, io.nb, 2, 1);
  detail::gpsins_out_init(io.report.compass, io.nc, 1, 1);
  detail::gpsins_out_init(io.report.odometer, io.no, 1, 1);
  detail::gpsins_out_init(io.report.mag, io.n, 1, 1);
  detail::gpsins_out_init(io.report.zupt, io.n, 1, 3);
  detail::gpsins_out_init(io.report.zaru, io.n, 1, 3);
  detail::gpsins_out_init(io.report.nhc, io.n, 1, 2);
  if (io.n == 0) return;
  const double t0 = io.t[0];
  const double gps_offset = double(f.params().gps_time_offset);
  auto gps_time = [&](std::size_t i) { return io.gps_t[i] + gps_offset; };
  std::size_t ig = 0, ib = 0, ic = 0, io_ = 0;
  while (ig < io.ng && gps_time(ig) <= t0) ++ig;
  while (ib < io.nb && io.baro_t[ib] <= t0) ++ib;
  while (ic < io.nc && io.compass_t[ic] <= t0) ++ic;
  while (io_ < io.no && io.odo_t[io_] <= t0) ++io_;

  for (std::size_t k = 0; k < io.n; ++k) {
    std::uint32_t fl = 0;
    const bool was_nav = f.navigating();
    const S q_scale0 = f.q_scale();
    if (k > 0) {
      const detail::GpsInsSampleStep<S> u = detail::gpsins_sample_step(f.params(), io.t, io.gyro, io.accel, io.increments, k);
      if (u.m > 1) fl |= gf::kCoasted;
      Status s = Status::Ok;
      for (long j = 0; j < u.m && s == Status::Ok; ++j) s = f.predict(u.w, u.a, u.dt);
      if (s != Status::Ok) fl |= gf::kPredictSkipped | (s == Status::Saturated ? gf::kSaturated : 0u);
      obs.after_predict(k, f);
      const ConstraintResult<S> cr = f.update_constraints();
      detail::gpsins_out_write(io.report.zupt, k, 1, 0, cr.zupt);
      detail::gpsins_out_write(io.report.zaru, k, 1, 0, cr.zaru);
      detail::gpsins_out_write(io.report.nhc, k, 1, 0, cr.nhc);
      if (cr.zupt.status == Status::Ok || cr.zaru.status == Status::Ok || cr.nhc.status == Status::Ok)
        fl |= gf::kConstraintUsed;
      if (io.mag) {
        const Vec3<S> mk = Eigen::Map<const Vec3<S>>(io.mag + 3 * k);
        if (!(std::isnan(mk[0]) && std::isnan(mk[1]) && std::isnan(mk[2]))) {
          const GpsInsUpdate<S, 1> r = f.update_mag(mk);
          detail::gpsins_out_write(io.report.mag, k, 1, 0, r);
          fl |= detail::gpsins_update_flags(r, gf::kHeadingUsed, gf::kMagRejected);
          if (fl & gf::kAidSkipped) fl |= gf::kMagSkipped;
        }
      }
      const double tk = io.t[k];
      for (; ic < io.nc && io.compass_t[ic] <= tk; ++ic) {
        const GpsInsUpdate<S, 1> r = f.update_compass(io.compass_yaw[ic]);
        detail::gpsins_out_write(io.report.compass, ic, 1, 0, r);
        fl |= detail::gpsins_update_flags(r, gf::kHeadingUsed, gf::kHeadingRejected);
      }
      for (; io_ < io.no && io.odo_t[io_] <= tk; ++io_) {
        const GpsInsUpdate<S, 1> r = f.update_odometer(io.odo_speed[io_]);
        detail::gpsins_out_write(io.report.odometer, io_, 1, 0, r);
        fl |= detail::gpsins_update_flags(r, gf::kConstraintUsed, 0u);
      }
      for (; ib < io.nb && io.baro_t[ib] <= tk; ++ib) {
        const BaroResult<S> r = f.update_baro(io.baro_h[ib]);
        detail::gpsins_out_write(io.report.baro, ib, 2, 0, r.height);
        detail::gpsins_out_write(io.report.baro, ib, 2, 1, r.vd);
        fl |= detail::gpsins_update_flags(r.height, gf::kBaroUsed, gf::kBaroRejected);
        fl |= detail::gpsins_update_flags(r.vd, gf::kBaroVdUsed, gf::kBaroVdRejected);
      }
      for (; ig < io.ng && gps_time(ig) <= tk; ++ig) {
        const double* llh = io.gps_llh + 3 * ig;
        if (std::isnan(llh[0]) && std::isnan(llh[1]) && std::isnan(llh[2])) {
          GpsInsUpdate<S, 3> absent;
          absent.status = Status::NonFinite;
          absent.decision = GpsInsDecision::Skipped;
          detail::gpsins_out_write(io.report.gps, ig, 2, 0, absent);
          continue;
        }
        const Vec3<S> vel = io.gps_vel ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_vel + 3 * ig)) : Vec3<S>::Constant(nan);
        const Vec3<S> ps = io.gps_pos_sigma ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_pos_sigma + 3 * ig))
                                            : Vec3<S>::Constant(nan);
        const Vec3<S> vs = io.gps_vel_sigma ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_vel_sigma + 3 * ig))
                                            : Vec3<S>::Constant(nan);
        const GpsResult<S> r = f.update_gps(llh[0], llh[1], llh[2], vel, ps, vs, S(tk - gps_time(ig)));
        detail::gpsins_out_write(io.report.gps, ig, 2, 0, r.pos);
        detail::gpsins_out_write(io.report.gps, ig, 2, 1, r.vel);
        fl |= detail::gpsins_update_flags(r.pos, gf::kGpsPosUsed, gf::kGpsPosRejected);
        fl |= detail::gpsins_update_flags(r.vel, gf::kGpsVelUsed, gf::kGpsVelRejected);
      }
    }
    if (f.at_rest()) fl |= gf::kAtRest;
    switch (f.phase()) {
      case GpsInsPhase::Aligning: fl |= gf::kAligning; break;
      case GpsInsPhase::Levelled: fl |= gf::kLevelled; break;
      case GpsInsPhase::Navigating: fl |= gf::kNavigating; break;
    }
    if (!was_nav && f.navigating()) fl |= gf::kInitialized;
    if (f.q_scale() != q_scale0) fl |= gf::kAdapted;
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
    if (io.acc_scale) Eigen::Map<Vec3<S>>(io.acc_scale + 3 * k) = f.acc_scale();
    if (io.gyro_scale) Eigen::Map<Vec3<S>>(io.gyro_scale + 3 * k) = f.gyro_scale();
    constexpr int N = GpsInsFilter<S, SF>::kStates;
    if (io.sigma)
      Eigen::Map<Vec<S, N>>(io.sigma + N * k) =
          nav ? Vec<S, N>(f.covariance().diagonal().cwiseMax(S(0)).cwiseSqrt()) : Vec<S, N>::Constant(nan);
    if (io.baro_offset)
      io.baro_offset[k] = nav && f.state().baro_offset_valid ? f.baro_offset() : std::numeric_limits<double>::quiet_NaN();
    if (io.q_scale) io.q_scale[k] = f.q_scale();
    if (io.flags) io.flags[k] = fl;
    obs.after_sample(k, f);
  }
}

}  // namespace quatnav
