// quatnav: GpsInsFilter's parameters and state (nav/gps_ins.hpp), each field declared once
// (core/fields.hpp): the binding, the dict round trip and the Python tables come from these rows.
#pragma once

#include <array>
#include <cstdint>

#include "../../core/fields.hpp"
#include "../../core/quaternion.hpp"
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
  /* The gyro's scale-factor and misalignment errors as an attitude noise that grows with the rate \
     (gpsins_Qc_rate, model.hpp); the attitude filters' name and unit */                            \
  X(S, gyro_rate_noise, S(0), "1/sqrt(Hz)",                                                           \
    "rate-proportional attitude process noise: density gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only") \
  /* Scale-factor states (GpsInsFilter<S, true>, Python scale_factors=True; unused otherwise) */      \
  X(S, gyro_scale_noise, S(1.0e-5), "1/sqrt(s)", "gyro scale-factor random-walk density (scale-factor states only)") \
  X(S, acc_scale_noise, S(1.0e-5), "1/sqrt(s)", "accelerometer scale-factor random-walk density (scale-factor states only)") \
  X(S, init_gyro_scale_sigma, S(5.0e-3), "1", "gyro scale-factor one-sigma at the start of navigation (scale-factor states only)") \
  X(S, init_acc_scale_sigma, S(3.0e-3), "1", "accelerometer scale-factor one-sigma at the start of navigation (scale-factor states only)") \
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
  /* the altimeter offset (its reading minus the ellipsoidal height) is the 16th state, a random walk */ \
  X(S, baro_offset_noise, S(0.02), "m/sqrt(s)", "random-walk density of the altimeter offset")          \
  X(S, compass_sigma, S(0.035), "rad", "one-sigma of a compass heading")                                \
  X(S, declination, S(0), "rad", "magnetic declination, east of true north (added to compass headings)") \
  X(S, gate_gps_pos, S(21.108), "1 (chi-square, 3 dof)", "NIS gate of the GPS position (0: off)")       \
  X(S, gate_gps_vel, S(21.108), "1 (chi-square, 3 dof)", "NIS gate of the GPS velocity (0: off)")       \
  X(S, gate_baro, S(15.137), "1 (chi-square, 1 dof)", "NIS gate of the altimeter (0: off)")             \
  X(S, gate_compass, S(15.137), "1 (chi-square, 1 dof)", "NIS gate of the compass (0: off)")            \
  /* What the GNSS model leaves out enters R: a floor on the fix's one-sigma set by the receiver's \
     solution kind (GnssSolution), the uncertainty of its time on the IMU clock (times the antenna's \
     velocity or acceleration), the lever arm's. */                                                   \
  X(S, gps_pos_sigma_min, S(0.01), "m",                                                                 \
    "floor of a GPS position one-sigma (given or per fix) of an RTK-fixed solution or one of unknown kind") \
  X(S, gps_float_sigma_min, S(0.3), "m", "floor of a GPS position one-sigma of an RTK-float solution") \
  X(S, gps_dgnss_sigma_min, S(0.6), "m", "floor of a GPS position one-sigma of a DGNSS, SBAS or PPP solution") \
  X(S, gps_single_sigma_min, S(1.5), "m", "floor of a GPS position one-sigma of a single (standalone) solution") \
  X(S, gps_vertical_floor_ratio, S(2), "1",                                                            \
    "floor of a GPS position's down one-sigma over the north and east floor of its solution kind")    \
  /* The errors of an RTK-float, DGNSS or single solution wander (atmosphere, multipath, the float \
     ambiguities): fixes a fraction of gps_error_tau apart repeat most of one error. Such a fix's R is \
     raised by the factor (1 + rho) / (1 - rho), rho = exp(-dt / tau), dt the time since the last   \
     accepted position fix: a stretch of them then weighs as one fix per 2 tau (the variance of the \
     mean of a first-order Gauss-Markov sequence). RTK-fixed fixes and those of unknown kind are    \
     taken as white. */                                                                               \
  X(S, gps_error_tau, S(20), "s",                                                                      \
    "correlation time of the position errors of RTK-float, DGNSS and single solutions (0: white)")    \
  X(S, gps_vel_sigma_min, S(0.01), "m/s", "floor of a GPS velocity one-sigma (given or per fix)")        \
  X(S, gps_time_offset, S(0), "s",                                                                      \
    "added to the GNSS times to put them on the IMU clock (a receiver latency L: -L)")                 \
  X(S, gps_time_sigma, S(0.005), "s", "one-sigma of the GNSS time on the IMU clock")                    \
  X(S, lever_arm_sigma, S(0), "m", "one-sigma of each lever-arm component")                             \
  /* Robust weighting of the GNSS aids (Huber): an innovation component beyond k of its own sigma   \
     has its variance raised by |z| / k, and the chi-square gate judges the fix so weighted: only   \
     a gross outlier is refused (IGG-III). k = 3: no fix of the simulated RTK car refused (4 RTK-   \
     fixed positions of 32,232 with 0), every other figure of the car, NaveGo and the real walk     \
     within its noise (docs/GPSINS_DATA.md). */                                                       \
  X(S, gps_robust_k, S(3), "1",                                                                         \
    "Huber threshold of the GNSS aids: an innovation component beyond it (in its sigmas) is down-weighted, and the gate judges the fix so weighted (0: off)") \
  /* A GNSS fix that fails its gate right after one that failed too is not an outlier: the INS is   \
     off. Its position and velocity covariance is inflated until the fix is consistent (NIS = rows), and the fix applied; \
     beyond inflate_max the position (velocity) is reset to the fix. */                                \
  X(S, inflate_after, S(1), "1",                                                                        \
    "consecutive gate rejections of a GNSS aid after which the next failing fix inflates the covariance (0: never)") \
  X(S, inflate_max, S(1e4), "1", "largest covariance inflation; a fix that needs more resets the state to it") \
  /* Innovation-based adaptation: a process-noise scale raised while the GNSS NIS stays above 3 per \
     row, lowered while it stays below 1/3 */                                                          \
  X(S, adapt_q_max, S(100), "1", "largest process-noise scale of the innovation-based adaptation (1: off)") \
  X(S, adapt_gain, S(0.2), "1", "step of the adaptation per GNSS update (natural log of the scale)")     \
  X(S, align_time, S(2.0), "s", "duration of the static alignment (still samples; motion restarts it)")  \
  X(S, min_speed_for_heading, S(1.0), "m/s", "GPS speed above which the heading comes from the GPS track") \
  X(bool, heading_from_gps, true, "-", "initialize the heading from the GPS track (without compass)")    \
  /* Alignment in motion (gps_ins/alignment.hpp): TRIAD of the GNSS velocity change against the     \
     specific force over a window, the course for the heading; with positions only, the course    \
     between fixes at least align_course_distance apart. */                                        \
  X(S, align_motion_time, S(1.0), "s", "shortest window of an alignment in motion")                     \
  X(S, align_motion_max, S(10.0), "s", "longest window of an alignment in motion (then it restarts)")   \
  X(S, align_course_distance, S(10.0), "m",                                                             \
    "distance between the position fixes whose course gives the heading (position-only GNSS)")        \
  X(S, align_level_sigma, S(0.1), "rad", "roll/pitch one-sigma after an alignment in motion without GNSS velocity") \
  /* Rest: |w - lp(w)| < rest_gyr_th, |f - lp(f)| < rest_acc_th, ||lp(f)| - g| < rest_acc_th, held */ \
  X(S, rest_gyr_th, S(0.05), "rad/s", "rest: largest deviation of the gyro from its low-pass")          \
  X(S, rest_acc_th, S(0.5), "m/s^2",                                                                    \
    "rest: largest deviation of the accelerometer from its low-pass and of its norm from gravity")   \
  X(S, rest_time, S(1.0), "s", "rest: shortest duration")                                               \
  X(S, rest_tau, S(0.5), "s", "rest: low-pass time constant")                                            \
  X(S, rest_speed, S(0.3), "m/s",                                                                       \
    "rest: largest speed (the GNSS's before navigation; during it the INS's, plus three "            \
    "sigma up to this value again)")                                                                   \
  /* Pseudo-measurements: at rest zero velocity and zero angular rate (w_ie), while moving the     \
     non-holonomic constraint (no lateral or vertical body velocity at the IMU) */                  \
  X(bool, zupt, true, "-", "zero-velocity and zero-angular-rate updates at rest")                       \
  X(S, zupt_sigma, S(0.02), "m/s", "one-sigma of the velocity at rest")                                 \
  X(S, zaru_sigma, S(0.005), "rad/s", "one-sigma of the angular rate at rest beyond the gyro's white noise") \
  X(S, gate_zupt, S(21.108), "1 (chi-square, 3 dof)", "NIS gate of the zero-velocity and zero-rate updates (0: off)") \
  X(bool, nhc, false, "-", "non-holonomic constraint: no lateral or vertical velocity (wheeled vehicles)") \
  X(S, nhc_sigma, S(0.1), "m/s", "one-sigma of the lateral and vertical body velocity")                 \
  X(S, gate_nhc, S(18.421), "1 (chi-square, 2 dof)", "NIS gate of the non-holonomic constraint (0: off)") \
  X(bool, nhc_auto, true, "-",                                                                          \
    "apply the non-holonomic constraint once the vehicle has shown it: nhc_auto_time s of GNSS-aided "  \
    "motion above nhc_auto_speed with the lateral and vertical body velocity within nhc_auto_limit "     \
    "(RMS); its R is then the larger of nhc_sigma^2 and that mean square")                               \
  X(S, nhc_auto_speed, S(3), "m/s", "non-holonomic evidence: slowest speed that counts")                \
  X(S, nhc_auto_time, S(20), "s", "non-holonomic evidence: duration needed (the mean square's time constant is a quarter of it)") \
  X(S, nhc_auto_limit, S(0.3), "m/s", "non-holonomic evidence: largest RMS lateral and vertical body velocity (above twice it the evidence is lost)") \
  X(S, nhc_auto_rate, S(0.05), "rad/s",                                                                 \
    "non-holonomic evidence: largest body yaw rate at which the IMU's mounting (its mean lateral and vertical velocity per forward speed) is learned") \
  X(S, nhc_mount_tau_yaw, S(300), "s",                                                                   \
    "time constant over which the IMU's mounting in yaw (lateral velocity per forward speed) is learned from straight GNSS-aided driving (0: not learned)") \
  X(S, nhc_mount_tau_pitch, S(20), "s",                                                                  \
    "time constant over which the IMU's mounting in pitch (vertical velocity per forward speed) is learned from straight GNSS-aided driving (0: not learned)") \
  X(bool, nhc_lateral_aided, false, "-",                                                                 \
    "apply the learned non-holonomic constraint's lateral row while GNSS-aided too (default: in outages only; its mounting yaw is learned from the aided heading)") \
  X(S, nhc_arm, S(0), "m",                                                                               \
    "largest distance of the IMU from the non-slipping axle: the constraint's lateral variance gains (w_z nhc_arm)^2 (0: off)") \
  X(Vec3<S>, nhc_lever_b, Vec3<S>::Zero(), "m",                                                         \
    "the non-slipping point (the middle of the rear axle) relative to the IMU, body FRD: the constraint holds the velocity there, v_b + w x nhc_lever_b") \
  X(S, pseudo_interval, S(0.1), "s", "shortest interval between two zero-velocity or non-holonomic updates") \
  X(S, odometer_sigma, S(0.05), "m/s", "one-sigma of an odometer speed")                                \
  X(S, gate_odometer, S(15.137), "1 (chi-square, 1 dof)", "NIS gate of the odometer (0: off)")          \
  /* Raw magnetometer: heading tilt-compensated with the filter's attitude; disturbance tests on its \
     norm and dip against a reference learned over mag_ref_samples samples */                      \
  X(S, mag_heading_sigma, S(0.05), "rad", "one-sigma of a magnetometer heading")                        \
  X(bool, mag_heading_only, true, "-",                                                                  \
    "the magnetometer corrects the heading only (its tilt terms go into R; false: the full row)")     \
  X(S, mag_norm_tol, S(0.1), "1", "reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off)")    \
  X(S, mag_dip_tol, S(0.1), "rad", "reject the magnetometer when its dip differs from the reference by more (0: off)") \
  X(int, mag_ref_samples, 50, "1", "magnetometer samples over which the reference norm and dip are averaged") \
  X(S, gate_mag, S(15.137), "1 (chi-square, 1 dof)", "NIS gate of the magnetometer heading (0: off)")   \
  /* The sensor model */                                                                               \
  X(Mat3<S>, imu_rotation, Mat3<S>::Identity(), "1",                                                    \
    "rotation from the IMU axes to the body axes: body = imu_rotation imu")                           \
  X(S, max_coast, S(10.0), "s", "longest IMU gap the batch run coasts across (in steps of at most max_dt)") \
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

