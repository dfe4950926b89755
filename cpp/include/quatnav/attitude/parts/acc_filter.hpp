// quatnav: the accelerometer's treatment before an attitude update, a part of the attitude
// filters (QuaternionEKFPaper, QuaternionEKF, EulerEKF, MargFilter compose it): a low-pass in a
// quasi-inertial frame, the rejection of samples whose norm is not gravity's, an adaptive noise
// and the recovery from a run of rejections.
//
//  * Low-pass (acc_lp_tau > 0). Each sample is rotated into a frame q_i carried by the
//    bias-corrected gyro alone (q_i <- q_i * exp((w - b) dt) at every predict), low-passed there
//    and rotated back into the current body frame; the result replaces the raw sample. Linear
//    accelerations average out in that frame (their mean over an interval is a velocity change
//    over its length) while gravity stays. The frame turns by about sigma_b * tau for a gyro-bias
//    error sigma_b, so while the filter's largest gyro-bias variance sigma_b^2 exceeds
//    acc_lp_bias_sigma^2 the time constant is acc_lp_tau * (acc_lp_bias_sigma / sigma_b)^2: the
//    low-pass is only trusted as far as the bias is known. That shorter low-pass passes the
//    linear acceleration on to the update, harmless while the body only turns, fatal under
//    sustained linear acceleration: a filter started in a pendulum's or a limb's swing, its bias
//    unknown, took the swing's centripetal acceleration for gravity and learned a bias of tens of
//    deg/s along the swinging axis (whose variance, unobserved, kept the low-pass short for the
//    whole run): 6D and 9D errors of 90-110 deg. So the shrink fades out as the raw samples'
//    low-passed ||a| - g| (time constant acc_lp_tau) approaches acc_lp_dev:
//        tau = tau_b + (acc_lp_tau - tau_b) min(1, dev_lp / acc_lp_dev),
//    tau_b the shrunk time constant above.
//  * The bias weight (bias_weight()): the body's attitude in the same frame is low-passed with
//    the same time constant. The low-passed sample's error (the part of a periodic linear
//    acceleration the low-pass lets through: centripetal and tangential acceleration of a swing)
//    is correlated over that time and in phase with the motion; a bias component that swings
//    in and out of the vertical with the motion is seen only through an oscillation at the
//    motion's frequency, where that error lives, and learning it from the accelerometer turns
//    the error into a bias (a pendulum's string axis: 1.4 deg/s in a minute, 12 deg of 6D
//    heading). So the accelerometer's gain in the bias block is weighted by
//        W = C^T (I - g g^T) C,   C = the low-passed C_ib, g = the low-passed C_ib u, normalized
//    (u the body-frame vertical of the filter, C_ib u the vertical in the low-pass frame): the
//    body directions that stayed horizontal over the time constant keep their gain, those that
//    swung through the vertical lose it (VQF estimates the bias in motion through a low-passed
//    rotation matrix in the same way). W is symmetric with eigenvalues in [0, 1]; without
//    rotation W = I - u u^T, the plain projection off the vertical. (Projecting W off the
//    current vertical as well, P_u W P_u, couples the swinging directions again, in phase with
//    the swing: 6.4 deg on the pendulum in 6D against 1.5.) The vertical in the low-pass frame
//    is constant but for the filter's tilt error, which under a swing oscillates with the swing;
//    g is therefore low-passed as C is (g_i_lp, the current one while that average is shorter
//    than 0.5). With the current vertical, W swung in the same phase as the accelerometer's
//    error and the string axis of a pendulum started in the swing still learned a bias: 6D 8.5
//    -> 5.7 deg, and 8.8 / 7.8 / 5.9 -> 6.3 / 4.8 / 4.0 on three held-out seeds; a run's
//    torso, whose vertical barely swings, loses 0.6-1.8 deg in 6D instead (docs/broad.md).
//    QuaternionEKF gives screen() its vertical; EulerEKF does not and keeps the current one
//    (with the low-passed one its 6D figure started in the motion went 8.89 -> 9.13 deg).
//    A low-pass has averaged nothing before it has run for about its time constant: its first
//    sample, with whatever linear acceleration it holds, keeps a weight of e^(-t/tau). So W
//    grows from 0 to full over the low-pass's first 2 acc_lp_tau (W times min(1, age / (2
//    acc_lp_tau)), age the time since its first sample): a filter started in a swing or a run no
//    longer learns, in its first seconds, a bias that the motion's linear acceleration made up
//    and that it then keeps where the bias is unobservable (docs/broad.md). A filter started at
//    rest learns its bias there from the zero-rate rows (parts/rest.hpp) meanwhile.
//    And W falls with the linear acceleration the raw samples show: times
//        1 / (1 + (dev_lp / acc_bias_dev)^2),   dev_lp the low-passed ||a| - g| above.
//    The low-passed sample's error is the part of the linear acceleration the low-pass lets
//    through, correlated over its time constant, while the update takes it as white noise at
//    every sample: what the accelerometer says about the bias is worth the less the more linear
//    acceleration there is. A body that only turns (dev_lp at the noise's level) keeps the full
//    gain and learns its bias in motion as before; a run or a vibrating mount (dev_lp of several
//    m/s^2) learns it from rest, or more slowly. With acc_bias_dev = 2 m/s^2, started in a
//    pendulum's swing, 6D: 18.9 -> 8.5 deg; every data set and mode of docs/broad.md moved by
//    at most 0.001 deg the wrong way (chosen there beside 0.25, 0.5 and 1).
//  * Rejection (acc_reject > 0): a sample with ||a| - g| > acc_reject is not used.
//  * Adaptive noise: the filter's one-sigma of the normalized sample grows by
//    acc_adapt * ||a| - g| / g (MargFilter lowers its gain instead).
//  * Recovery (acc_recovery_time > 0): after that long with every update rejected (by the norm
//    test or the filter's gate) the samples are accepted again, with the adaptive noise and
//    without the default gate, so that a filter with a wrong tilt comes back.
//
// The part follows the input signal: the low-pass and the timer advance whatever the update does.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "../attitude.hpp"
#include "../../core/fields.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"

