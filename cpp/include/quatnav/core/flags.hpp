// quatnav: the one table of per-sample flags written by every filter's batch run.
//
// Each flag has one bit, the same in every filter; a filter sets the subset that applies to it
// (the "filters" column). The table is declared once, in QUATNAV_FLAG_TABLE below: the constants
// in namespace flags and the table kFlagTable (bound to Python as quatnav.Flag) both come from it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace quatnav {

// X(constant, python_name, bit, doc). Bit 31 is free.
#define QUATNAV_FLAG_TABLE(X)                                                                        \
  X(kInitialized, initialized, 0, "the filter was initialized at this sample (GpsInsFilter: navigation started)") \
  X(kPredictSkipped, predict_skipped, 1, "time update skipped (invalid IMU sample or dt)")          \
  X(kAccSkipped, acc_skipped, 2, "accelerometer update skipped (invalid input)")                    \
  X(kMagSkipped, mag_skipped, 3, "magnetometer update skipped (invalid input)")                     \
  X(kAccRejected, acc_rejected, 4, "accelerometer rejected (gate or disturbance)")                  \
  X(kMagRejected, mag_rejected, 5, "magnetometer rejected (gate or disturbance)")                   \
  X(kSolveFailed, solve_failed, 6, "a Kalman correction failed; state kept")                        \
  X(kSingular, singular, 7, "near a parametrization singularity (EulerEKF)")                        \
  X(kAtRest, at_rest, 8, "rest detected")                                                            \
  X(kNoMag, no_mag, 9, "no magnetometer sample at this step")                                       \
  X(kSaturated, saturated, 10, "a reading was saturated (its step skipped)")                       \
  X(kGpsCorrected, gps_corrected, 11, "MargFilter: accelerometer corrected with GPS acceleration (eq. 7)") \
  X(kGnNotConverged, gn_not_converged, 12, "MargFilter: Gauss-Newton stopped at gn_max_iter")       \
  X(kAligning, aligning, 13, "GpsInsFilter: still averaging the accelerometer")                     \
  X(kLevelled, levelled, 14, "GpsInsFilter: levelled, waiting for heading and a fix")               \
  X(kNavigating, navigating, 15, "GpsInsFilter: the full filter runs")                              \
  X(kGpsPosUsed, gps_pos_used, 16, "a GPS position was applied")                                    \
  X(kGpsPosRejected, gps_pos_rejected, 17, "a GPS position failed its gate")                        \
  X(kGpsVelUsed, gps_vel_used, 18, "a GPS velocity was applied")                                    \
  X(kGpsVelRejected, gps_vel_rejected, 19, "a GPS velocity failed its gate")                        \
  X(kBaroUsed, baro_used, 20, "an altimeter height was applied")                                    \
  X(kBaroRejected, baro_rejected, 21, "an altimeter height failed its gate")                        \
  X(kBaroVdUsed, baro_vd_used, 22, "an altimeter vertical velocity was applied")                    \
  X(kBaroVdRejected, baro_vd_rejected, 23, "an altimeter vertical velocity failed its gate")        \
  X(kHeadingUsed, heading_used, 24, "a heading (compass or yaw) was applied")                       \
  X(kHeadingRejected, heading_rejected, 25, "a heading (compass or yaw) failed its gate")           \
  X(kAidSkipped, aid_skipped, 26, "an aiding sample was invalid or its update failed")              \
  X(kGpsReset, gps_reset, 27, "a GPS position or velocity reset (gate lockout)")                         \
  X(kCoasted, coasted, 28, "GpsInsFilter: an IMU gap longer than max_dt was coasted in steps of at most max_dt") \
  X(kAdapted, adapted, 29, "GpsInsFilter: a GNSS fix applied after a covariance inflation, or the process-noise scale changed") \
  X(kConstraintUsed, constraint_used, 30, "GpsInsFilter: a zero-velocity, zero-rate, non-holonomic or odometer update was applied")

/// Per-sample flags (a uint32 bit mask), one table for every filter.
namespace flags {
#define QUATNAV_FLAG_CONSTANT(k, name, bit, doc) constexpr std::uint32_t k = 1u << (bit);
QUATNAV_FLAG_TABLE(QUATNAV_FLAG_CONSTANT)
#undef QUATNAV_FLAG_CONSTANT
}  // namespace flags

/// One row of the flag table.
struct FlagInfo {
  const char* name;  ///< the Python name (quatnav.Flag member, result.flag(name))
  std::uint32_t bit;  ///< the mask, 1 << bit number
  const char* doc;
};

#define QUATNAV_FLAG_ROW(k, name, bit, doc) FlagInfo{#name, 1u << (bit), doc},
inline constexpr FlagInfo kFlagTable[] = {QUATNAV_FLAG_TABLE(QUATNAV_FLAG_ROW)};
#undef QUATNAV_FLAG_ROW
inline constexpr std::size_t kFlagCount = sizeof(kFlagTable) / sizeof(kFlagTable[0]);

}  // namespace quatnav