/// What one aid sample did (the per-sample report of the batch run and of every update).
enum class GpsInsDecision : std::uint8_t {
  None = 0,      ///< no update (before alignment, or the sample gave none)
  Accepted = 1,  ///< applied
  Rejected = 2,  ///< refused by its gate (an isolated outlier)
  Inflated = 3,  ///< applied after the covariance was inflated to make it consistent
  Reset = 4,     ///< the state was reset to the fix (the inflation needed exceeded inflate_max)
  Skipped = 5,   ///< invalid input, or the update failed (state untouched)
  Aligned = 6,   ///< used by the alignment (heading, start of navigation)
  Weighted = 7,  ///< applied with its variance raised where a component lay beyond gps_robust_k sigmas
};

inline constexpr int kGpsInsDecisions = 8;
/// The Python name of a decision (quatnav.filters.tables.GPSINS_DECISIONS, tested equal).
inline const char* to_string(GpsInsDecision d) {
  switch (d) {
    case GpsInsDecision::None: return "none";
    case GpsInsDecision::Accepted: return "accepted";
    case GpsInsDecision::Rejected: return "rejected";
    case GpsInsDecision::Inflated: return "inflated";
    case GpsInsDecision::Reset: return "reset";
    case GpsInsDecision::Skipped: return "skipped";
    case GpsInsDecision::Aligned: return "aligned";
    case GpsInsDecision::Weighted: return "weighted";
  }
  return "unknown";
}

