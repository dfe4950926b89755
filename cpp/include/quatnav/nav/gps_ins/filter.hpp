// quatnav: GpsInsFilter, the loosely coupled GPS/INS feedback Kalman filter of paper 004: the class (alignment
// phases, time update, one update per aid through one gated correction path). Model, equations and the paper's
// slips: nav/gps_ins.hpp; its pieces: params.hpp, model.hpp, aids.hpp, alignment.hpp; its batch run: batch.hpp.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "../../core/checks.hpp"
#include "../../core/commit.hpp"
#include "../../core/covariance.hpp"
#include "../../core/earth.hpp"
#include "../../core/kalman.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"
#include "../strapdown.hpp"
#include "aids.hpp"
#include "alignment.hpp"
#include "model.hpp"
#include "params.hpp"

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
    // As the filter keeps them (detail::gpsins_state_ok): everything finite, |q| = 1, the
    // latitude off the poles, P exactly symmetric with a non-negative diagonal, the enums in range.
    if (!detail::gpsins_state_ok(s)) return Status::InvalidArgument;
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
    s.rest_v = v_n;
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
    bool resolved = true;  // navigating: the INS speed resolves rest_speed (detail::gpsins_rest_slow)
    const bool slow = s.phase == GpsInsPhase::Navigating
                          ? detail::gpsins_rest_slow(s, params_, resolved)
                          : !(s.gnss_speed >= S(0) && s.t - s.gnss_speed_t < 2.0 && s.gnss_speed > params_.rest_speed);
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
          if (!detail::gpsins_state_ok(s)) return Status::NumericalFailure;
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
      const Vec3<S> v0 = s.nav.v_n;
      const Status st = strapdown_step(s.nav, w, f, dt, sp);
      if (st != Status::Ok) return st;
      if (!resolved) detail::gpsins_rest_velocity(s, params_, Vec3<S>(s.nav.v_n - v0), g);
      Mat16 P = detail::gpsins_propagate_P<S, SF_>(Phi, s.P, params_, s.q_scale, s.nav.q_nb, w, dt);
      symmetrize(P);
      if (params_.acc_bias_tau > S(0)) s.acc_bias *= std::exp(-dt / params_.acc_bias_tau);
      if (params_.gyro_bias_tau > S(0)) s.gyro_bias *= std::exp(-dt / params_.gyro_bias_tau);
      if (!P.allFinite()) return Status::NumericalFailure;
      floor_covariance<S, kStates>(P, params_.cov_floor);  // may fail near the overflow limit: s.P below
      s.P = P;
    }
    if (s.phase == GpsInsPhase::Navigating) detail::gpsins_nhc_evidence(s, params_, dt);
    s.omega_b = w;
    s.f_b = f;
    s.dt_last = double(dt);
    s.t += double(dt);
    // The whole candidate as set_state() would take it: the rest low-passes and the motion window
    // of a reading near the float maximum, a propagated P that lost its non-negative diagonal (an
    // indefinite or ill-conditioned P) are refused.
    if (!detail::gpsins_state_ok(s)) return Status::NumericalFailure;
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
      // Forced (nhc): nhc_sigma; by evidence: no less than the motion showed, and the lateral row
      // only in an outage (nhc_lateral_aided): while aided it would pin the heading to the track
      // through a mounting yaw not yet learned (heading NEES 85 on the simulated car).
      const S r0 = params_.nhc_sigma * params_.nhc_sigma;
      const bool lateral = params_.nhc || params_.nhc_lateral_aided || !detail::gpsins_gnss_aided(st_);
      r.nhc = apply(gpsins_aid::NonHolonomic<S>{params_.nhc ? r0 : std::max(r0, st_.nhc_ms), st_.nhc_ky, st_.nhc_kz,
                                                lateral});
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
  /// valid `age` seconds before the filter's time (0: now), of the receiver's solution kind `kind`
  /// (which sets the floor of the one-sigma, detail::gnss_sigma_floor). While Levelled with a
  /// heading known, the first fix starts navigation (at zero velocity; update_gps starts with the
  /// fix's velocity).
  GpsInsUpdate<S, 3> update_gps_position(double lat, double lon, double h, const Vec3<S>& sigma, S age = S(0),
                                         GnssSolution kind = GnssSolution::Unknown) {
    const Vec3<S> nan3 = Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN());
    return position_update(lat, lon, h, sigma, age, nan3, nan3, kind);
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
      // A speed that overflows (components near the float maximum) is not recorded.
      const S moving = speed - S(3) * std::sqrt(sig[0] * sig[0] + sig[1] * sig[1]);
      if (std::isfinite(moving)) {
        st_.gnss_speed = moving > S(0) ? moving : S(0);
        st_.gnss_speed_t = st_.t;
      }
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
  /// velocity means "no velocity in this fix". `age`, `kind`: as update_gps_position.
  GpsResult<S> update_gps(double lat, double lon, double h, const Vec3<S>& v_n, const Vec3<S>& pos_sigma,
                          const Vec3<S>& vel_sigma, S age = S(0), GnssSolution kind = GnssSolution::Unknown) {
    GpsResult<S> r;
    const bool have_vel = !std::isnan(v_n[0]) || !std::isnan(v_n[1]) || !std::isnan(v_n[2]);
    if (st_.phase != GpsInsPhase::Navigating) {
      if (have_vel) r.vel = update_gps_velocity(v_n, vel_sigma, age);
      r.pos = position_update(lat, lon, h, pos_sigma, age, v_n, vel_sigma, kind);
      return r;
    }
    r.pos = position_update(lat, lon, h, pos_sigma, age, v_n, vel_sigma, kind);
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
      // used: Ok, decision Aligned, innovation and NIS zero). A height whose difference from the
      // INS height overflows (a reading near the double maximum) is refused, nothing kept.
      if (!detail::gpsins_init_baro_offset(st_, h_baro, params_.baro_sigma)) {
        restore(saved);
        r.height.status = Status::NumericalFailure;
        count(GpsInsAid::Baro, r.height);
        return r;
      }
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
                                     const Vec3<S>& v0_n, const Vec3<S>& vel_sigma, GnssSolution kind) {
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
    const Vec3<S> floor = detail::gnss_sigma_floor(params_, kind);
    const Vec3<S> psig = sig.cwiseMax(floor);
    if (st_.phase != GpsInsPhase::Navigating) {
      // Before navigation a fix is recorded (NotInitialized) or starts navigation (Ok); a refused
      // start (NumericalFailure) undoes what the fix recorded on the way (window, GNSS speed).
      const State saved = st_;
      res.status = st_.phase == GpsInsPhase::Aligning ? align_in_motion(lat, lon, h, psig, v0_n, gps_vel_sigma(vel_sigma))
                                                      : levelled_fix(lat, lon, h, psig, v0_n);
      if (res.status == Status::Ok)
        res.decision = GpsInsDecision::Aligned;
      else if (res.status != Status::NotInitialized)
        restore(saved);
      return res;
    }
    return detail::position_used(st_, apply(detail::gnss_position(st_, params_, lat, lon, h, sig, age, floor, kind)), age);
  }

  // Levelled, a fix: with a heading known it starts navigation; without, the course between
  // position fixes once moving (NotInitialized while too close).
  Status levelled_fix(double lat, double lon, double h, const Vec3<S>& psig, const Vec3<S>& v0_n) {
    if (!st_.heading_known) {
      Quat<S> q;
      Vec3<S> v;
      S vs, ys, ls;
      if (!window_course(lat, lon, h, psig, false, q, v, vs, ys, ls)) return Status::NotInitialized;
      return start(lat, lon, h, psig, q, v, vs, params_.init_level_sigma, ys, st_.align_method,
                   GpsInsHeading::GnssCourse);
    }
    const Vec3<S> v0 = st_.init_v_valid ? st_.init_v : (v0_n.allFinite() ? v0_n : Vec3<S>::Zero());
    return start(lat, lon, h, psig, st_.nav.q_nb, v0, params_.init_vel_sigma, params_.init_level_sigma,
                 params_.init_yaw_sigma, st_.align_method, st_.heading_source);
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
    // The window tells rest from motion (a speed that overflows is not recorded).
    if (T > 0.0 && S(2) * sh / S(T) < S(0.5) * params_.rest_speed && std::isfinite(dist / S(T))) {
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
    s.nav_start_t = s.gps_pos_t = s.t;  // gps_pos_t: the fix it starts from (gnss_correlation_scale)
    s.rest_v = v0;
    s.mot_valid = false;
    s.baro_offset_valid = false;
    // From the last altimeter sample; one whose offset overflows leaves it to the next sample.
    if (s.baro_last_valid) detail::gpsins_init_baro_offset(s, s.baro_last, params_.baro_sigma);
    if (!detail::gpsins_state_ok(s)) return Status::NumericalFailure;
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
    if (r.decision == GpsInsDecision::Weighted) ++st_.counters.weighted[k];
    if (r.decision == GpsInsDecision::Reset) ++st_.counters.resets[k];
    return r;
  }

  /// The Kalman correction of an aid with the covariance P (its H nonzero only in the piece's
  /// columns), injected into the nominal state and committed; the status says what happened.
  /// With robust_k > 0 a correction is made again with R raised where the innovation's components
  /// lie beyond robust_k of their sigmas (detail::huber_scales; *weighted says so), and a fix the
  /// gate refused is judged again on that weighted innovation (detail::gpsins_huber_correct: only
  /// a gross outlier stays refused); res keeps the innovation, its covariance and NIS as it came.
  template <class Aid>
  Status correct_and_commit(const Mat16& P0, const AidMeasurement<S, Aid::M, kStates>& m, S gate,
                            UpdateResult<S, Aid::M>& res, S robust_k = S(0), bool* weighted = nullptr) {
    Mat16 P = P0;
    Vec16 dx = Vec16::Zero();
    // kalman_correct refuses an infinite NIS (a finite reading near the float maximum, a height
    // of 1e300 m) with NumericalFailure.
    kalman_correct<S, kStates, Aid::M, Aid::C0, Aid::NC>(P, m.H, m.R, m.y, dx, res, gate);
    const bool w = detail::gpsins_huber_correct<Aid>(P0, m, robust_k, gate, P, dx, res);
    if (weighted) *weighted = w;
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
          // The floor of a P near the overflow limit can fail; a P ill-conditioned beyond the
          // precision loses its non-negative diagonal in the Joseph form: refused.
          return detail::acceptable_covariance<S, kStates>(Pc);
        },
        [&](State& s, const Mat16& Pc) {
          s.P = Pc;
          st_ = s;
        });
  }

  /// The one gated correction path of every aid (gpsins_aid pieces): the piece's innovation, H
  /// and R at the current state; the chi-square gate; for a GNSS aid (kAdaptive) the isolation of
  /// an outlier (a fix failing its gate after one that passed is rejected), the inflation of the
  /// position and velocity block of P when fixes keep failing (the INS is off, not the fix:
  /// P_pv <- a P_pv with the smallest a >= 1 that makes the fix's NIS equal its rows, up to
  /// inflate_max, beyond which the state is reset to the fix; the attitude is left alone: on a
  /// straight road a heading sigma inflated to tens of degrees is walked by the fixes' noise
  /// through the lever arm, and a car enters its next outage with the heading off by as much) and
  /// the innovation-based adaptation of the process
  /// noise; then the Kalman correction, the injection into the nominal state and the counters.
  template <class Aid> GpsInsUpdate<S, Aid::M> apply(const Aid& aid) {
    constexpr int M = Aid::M;
    AidMeasurement<S, M, kStates> m;
    aid.measure(st_, params_, m);
    GpsInsUpdate<S, M> res;
    std::uint32_t& run = st_.reject_run[std::size_t(Aid::kind)];
    bool weighted = false;
    const Status st = correct_and_commit<Aid>(st_.P, m, Aid::gate(params_), res,
                                              Aid::kAdaptive ? params_.gps_robust_k : S(0), &weighted);
    if (st == Status::Ok) {
      run = 0;
      if (weighted) res.decision = GpsInsDecision::Weighted;
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
          P.template topLeftCorner<6, 6>() *= a;
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
          if (aid.reset(s, params_, R) && detail::gpsins_nav_ok(s) && detail::acceptable_covariance<S, kStates>(s.P)) {
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
  /// the position and velocity columns and block), by bisection on log a; a value above
  /// inflate_max when even that is not enough.
  template <int M> S inflation(const AidMeasurement<S, M, kStates>& m, const UpdateResult<S, M>& gated) const {
    const Mat<S, M, 6> Hn = m.H.template leftCols<6>();
    const Mat<S, 6, 6> Pn = st_.P.template topLeftCorner<6, 6>();
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

}  // namespace quatnav
