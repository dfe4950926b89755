// quatnav: rest detection and its zero-rate measurement of the gyro bias, a part of the attitude
// filters (QuaternionEKFPaper, QuaternionEKF, EulerEKF, MargFilter compose it).
//
// Rest is declared once, for rest_time without a break, (i) the gyro stays within rest_gyr_th of
// its low-pass, (ii) that low-pass within rest_gyr_th of the bias estimate or of zero and (iii)
// the accelerometer within rest_acc_th of its low-pass (first-order low-passes with time constant
// rest_tau, the gyro's advanced at each predict, the accelerometer's at each accelerometer
// sample). Test (ii) tells a slow steady rotation from rest; "or of zero" keeps a wrong bias
// estimate from locking rest out: a filter that learned a bias of tens of deg/s in fast motion
// (started moving, no heading reference) would otherwise never see rest again, and so never
// learn the bias back, while a still gyro reading near zero is rest whatever the estimate. At
// rest the body does not turn, so the gyro reading of the last predict is the bias plus noise, a
// measurement of the bias:
//     z = w - b = 0 + v,   E[v v^T] = (gyro_noise^2 / dt + rest_rate_noise^2) I,
// gyro_noise^2 / dt the white noise of one sample and rest_rate_noise the residual rate (a
// vehicle at rest still vibrates). The Kalman filters apply it to their bias block; MargFilter,
// which has no covariance, takes the low-passed gyro as its bias (marg_filter.hpp).
//
// The part follows the input signal: its step runs at every accelerometer sample, whatever the
// filter's update then does (accepted, rejected or refused).
#pragma once

#include <cmath>

#include "../attitude.hpp"
#include "../../core/fields.hpp"
#include "../../core/types.hpp"

namespace quatnav {

// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_REST_PARAMS(X)                                                                          \
  X(bool, rest_detection, true, "-", "detect rest and use it as a zero-rate measurement of the gyro bias") \
  X(S, rest_gyr_th, S(0.03), "rad/s", "rest: largest deviation of the low-passed gyro")                  \
  X(S, rest_acc_th, S(0.5), "m/s^2", "rest: largest deviation of the low-passed accelerometer")          \
  X(S, rest_time, S(1.5), "s", "rest: shortest duration")                                                \
  X(S, rest_tau, S(0.5), "s", "rest: low-pass time constant")                                            \
  X(S, rest_rate_noise, S(0.02), "rad/s", "std of the residual rate at rest")

/// Parameters of the rest detection (the defaults are QuaternionEKF's, chosen on BROAD).
template <class S> struct RestParams {
  QUATNAV_FIELDS(RestParams, QUATNAV_REST_PARAMS)
};

#define QUATNAV_REST_STATE(X)                                                                           \
  X(Vec3<S>, gyr_last, Vec3<S>::Zero(), "rad/s", "gyro sample of the last predict")                     \
  X(Vec3<S>, gyr_lp, Vec3<S>::Zero(), "rad/s", "low-passed gyro of the rest test")                      \
  X(Vec3<S>, acc_lp, Vec3<S>::Zero(), "m/s^2", "low-passed accelerometer of the rest test")             \
  X(bool, rest_lp_init, false, "-", "the low-pass filters of the rest test hold a sample")               \
  X(S, rest_t, S(0), "s", "time the rest conditions have held")

template <class S> struct RestState {
  QUATNAV_FIELDS(RestState, QUATNAV_REST_STATE)
};

/// The steps of the rest detection, on a filter's RestParams and RestState.
template <class S> struct Rest {
  using Params = RestParams<S>;
  using State = RestState<S>;

  /// Switch the part off (the plain filters of the papers).
  static void off(Params& p) { p.rest_detection = false; }

  /// When the filter starts (initialize): the low-passes start again from the next samples.
  static void restart(State& s) {
    s.rest_lp_init = false;
    s.rest_t = S(0);
  }

  /// At every predict: the gyro sample [rad/s] of a step of dt [s].
  static void predict(const Params& p, State& s, const Vec3<S>& gyr, S dt) {
    if (!p.rest_detection) return;
    s.gyr_last = gyr;
    if (s.rest_lp_init) detail::lowpass(s.gyr_lp, gyr, dt, p.rest_tau);
  }

  /// At every accelerometer sample (dt: the step of the last predict): the rest test. True at rest,
  /// when the filter applies the zero-rate measurement.
  static bool update(const Params& p, State& s, const Vec3<S>& acc, const Vec3<S>& gyro_bias, S dt) {
    if (!p.rest_detection) return false;
    if (!s.rest_lp_init || !(dt > S(0))) {
      s.gyr_lp = s.gyr_last;
      s.acc_lp = acc;
      s.rest_lp_init = dt > S(0);
      s.rest_t = S(0);
      return false;
    }
    detail::lowpass(s.acc_lp, acc, dt, p.rest_tau);
    const bool still = (s.gyr_last - s.gyr_lp).norm() < p.rest_gyr_th &&
                       ((s.gyr_lp - gyro_bias).norm() < p.rest_gyr_th || s.gyr_lp.norm() < p.rest_gyr_th) &&
                       (acc - s.acc_lp).norm() < p.rest_acc_th;
    s.rest_t = still ? s.rest_t + dt : S(0);
    return s.rest_t >= p.rest_time;
  }

  /// True while rest is detected.
  static bool at_rest(const Params& p, const State& s) { return p.rest_detection && s.rest_t >= p.rest_time; }

  /// The zero-rate measurement's innovation z - h(b) = w - b.
  static Vec3<S> zero_rate_innovation(const State& s, const Vec3<S>& gyro_bias) { return s.gyr_last - gyro_bias; }

  /// Its variance per component: gyro_noise^2 / dt + rest_rate_noise^2.
  static S zero_rate_variance(const Params& p, S gyro_noise, S dt) {
    return gyro_noise * gyro_noise / dt + p.rest_rate_noise * p.rest_rate_noise;
  }
};

}  // namespace quatnav