/// The receiver's solution kind of a GNSS fix (RTKLIB's Q, NMEA GGA's fix quality, PX4's
/// fix_type; quatnav.filters.gpsins.gnss_solution maps them): it sets the floor of the fix's
/// one-sigma (gps_pos_sigma_min, gps_float_sigma_min, gps_dgnss_sigma_min, gps_single_sigma_min).
/// The Python names: quatnav.filters.tables.GNSS_SOLUTIONS (tested equal).
enum class GnssSolution : std::uint8_t { Unknown = 0, RtkFixed = 1, RtkFloat = 2, Dgnss = 3, Single = 4 };
inline constexpr int kGnssSolutions = 5;
inline const char* to_string(GnssSolution k) {
  switch (k) {
    case GnssSolution::Unknown: return "unknown";
    case GnssSolution::RtkFixed: return "rtk_fixed";
    case GnssSolution::RtkFloat: return "rtk_float";
    case GnssSolution::Dgnss: return "dgnss";
    case GnssSolution::Single: return "single";
  }
  return "unknown";
}

/// The kinds of aid, the index of each in the counters.
enum class GpsInsAid : std::uint8_t {
  GpsPos = 0, GpsVel = 1, Baro = 2, BaroVd = 3, Compass = 4, Mag = 5, Zupt = 6, Zaru = 7, Nhc = 8, Odometer = 9
};
inline constexpr int kGpsInsAidKinds = 10;
/// Python names of the aid kinds, in GpsInsAid order (the keys of the counters).
inline constexpr const char* kGpsInsAidNames[kGpsInsAidKinds] = {"gps_pos", "gps_vel", "baro", "baro_vd", "compass",
                                                                 "mag",     "zupt",    "zaru", "nhc",     "odometer"};

