// quatnav: clipped gyro readings, a part of the quaternion EKFs (QuaternionEKF, QuaternionEKFPaper).
//
// A gyro reads at most its range: beyond it an axis reports the range itself, the same value
// sample after sample, and the step turns the attitude by less than the body turned. Without the
// range given (gyro_range, which refuses such steps), the part recognizes the clip by that
// signature: an axis whose reading repeats its previous gyro_clip_repeats readings exactly, at
// or above every magnitude seen so far on any axis and at least gyro_clip_min_rate. (One repeat
// was not enough: BROAD's trial 21 repeats a 610 deg/s reading once, the simulated pendulum,
// limb swings, running and shaking at 80-190 deg/s early in their motion; none repeats twice,
// the simulated clipped gyro does so on 228 of its 234 clipped samples.) A clipped step is still
// taken (the reading is the best lower bound of the rate) but the filter stops trusting it:
//   - the attitude error of that body axis gets the variance (gyro_clip_noise |w_i| dt)^2 (the
//     rate beyond the range is unknown, of the order of the range itself), so that the
//     accelerometer (and the magnetometer in 9D) take the attitude back at once;
//   - the accelerometer part's low-pass restarts (AccFilter::restart): it runs in a frame carried
//     by the gyro, which the clip turned wrongly, and would otherwise hold the wrong vertical for
//     its time constant.
// The first gyro_clip_repeats samples of an event are not recognized. On the simulated
// flips at 650 deg/s with a 500 deg/s gyro (quatnav eval sim:fast_gyro_saturation) the
// inclination RMSE drops from 15.6 to about 1.5 deg (docs/broad.md).
#pragma once

#include <cmath>

#include "../../core/fields.hpp"
#include "../../core/types.hpp"

namespace quatnav {

// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_GYRO_CLIP_PARAMS(X)                                                                     \
  X(bool, gyro_clip, true, "-",                                                                         \
    "recognize clipped gyro readings (an axis stuck at the largest magnitude seen) and distrust them")  \
  X(S, gyro_clip_min_rate, S(1), "rad/s", "smallest reading taken for a clip")                          \
  X(int, gyro_clip_repeats, 2, "1", "a clip: the reading repeats this many previous readings exactly")   \
  X(S, gyro_clip_noise, S(1), "1",                                                                      \
    "std of a clipped step's attitude error about that axis, as a fraction of reading times dt")

/// Parameters of the clip recognition.
template <class S> struct GyroClipParams {
  QUATNAV_FIELDS(GyroClipParams, QUATNAV_GYRO_CLIP_PARAMS)
};

#define QUATNAV_GYRO_CLIP_STATE(X)                                                                      \
  X(Vec3<S>, gyr_prev, Vec3<S>::Zero(), "rad/s", "gyro reading of the last predict")                    \
  X(S, gyr_max, S(0), "rad/s", "largest magnitude of any axis's reading so far")                        \
  X(Vec3<S>, gyr_repeats, Vec3<S>::Zero(), "1", "how many previous readings each axis's repeats")         \
  X(bool, clip_init, false, "-", "gyr_prev holds a reading")

template <class S> struct GyroClipState {
  QUATNAV_FIELDS(GyroClipState, QUATNAV_GYRO_CLIP_STATE)
};

/// The steps of the clip recognition, on a filter's GyroClipParams and GyroClipState.
template <class S> struct GyroClip {
  using Params = GyroClipParams<S>;
  using State = GyroClipState<S>;

  static void off(Params& p) { p.gyro_clip = false; }

  /// When the filter starts (initialize): nothing seen yet.
  static void restart(State& s) {
    s.gyr_max = S(0);
    s.clip_init = false;
  }

  /// At every predict, on a copy of the state that the filter commits with the step: the gyro
  /// reading gyr [rad/s] of a step of dt [s]. Returns the diagonal of the variance [rad^2] to add
  /// to the body-frame attitude error (zero where no axis clipped).
  static Vec3<S> step(const Params& p, State& s, const Vec3<S>& gyr, S dt) {
    Vec3<S> var = Vec3<S>::Zero();
    if (!p.gyro_clip) return var;
    const Vec3<S> a = gyr.cwiseAbs();
    for (int i = 0; i < 3; ++i) {
      s.gyr_repeats[i] = (s.clip_init && gyr[i] == s.gyr_prev[i]) ? s.gyr_repeats[i] + S(1) : S(0);
      if (s.gyr_repeats[i] >= S(p.gyro_clip_repeats) && a[i] >= s.gyr_max && a[i] >= p.gyro_clip_min_rate) {
        const S sd = p.gyro_clip_noise * a[i] * dt;
        var[i] = sd * sd;
      }
    }
    s.gyr_max = a.maxCoeff() > s.gyr_max ? a.maxCoeff() : s.gyr_max;
    s.gyr_prev = gyr;
    s.clip_init = true;
    return var;
  }
};

}  // namespace quatnav