namespace quatnav {

// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_ACC_FILTER_PARAMS(X)                                                                    \
  X(S, gravity, S(9.81), "m/s^2", "magnitude of gravity, in the unit of acc")                            \
  X(S, acc_adapt, S(0), "1", "adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g")       \
  X(S, acc_reject, S(0), "m/s^2", "reject the accelerometer when ||a|-g| exceeds it (0: off)")            \
  X(S, acc_recovery_time, S(0), "s",                                                                     \
    "after this long with every accelerometer update rejected, accept again (0: never)")                 \
  X(S, acc_lp_tau, S(3), "s", "low-pass time constant of the accelerometer in a quasi-inertial frame (0: off)") \
  X(S, acc_lp_bias_sigma, S(0.006), "rad/s",                                                             \
    "above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by "                \
    "(acc_lp_bias_sigma / sigma_b)^2 (0: off)")                                                         \
  X(S, acc_lp_dev, S(1), "m/s^2",                                                                        \
    "the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches "  \
    "this (0: off)")                                                                                     \
  X(S, acc_bias_dev, S(2), "m/s^2",                                                                      \
    "the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), "   \
    "dev_lp the low-passed ||a|-g| of the raw samples (0: off)")

/// Parameters of the accelerometer part (the defaults are QuaternionEKF's, chosen on BROAD).
template <class S> struct AccFilterParams {
  QUATNAV_FIELDS(AccFilterParams, QUATNAV_ACC_FILTER_PARAMS)
};

#define QUATNAV_ACC_FILTER_STATE(X)                                                                     \
  X(Quat<S>, q_i, quat::identity<S>(), "1", "gyro-only frame of the accelerometer low-pass, q_ib")      \
  X(Vec3<S>, acc_i_lp, Vec3<S>::Zero(), "m/s^2", "low-passed accelerometer in that frame")              \
  X(Mat3<S>, C_i_lp, Mat3<S>::Identity(), "1", "low-passed attitude C_ib in that frame (the bias weight)") \
  X(Vec3<S>, g_i_lp, Vec3<S>::Zero(), "1", "low-passed body-frame vertical of the filter in that frame (the bias weight)") \
  X(bool, acc_lp_init, false, "-", "acc_i_lp holds a sample")                                           \
  X(S, acc_dev_lp, S(0), "m/s^2", "low-passed ||a| - g| of the raw samples (acc_lp_dev)")                \
  X(S, acc_lp_age, S(0), "s", "time since the low-pass's first sample (the bias weight's ramp)")          \
  X(S, acc_reject_t, S(0), "s", "time every accelerometer update was rejected")

template <class S> struct AccFilterState {
  QUATNAV_FIELDS(AccFilterState, QUATNAV_ACC_FILTER_STATE)
};

/// The sample an attitude filter uses, and how (AccFilter::screen).
template <class S> struct AccSample {
  Vec3<S> acc;                ///< the sample to use: low-passed when acc_lp_tau > 0 [unit of acc]
  S sigma_add = S(0);         ///< added to the filter's one-sigma of the normalized sample (acc_adapt)
  bool rejected = false;      ///< refused by the norm test: no update
  bool recovering = false;    ///< after acc_recovery_time of rejections: accept, without the default gate

  /// The NIS gate of the update: the one given, else the filter's default (none while recovering).
  S gate(S given, S default_gate) const { return given > S(0) ? given : (recovering ? S(0) : default_gate); }
};

/// The steps of the accelerometer part, on a filter's AccFilterParams and AccFilterState.
template <class S> struct AccFilter {
  using Params = AccFilterParams<S>;
  using State = AccFilterState<S>;

  /// Switch the part off (the plain filters of the papers): the raw sample, never rejected, the
  /// constant noise (gravity is kept: MargFilter's eq. 7 uses it).
  static void off(Params& p) {
    p.acc_adapt = p.acc_reject = p.acc_recovery_time = p.acc_lp_tau = p.acc_lp_bias_sigma = p.acc_lp_dev =
        p.acc_bias_dev = S(0);
  }

  /// When the filter starts (initialize): the low-pass and the timer start afresh.
  static void restart(State& s) {
    s.acc_lp_init = false;
    s.q_i = quat::identity<S>();
    s.acc_reject_t = S(0);
  }

  /// At every predict: carry the low-pass frame by the step's rotation dq = exp((w - b) dt).
  static void predict(const Params& p, State& s, const Quat<S>& dq) {
    if (!(p.acc_lp_tau > S(0))) return;
    const Quat<S> qi = quat::mul(s.q_i, dq);
    s.q_i = qi / qi.norm();
  }

  /// predict() for a filter that has no dq of its own: the bias-corrected rate w - b [rad/s] over dt [s].
  static void predict_rate(const Params& p, State& s, const Vec3<S>& rate, S dt) {
    if (p.acc_lp_tau > S(0)) predict(p, s, quat::from_rotvec(Vec3<S>(rate * dt)));
  }

  /// The low-pass time constant for a largest gyro-bias variance max_bias_var [(rad/s)^2]
  /// (0: a filter that does not shrink it).
  static S time_constant(const Params& p, S max_bias_var) {
    const S sb = p.acc_lp_bias_sigma;
    if (!(sb > S(0))) return p.acc_lp_tau;
    return max_bias_var > sb * sb ? p.acc_lp_tau * (sb * sb / max_bias_var) : p.acc_lp_tau;
  }

  /// The same, the shrink faded out by the low-passed linear acceleration dev_lp [m/s^2]
  /// (acc_lp_dev; the top of this file).
  static S time_constant(const Params& p, S max_bias_var, S dev_lp) {
    const S tau_b = time_constant(p, max_bias_var);
    if (!(p.acc_lp_dev > S(0)) || tau_b == p.acc_lp_tau) return tau_b;
    return tau_b + (p.acc_lp_tau - tau_b) * std::min(S(1), dev_lp / p.acc_lp_dev);
  }

  /// At every accelerometer sample acc (dt: the step of the last predict): the sample to use, its
  /// extra noise and whether it is refused. The filter then updates (or not) and calls finish().
  /// up: the filter's body-frame vertical (unit) at its current attitude, for the bias weight
  /// (zero: a filter that does not use bias_weight()).
  static AccSample<S> screen(const Params& p, State& s, const Vec3<S>& acc, S dt, S max_bias_var,
                             const Vec3<S>& up = Vec3<S>::Zero()) {
    AccSample<S> out;
    out.acc = acc;
    if (p.acc_lp_tau > S(0)) {
      const Mat3<S> C_ib = quat::to_rotmat(s.q_i);  // one rotation matrix for its uses here
      const Vec3<S> a_i = C_ib * acc;
      const Vec3<S> g_i = C_ib * up;
      const S dev_raw = std::abs(acc.norm() - p.gravity);
      if (!s.acc_lp_init || !(dt > S(0))) {
        s.acc_i_lp = a_i;
        s.C_i_lp = C_ib;
        s.g_i_lp = g_i;
        s.acc_dev_lp = dev_raw;
        s.acc_lp_age = S(0);
        s.acc_lp_init = true;
      } else {
        s.acc_lp_age = std::min(s.acc_lp_age + dt, S(2) * p.acc_lp_tau);
        detail::lowpass(s.acc_dev_lp, dev_raw, dt, p.acc_lp_tau);
        const S tau = time_constant(p, max_bias_var, s.acc_dev_lp);
        detail::lowpass(s.acc_i_lp, a_i, dt, tau);
        detail::lowpass(s.C_i_lp, C_ib, dt, tau);
        detail::lowpass(s.g_i_lp, g_i, dt, tau);
      }
      out.acc.noalias() = C_ib.transpose() * s.acc_i_lp;
    }
    const S g = p.gravity;
    const S dev = g > S(0) ? std::abs(out.acc.norm() - g) : S(0);
    out.recovering = p.acc_recovery_time > S(0) && s.acc_reject_t >= p.acc_recovery_time;
    out.rejected = p.acc_reject > S(0) && dev > p.acc_reject && !out.recovering;
    out.sigma_add = g > S(0) ? p.acc_adapt * dev / g : S(0);
    return out;
  }

  /// The weight of the accelerometer's gain in the gyro-bias block (the top of this file) for the
  /// filter's body-frame vertical u (unit): W = C^T (I - g g^T) C, g = C_ib u, times the ramp
  /// min(1, age / (2 acc_lp_tau)) and 1 / (1 + (dev_lp / acc_bias_dev)^2); I - u u^T without the
  /// low-pass or before its first sample.
  static Mat3<S> bias_weight(const Params& p, const State& s, const Vec3<S>& u) {
    if (!(p.acc_lp_tau > S(0)) || !s.acc_lp_init) return Mat3<S>::Identity() - u * u.transpose();
    // The vertical in the low-pass frame, low-passed as C is (g_i_lp; the top of this file); the
    // current one where that average has no direction (a frame that turned the vertical away).
    const S n2 = s.g_i_lp.squaredNorm();
    const Vec3<S> g = n2 > S(0.25) ? Vec3<S>(s.g_i_lp / std::sqrt(n2)) : Vec3<S>(quat::rotate(s.q_i, u));
    const Eigen::Matrix<S, 1, 3> gC = g.transpose() * s.C_i_lp;
    Mat3<S> W;
    W.noalias() = s.C_i_lp.transpose() * s.C_i_lp;
    W.noalias() -= gC.transpose() * gC;
    const S ramp_end = S(2) * p.acc_lp_tau;
    if (s.acc_lp_age < ramp_end) W *= s.acc_lp_age / ramp_end;
    if (p.acc_bias_dev > S(0)) {
      const S r = s.acc_dev_lp / p.acc_bias_dev;
      W *= S(1) / (S(1) + r * r);
    }
    return W;
  }

  /// The accelerometer update of an attitude filter: screen(), the filter's own update
  /// filter_update(const AccSample&) -> its result (not called for a refused sample), finish();
  /// kAccRejected in sample_flags when the sample was rejected (norm test or the filter's gate).
  template <class Update>
  static auto update(const Params& p, State& s, const Vec3<S>& acc, S dt, S max_bias_var, std::uint32_t& sample_flags,
                     Update&& filter_update, const Vec3<S>& up = Vec3<S>::Zero()) {
    const AccSample<S> in = screen(p, s, acc, dt, max_bias_var, up);
    using Result = decltype(filter_update(in));
    Result res = in.rejected ? Result{} : filter_update(in);  // one result, built in place
    if (in.rejected) res.status = Status::Rejected;
    finish(p, s, res.status, dt);
    if (res.status == Status::Rejected) sample_flags |= flags::kAccRejected;
    return res;
  }

  /// After the update (status Rejected also for a sample refused by screen()): the rejection timer.
  static void finish(const Params& p, State& s, Status status, S dt) {
    if (status == Status::Ok) {
      s.acc_reject_t = S(0);
    } else if (status == Status::Rejected && p.acc_recovery_time > S(0)) {
      s.acc_reject_t += dt;
    }
  }
};

}  // namespace quatnav