/// How the filter was aligned (state().align_method) and where its heading came from
/// (state().heading_source).
enum class GpsInsAlignment : std::uint8_t {
  None = 0,           ///< not aligned yet
  Static = 1,         ///< levelled at rest from the accelerometer
  GnssVelocity = 2,   ///< in motion: TRIAD of the GNSS velocity change against the specific force
  GnssCourse = 3,     ///< in motion, positions only: level from the mean specific force, large sigma
  Given = 4,          ///< set_initial() or reset()
};
enum class GpsInsHeading : std::uint8_t {
  None = 0, Compass = 1, Magnetometer = 2, GnssVelocity = 3, GnssCourse = 4, Given = 5
};
inline const char* to_string(GpsInsAlignment a) {
  switch (a) {
    case GpsInsAlignment::None: return "none";
    case GpsInsAlignment::Static: return "static";
    case GpsInsAlignment::GnssVelocity: return "gnss_velocity";
    case GpsInsAlignment::GnssCourse: return "gnss_course";
    case GpsInsAlignment::Given: return "given";
  }
  return "unknown";
}
inline const char* to_string(GpsInsHeading h) {
  switch (h) {
    case GpsInsHeading::None: return "none";
    case GpsInsHeading::Compass: return "compass";
    case GpsInsHeading::Magnetometer: return "magnetometer";
    case GpsInsHeading::GnssVelocity: return "gnss_velocity";
    case GpsInsHeading::GnssCourse: return "gnss_course";
    case GpsInsHeading::Given: return "given";
  }
  return "unknown";
}

