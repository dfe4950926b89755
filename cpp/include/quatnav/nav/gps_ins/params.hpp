// quatnav: GpsInsFilter's parameters and state (nav/gps_ins.hpp), each field declared once
// (core/fields.hpp): the binding, the dict round trip and the Python tables come from these rows.
#pragma once

#include <array>
#include <cstdint>

#include "../../core/fields.hpp"
#include "../../core/types.hpp"
#include "../strapdown.hpp"

namespace quatnav {

/// Parameters (units beside each field; defaults fit a MEMS IMU and a standalone GPS).
// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_GPSINS_PARAMS(X)                                                                      \
  X(S, gyro_noise, S(8.7e-4), "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)")        \
  X(S, acc_noise, S(2.0e-3), "m/s^2/sqrt(Hz)", "accelerometer white-noise density (velocity random walk)") \
  X(S, gyro_bias_noise, S(1.0e-5), "rad/s^2/sqrt(Hz)", "gyro-bias random-walk density")                 \
  X(S, acc_bias_noise, S(1.0e-4), "m/s^3/sqrt(Hz)", "accelerometer-bias random-walk density")           \
  X(S, gyro_bias_tau, S(0), "s", "Gauss-Markov time constant of the gyro bias (0: random walk)")        \
  X(S, acc_bias_tau, S(0), "s", "Gauss-Markov time constant of the accelerometer bias (0: random walk)") \
  X(S, init_gyro_bias_sigma, S(5.0e-3), "rad/s", "gyro-bias one-sigma at the start of navigation")      \
  X(S, init_acc_bias_sigma, S(0.1), "m/s^2", "accelerometer-bias one-sigma at the start of navigation")  \
  X(S, init_level_sigma, S(0.035), "rad", "roll/pitch one-sigma after the alignment")                    \
  X(S, init_yaw_sigma, S(0.175), "rad", "yaw one-sigma after the alignment")                            \
  X(S, init_vel_sigma, S(0.5), "m/s", "velocity one-sigma at the start of navigation")                  \
  X(S, gps_pos_sigma_h, S(2.5), "m", "horizontal one-sigma of a GPS position (per-fix sigma overrides)") \
  X(S, gps_pos_sigma_v, S(5.0), "m", "vertical one-sigma of a GPS position")                            \
  X(S, gps_vel_sigma, S(0.1), "m/s", "one-sigma of each GPS velocity component")                        \
  X(Vec3<S>, lever_arm_b, Vec3<S>::Zero(), "m", "GPS antenna relative to the IMU, body FRD")            \
  X(S, baro_sigma, S(0.5), "m", "one-sigma of an altimeter height")                                     \
  X(S, baro_rate_baseline, S(1.0), "s", "baseline of the altimeter's vertical-velocity difference")     \
  X(S, baro_vd_sigma, S(0.1), "m/s", "one-sigma of the altimeter's vertical velocity")                  \
  X(S, baro_offset_fixes, S(100), "1", "GPS fixes over which the altimeter offset is averaged")          \
  X(S, compass_sigma, S(0.035), "rad", "one-sigma of a compass heading")                                \
  X(S, declination, S(0), "rad", "magnetic declination, east of true north (added to compass headings)") \
  X(S, gate_gps_pos, S(21.108), "1 (chi-square, 3 dof)", "NIS gate of the GPS position (0: off)")       \
  X(S, gate_gps_vel, S(21.108), "1 (chi-square, 3 dof)", "NIS gate of the GPS velocity (0: off)")       \
  X(S, gate_baro, S(15.137), "1 (chi-square, 1 dof)", "NIS gate of the altimeter (0: off)")             \
  X(S, gate_compass, S(15.137), "1 (chi-square, 1 dof)", "NIS gate of the compass (0: off)")            \
  /* after that many consecutive gate rejections of GPS position (velocity) the next rejected one  \
     resets the position (velocity) to the fix */                                                      \
  X(S, gps_reset_after, S(5), "1", "consecutive gate rejections before a GPS reset (0: never)")         \
  X(S, align_time, S(2.0), "s", "duration of the static alignment")                                     \
  X(S, min_speed_for_heading, S(1.0), "m/s", "GPS speed above which the heading comes from the GPS track") \
  X(bool, heading_from_gps, true, "-", "initialize the heading from the GPS track (without compass)")    \
  X(bool, earth_rotation, true, "-", "include the Earth rate, transport rate and Coriolis terms")         \
  X(S, max_dt, S(1), "s", "longest accepted IMU step")                                                  \
  X(S, gyro_range, S(0), "rad/s",                                                                       \
    "gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited)")   \
  X(S, acc_range, S(0), "m/s^2", "accelerometer range per axis, as gyro_range (0: unlimited)")           \
  /* applied only when P is not positive definite above it (covariance.hpp) */                         \
  X(S, cov_floor, S(0), "state units^2", "eigenvalue floor of the error covariance (0: off)")

template <class S> struct GpsInsParams {
  QUATNAV_FIELDS(GpsInsParams, QUATNAV_GPSINS_PARAMS)
};

/// Alignment phase.
enum class GpsInsPhase : std::uint8_t { Aligning = 0, Levelled = 1, Navigating = 2 };

/// The kinds of aid, the index of each in the counters.
enum class GpsInsAid : std::uint8_t { GpsPos = 0, GpsVel = 1, Baro = 2, BaroVd = 3, Compass = 4 };
inline constexpr int kGpsInsAidKinds = 5;
/// Python names of the aid kinds, in GpsInsAid order (the keys of the counters).
inline constexpr const char* kGpsInsAidNames[kGpsInsAidKinds] = {"gps_pos", "gps_vel", "baro", "baro_vd",
                                                                 "compass"};

/// Counts of measurement outcomes per aid kind (GpsInsAid order).
using GpsInsCounts = std::array<std::uint32_t, kGpsInsAidKinds>;
#define QUATNAV_GPSINS_COUNTERS(X)                                                                    \
  X(GpsInsCounts, accepted, GpsInsCounts{}, "-", "updates applied, per aid kind")                      \
  X(GpsInsCounts, rejected, GpsInsCounts{}, "-", "updates refused by the chi-square gate, per aid kind") \
  X(GpsInsCounts, skipped, GpsInsCounts{}, "-", "samples skipped as invalid (or failed updates), per aid kind") \
  X(GpsInsCounts, resets, GpsInsCounts{}, "-", "gate-lockout resets, per aid kind")

struct GpsInsCounters {
  QUATNAV_FIELDS(GpsInsCounters, QUATNAV_GPSINS_COUNTERS)
};

/// Everything the filter holds (plain data; state()/set_state() round-trip exactly). The nominal
/// navigation state `nav` and the counters appear flattened in the dict of get_state().
#define QUATNAV_GPSINS_STATE(X)                                                                       \
  X(StrapdownState<S>, nav, StrapdownState<S>(), "-", "nominal navigation state")                      \
  X(Vec3<S>, acc_bias, Vec3<S>::Zero(), "m/s^2", "accelerometer bias estimate")                         \
  X(Vec3<S>, gyro_bias, Vec3<S>::Zero(), "rad/s", "gyro bias estimate")                                 \
  X(Mat15, P, Mat15::Zero(), "state units^2", "error-state covariance")                                  \
  X(double, t, 0.0, "s", "filter time: sum of the accepted IMU intervals")                              \
  X(Vec3<S>, omega_b, Vec3<S>::Zero(), "rad/s", "last bias-corrected body rate")                         \
  X(Vec3<S>, f_b, Vec3<S>::Zero(), "m/s^2", "last bias-corrected specific force")                        \
  X(GpsInsPhase, phase, GpsInsPhase::Aligning, "-", "alignment phase: 0 aligning, 1 levelled, 2 navigating") \
  X(Vec3<double>, align_sum, Vec3<double>::Zero(), "m/s", "sum of f_ib_b dt while aligning")             \
  X(double, align_time, 0.0, "s", "time accumulated while aligning")                                    \
  X(bool, heading_known, false, "-", "levelled: the yaw has been set")                                  \
  X(bool, baro_offset_valid, false, "-", "the altimeter offset has a value")                            \
  X(double, baro_offset, 0.0, "m", "added to the altimeter height")                                     \
  X(double, baro_last, 0.0, "m", "latest altimeter height seen")                                        \
  X(bool, baro_last_valid, false, "-", "baro_last holds a height")                                      \
  X(bool, baro_ref_valid, false, "-", "a derivative baseline has started")                              \
  X(double, baro_ref_h, 0.0, "m", "altimeter height at the start of the derivative baseline")           \
  X(double, baro_ref_t, 0.0, "s", "filter time at the start of the derivative baseline")                \
  X(double, baro_offset_n, 0.0, "1", "fixes averaged into baro_offset so far")                          \
  X(std::uint32_t, gps_pos_reject_run, 0u, "-", "consecutive gate rejections of GPS position")          \
  X(std::uint32_t, gps_vel_reject_run, 0u, "-", "consecutive gate rejections of GPS velocity")          \
  X(GpsInsCounters, counters, GpsInsCounters(), "-", "outcomes per aid kind")

template <class S> struct GpsInsState {
  using Mat15 = Mat<S, 15, 15>;
  QUATNAV_FIELDS(GpsInsState, QUATNAV_GPSINS_STATE)
};

}  // namespace quatnav
