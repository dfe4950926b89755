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
// Qc: accelerometer white noise on dv, gyro white noise on psi and, with gyro_rate_noise, a term
// that grows with the rate for the gyro's scale-factor and misalignment errors (a full 3 x 3 block,
// detail::gpsins_Qc_rate, off by default), bias driving noise on db (all scaled by the
// adaptation's q_scale, see below), the offset's random walk.
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
//   robust weighting (Huber; gps_robust_k > 0, off by default): a fix the gate passes is
//     applied with the variance of each innovation component z_i (in its own sigmas) beyond
//     gps_robust_k raised by |z_i| / k (decision Weighted): a fix a little off counts less; the
//     gate sees the fix as it came;
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

#include "gps_ins/batch.hpp"
#include "gps_ins/filter.hpp"