/// Counts of measurement outcomes per aid kind (GpsInsAid order).
using GpsInsCounts = std::array<std::uint32_t, kGpsInsAidKinds>;
#define QUATNAV_GPSINS_COUNTERS(X)                                                                    \
  X(GpsInsCounts, accepted, GpsInsCounts{}, "-", "updates applied, per aid kind")                      \
  X(GpsInsCounts, rejected, GpsInsCounts{}, "-", "updates refused by the chi-square gate, per aid kind") \
  X(GpsInsCounts, skipped, GpsInsCounts{}, "-", "samples skipped as invalid (or failed updates), per aid kind") \
  X(GpsInsCounts, inflated, GpsInsCounts{}, "-", "updates applied after a covariance inflation, per aid kind") \
  X(GpsInsCounts, weighted, GpsInsCounts{}, "-", "updates applied down-weighted (robust weighting), per aid kind") \
  X(GpsInsCounts, resets, GpsInsCounts{}, "-", "state resets to a fix, per aid kind")

struct GpsInsCounters {
  QUATNAV_FIELDS(GpsInsCounters, QUATNAV_GPSINS_COUNTERS)
};

/// Everything the filter holds (plain data; state()/set_state() round-trip exactly). The nominal
/// navigation state `nav` and the counters appear flattened in the dict of get_state().
#define QUATNAV_GPSINS_STATE(X)                                                                       \
  X(StrapdownState<S>, nav, StrapdownState<S>(), "-", "nominal navigation state")                      \
  X(Vec3<S>, acc_bias, Vec3<S>::Zero(), "m/s^2", "accelerometer bias estimate")                         \
  X(Vec3<S>, gyro_bias, Vec3<S>::Zero(), "rad/s", "gyro bias estimate")                                 \
  X(Vec3<S>, acc_scale, Vec3<S>::Zero(), "1", "accelerometer scale-factor estimate (scale-factor states only; else 0)") \
  X(Vec3<S>, gyro_scale, Vec3<S>::Zero(), "1", "gyro scale-factor estimate (scale-factor states only; else 0)") \
  X(Mat16, P, Mat16::Zero(), "state units^2",                                                           \
    "error-state covariance [dp, dv, psi, db_a, db_g, d_baro_offset] (and ds_a, ds_g with scale-factor states)") \
  X(double, t, 0.0, "s", "filter time: sum of the accepted IMU intervals")                              \
  X(Vec3<S>, omega_b, Vec3<S>::Zero(), "rad/s", "last bias-corrected body rate")                         \
  X(Vec3<S>, f_b, Vec3<S>::Zero(), "m/s^2", "last bias-corrected specific force")                        \
  X(double, dt_last, 0.0, "s", "last accepted IMU interval")                                            \
  X(GpsInsPhase, phase, GpsInsPhase::Aligning, "-", "alignment phase: 0 aligning, 1 levelled, 2 navigating") \
  X(Vec3<double>, align_sum, Vec3<double>::Zero(), "m/s", "sum of f_ib_b dt while aligning")             \
  X(double, align_time, 0.0, "s", "time accumulated while aligning")                                    \
  X(bool, heading_known, false, "-", "levelled: the yaw has been set")                                  \
  X(bool, baro_offset_valid, false, "-", "the altimeter offset state has been initialized")             \
  X(double, baro_offset, 0.0, "m", "altimeter offset estimate: its reading minus the ellipsoidal height") \
  X(double, baro_last, 0.0, "m", "latest altimeter height seen")                                        \
  X(bool, baro_last_valid, false, "-", "baro_last holds a height")                                      \
  X(bool, baro_ref_valid, false, "-", "a derivative baseline has started")                              \
  X(double, baro_ref_h, 0.0, "m", "altimeter height at the start of the derivative baseline")           \
  X(double, baro_ref_t, 0.0, "s", "filter time at the start of the derivative baseline")                \
  X(S, q_scale, S(1), "1", "process-noise scale of the innovation-based adaptation")                  \
  X(GpsInsAlignment, align_method, GpsInsAlignment::None, "-", "how the attitude was aligned")          \
  X(GpsInsHeading, heading_source, GpsInsHeading::None, "-", "where the initial heading came from")     \
  X(double, level_t, -1.0, "s", "filter time of the levelling (-1: not yet)")                           \
  X(double, nav_start_t, -1.0, "s", "filter time navigation started (-1: not yet)")                     \
  X(bool, rest_init, false, "-", "the rest low-passes hold a value")                                    \
  X(Vec3<S>, rest_gyr_lp, Vec3<S>::Zero(), "rad/s", "low-passed bias-corrected rate (rest test)")        \
  X(Vec3<S>, rest_acc_lp, Vec3<S>::Zero(), "m/s^2", "low-passed bias-corrected specific force (rest test)") \
  X(double, rest_t, 0.0, "s", "time the IMU has been still")                                            \
  X(Vec3<S>, rest_v, Vec3<S>::Zero(), "m/s",                                                           \
    "velocity of the rest test: the INS velocity, in an outage only its changes with an acceleration")  \
  X(S, gnss_speed, S(-1), "m/s", "last horizontal GNSS speed before navigation (-1: none)")              \
  X(double, gnss_speed_t, 0.0, "s", "filter time of that speed")                                        \
  X(double, pseudo_t, -1e9, "s", "filter time of the last zero-velocity or non-holonomic update")         \
  X(double, gnss_t, -1e9, "s", "filter time of the last accepted GNSS position or velocity update")     \
  X(double, gps_pos_t, -1e9, "s", "time of validity of the last accepted GNSS position")                \
  X(S, nhc_ms, S(-1), "m^2/s^2",                                                                        \
    "mean square lateral and vertical body velocity in GNSS-aided motion, about the mounting's (-1: none yet)") \
  X(S, nhc_ky, S(0), "1", "mean lateral body velocity per forward speed in straight GNSS-aided motion (the mounting's yaw)") \
  X(S, nhc_kz, S(0), "1", "mean vertical body velocity per forward speed in straight GNSS-aided motion (the mounting's pitch)") \
  X(double, nhc_t, 0.0, "s", "GNSS-aided motion with nhc_ms within nhc_auto_limit^2 (non-holonomic evidence)") \
  X(bool, mot_valid, false, "-", "a motion window is open (alignment in motion)")                       \
  X(double, mot_lat, 0.0, "rad", "latitude of the fix that opened the motion window")                   \
  X(double, mot_lon, 0.0, "rad", "longitude of that fix")                                               \
  X(double, mot_h, 0.0, "m", "height of that fix")                                                      \
  X(bool, mot_has_v, false, "-", "that fix had a velocity")                                             \
  X(Vec3<S>, mot_v0, Vec3<S>::Zero(), "m/s", "its velocity")                                            \
  X(Quat<S>, mot_q, quat::identity<S>(), "1", "rotation from the window's first body frame to the body") \
  X(Vec3<double>, mot_dv, Vec3<double>::Zero(), "m/s", "specific-force velocity increment in the window's first body frame") \
  X(double, mot_T, 0.0, "s", "duration of the motion window")                                           \
  X(bool, init_v_valid, false, "-", "set_initial() gave a velocity")                                    \
  X(Vec3<S>, init_v, Vec3<S>::Zero(), "m/s", "the velocity set_initial() gave")                         \
  X(S, mag_ref_norm, S(0), "field unit", "reference magnetometer norm")                                 \
  X(S, mag_ref_dip, S(0), "rad", "reference dip of the magnetic field")                                  \
  X(std::uint32_t, mag_ref_n, 0u, "-", "samples averaged into the reference")                           \
  X(GpsInsCounts, reject_run, GpsInsCounts{}, "-", "consecutive gate rejections, per aid kind")          \
  X(GpsInsCounters, counters, GpsInsCounters(), "-", "outcomes per aid kind")

/// SF: with the scale-factor states (22 error states instead of 16; gps_ins/model.hpp).
template <class S, bool SF = false> struct GpsInsState {
  static constexpr int kStates = SF ? 22 : 16;
  using Mat16 = Mat<S, kStates, kStates>;
  QUATNAV_FIELDS(GpsInsState, QUATNAV_GPSINS_STATE)
};

}  // namespace quatnav
