// quatnav: the parameters of the quaternion EKF, shared by its two forms: QuaternionEKF
// (quaternion_ekf.hpp, the 6-state error-state filter, the default) and QuaternionEKFPaper
// (quaternion_ekf_paper.hpp, the 7-state filter as paper 000 writes it), and the fields of
// their state.
#pragma once

#include "parts/parts.hpp"
#include "../core/fields.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

/// Parameters of QuaternionEKF (quaternion_ekf.hpp) and of its paper form QuaternionEKFPaper
/// (quaternion_ekf_paper.hpp). Every field has its
/// unit and default.
///
/// The first block is paper 000's filter. The second block adds what real data needs (linear
/// accelerations, magnetic disturbances, gyro bias at rest); paper() switches all of it off and
/// gives the plain filter of the paper with its original noise values. The robust features
/// assume acc in m/s^2 (they compare |acc| with `gravity`); with acc in other units set
/// `gravity` to 1 g in that unit.
///
/// The defaults were chosen on the BROAD benchmark (8 trials, one set for all, lowest mean
/// total RMSE; see docs/broad.md). The noise values are effective ones: they cover what the
/// model leaves out (correlated residual linear acceleration after the low-pass, field
/// deviations, scale-factor errors), so that the attitude error stays within the filter's own
/// 3 sigma on real data. All noise values scaled by one factor give the same estimates and a
/// covariance scaled by its square.
// X(type, name, default, unit, doc): each field once (core/fields.hpp). The robustness parts
// declare their own fields (parts/*.hpp), flattened beside these in the Python binding; paper()
// below holds the paper's values.
#define QUATNAV_QEKF_PARAMS(X)                                                                          \
  X(S, gyro_noise, S(0.01), "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)")            \
  X(S, gyro_bias_noise, S(1e-4), "rad/s^2/sqrt(Hz)", "gyro-bias random-walk density")                    \
  /* the gyro's scale-factor and misalignment errors grow with the rate and the accelerometer            \
     corrects them in the tilt only (attitude.hpp, detail::tilt_rate_noise) */                     \
  X(S, gyro_rate_noise, S(0.004), "1/sqrt(Hz)",                                                          \
    "rate-proportional attitude process noise: density gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only") \
  X(S, acc_sigma, S(0.4), "1 (normalized)", "std of each component of the normalized accelerometer")     \
  X(S, mag_sigma, S(1.0), "1 (normalized)", "std of each component of the normalized magnetometer")      \
  X(S, init_att_sigma, S(0.5), "rad", "attitude one-sigma after initialize")                             \
  X(S, init_gyro_bias_sigma, S(0.1), "rad/s", "gyro-bias one-sigma after initialize")                    \
  X(S, max_dt, S(1), "s", "longest accepted IMU step")                                                   \
  X(S, gyro_range, S(0), "rad/s",                                                                        \
    "gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited)")    \
  X(S, acc_range, S(0), "m/s^2", "accelerometer range per axis, as gyro_range (0: unlimited)")            \
  /* the floor acts in the error state [dtheta (rad, body frame), db (rad/s)] (covariance.hpp) */       \
  X(S, cov_floor, S(1e-12), "state units^2", "eigenvalue floor of the error covariance (0: off)")         \
  /* in [-pi, pi]; otherwise x is true north: the reference field points to heading `declination` \
     and initialize() adds it to the magnetic heading */                                             \
  X(S, declination, S(0), "rad", "magnetic declination, east of true north (0: x is magnetic north)")    \
  /* a scalar update of the heading of the field's horizontal projection whose gain is projected on  \
     the yaw direction, so that the magnetometer never tilts roll and pitch; false: eq. 12 rows 4-6 */ \
  X(bool, mag_heading_only, true, "-", "the magnetometer corrects heading only (false: 3-row update)")   \
  /* the Schmidt-Kalman update of quaternion_ekf.hpp (error-state filter only): gravity has no     \
     heading information; false: the optimal gain, which turns them through the correlations of P */ \
  X(bool, acc_tilt_only, true, "-",                                                                      \
    "the accelerometer corrects the tilt and the horizontal gyro bias only (false: the optimal gain)")    \
  X(S, acc_gate, S(0), "1 (chi-square, 3 dof)", "NIS gate of the accelerometer update (0: off)")          \
  X(S, mag_gate, S(9), "1 (chi-square)", "NIS gate of the magnetometer update (0: off)")                 \
  X(AccFilterParams<S>, acc, AccFilterParams<S>(), "-", "accelerometer low-pass, rejection, adaptive noise") \
  X(MagDisturbanceParams<S>, mag, MagDisturbanceParams<S>(), "-", "reference field and disturbance tests") \
  X(RestParams<S>, rest, RestParams<S>(), "-", "rest detection and zero-rate measurement")                \
  X(GyroClipParams<S>, clip, GyroClipParams<S>(), "-", "clipped gyro readings")

template <class S> struct QuaternionEKFParams {
  QUATNAV_FIELDS(QuaternionEKFParams, QUATNAV_QEKF_PARAMS)

  /// The plain filter of paper 000: its noise values, every robustness feature off.
  static QuaternionEKFParams paper() {
    QuaternionEKFParams p;
    p.gyro_noise = S(0.005);
    p.gyro_bias_noise = S(1e-5);
    p.gyro_rate_noise = S(0);
    p.acc_sigma = S(0.05);
    p.mag_sigma = S(0.1);
    p.init_att_sigma = S(0.05);
    p.init_gyro_bias_sigma = S(0.01);
    p.mag_heading_only = false;
    p.acc_tilt_only = false;
    p.acc_gate = p.mag_gate = S(0);
    AccFilter<S>::off(p.acc);
    MagDisturbance<S>::off(p.mag);
    Rest<S>::off(p.rest);
    GyroClip<S>::off(p.clip);
    return p;
  }
};

/// The complete state of QuaternionEKFPaper (7x7 covariance of [q_nb, gyro_bias]) and of
/// QuaternionEKF (6x6 covariance of the error state); state()/set_state() round-trip exactly.
#define QUATNAV_QEKF_STATE(X)                                                                           \
  X(Quat<S>, q_nb, quat::identity<S>(), "1", "attitude q_nb [w, x, y, z]")                               \
  X(Vec3<S>, gyro_bias, Vec3<S>::Zero(), "rad/s", "gyro bias")                                          \
  X(MatP, P, MatP::Identity(), "state units^2", kCovarianceDoc)                                         \
  X(bool, initialized, false, "-", "the filter has a state")                                            \
  X(S, dt_last, S(0), "s", "step of the last predict")                                                  \
  X(MagDisturbanceState<S>, mag, MagDisturbanceState<S>(), "-", "reference field and disturbance tests") \
  X(AccFilterState<S>, acc, AccFilterState<S>(), "-", "accelerometer low-pass and rejection timer")      \
  X(RestState<S>, rest, RestState<S>(), "-", "rest detection")                                         \
  X(GyroClipState<S>, clip, GyroClipState<S>(), "-", "clipped gyro readings")

}  // namespace quatnav
