// quatnav: 13-state velocity / quaternion / bias navigation filter with three time updates
// (Seong 2012, "A nonlinear navigation filter for biomimetic robot"; called paper 002 in the docs).
//
// State x = [v_n (3), q_nb (4), b_a (3), b_g (3)] (eq. 9): NED velocity with respect to the Earth
// (m/s), the attitude quaternion q_nb (Hamilton, [w, x, y, z], body FRD to NED), the
// accelerometer bias (m/s^2) and the gyro bias (rad/s). Inputs u = [f_ib_b, omega_ib_b] (eq. 10):
// the measured specific force (m/s^2) and angular rate (rad/s).
//
// Mechanization, eq. (1)-(3), with the sensor model f_ib_b = f_meas - b_a, omega_ib_b =
// omega_meas - b_g (eq. 6-7):
//     v_dot = C_nb(q) (f_meas - b_a) - (2 omega_ie_n + omega_en_n) x v_n + g_n           (1)
//     q_dot = 1/2 q * [0, omega_meas - b_g] - 1/2 [0, omega_in_n] * q,  omega_in = ie + en  (3)
//     b_a_dot = 0, b_g_dot = 0                                                            (7)
// discretized by one Euler step (eq. 12): x+ = x + dt f(x, u). C_nb(q) is the homogeneous quadratic
// form of eq. (5) (q0^2 + q1^2 - q2^2 - q3^2, ...), which is what makes f a polynomial in q.
//
// Deviations from the paper, each deliberate:
//  * Sign of the biases: the paper writes f = f_meas + delta_f (eq. 6), i.e. its states nabla and
//    rho are minus the sensor biases. We estimate the sensor biases b_a = -nabla, b_g = -rho (the
//    convention of every quatnav filter); the second derivatives below change sign accordingly.
//  * Eq. (3) writes q_dot = 1/2 C(q) {omega_ib_b - C_bn (omega_ie + omega_en)}. For a unit
//    quaternion q * [0, C_bn w] = [0, w] * q, so we use the right-hand form above: it is the same
//    kinematics, but bilinear in q (the paper's appendix instead freezes beta = omega_nb_b at the
//    estimate, eq. A.5, dropping the q-dependence of C_bn from the Jacobian).
//  * The Earth terms omega_ie_n, omega_en_n and g_n are inputs of a step: they are evaluated once
//    per step from the carried position (lat, h) and the prior velocity mean, like alpha in
//    eq. (A.4) and (A.8). The dependence of omega_en on v_n (|v|/R, about 3e-7 /s at 2 m/s) is
//    left out of F and of the second derivatives, as in eq. (A.8).
//  * The paper's appendix (eq. A.16-A.20) lists the second derivatives with duplicated and
//    mislabelled blocks (two blocks titled d2F_V/dq2 d(delta f_y), q1/q2 rows swapped, F_q entries
//    with three rows). They are derived anew here (nav13_second_order_term, nav13_hessian): the
//    only non-zero second derivatives of the Euler-discretized f_d are
//        d2 v+ / dq_i dq_j    = dt d/dq_j [J(q, a)]_{:, i}            (a = f_meas - b_a)
//        d2 v+ / dq_i db_a,k  = -dt [J(q, e_k)]_{:, i}
//        d2 q+ / dq_i db_g,k  = -dt/2 [Xi(e_i)]_{:, k}
//    with J(q, a) = d(C(q) a)/dq (eq. A.9) and Xi(q) v = q * [0, v]; each is checked against
//    finite differences in the tests.
//  * The measurement of yaw, eq. (14), uses atan2 (the full circle) and the innovation is wrapped
//    to (-pi, pi]. The correction eq. (22)-(23) uses the shared Joseph-form kalman_correct; the
//    quaternion is renormalized afterwards with the covariance projected by the normalization's
//    Jacobian, and likewise after every time update (the Euler step does not keep |q| = 1).
//  * Rotation term of the velocity increment (eq. 12). The inputs are means over the step (an
//    IMU's increments divided by dt), but the Euler step applies the specific force with the
//    attitude at the start of the step: v+ = v + dt C(q_k) a. The true increment is
//    int C(q(t)) a dt = dt C(q_k) (a + dt/2 w x a) + O(dt^3), so the Euler step is short by
//    dt^2/2 C (w x a) every step, an error that does not average out while the body rotates
//    (with w about 0.2 rad/s and |a| = g it is 0.01 m/s^2, the size of 1 mrad of tilt): on a
//    long run with a rotating attitude the mean attitude NEES was about 8 and the velocity NEES
//    about 6-7 instead of 3 (docs/ROBUSTNESS.md). predict() therefore adds the first-order
//    rotation correction of strapdown.hpp (Savage 2000, ch. 7; 1/2 dtheta x dv) to the measured
//    specific force, at the bias estimates:
//        f_ib_b <- f_ib_b + dt/2 (omega_ib_b - b_g) x (f_ib_b - b_a)   (nav13_rotation_correction)
//    before the time update; nav13_rhs, nav13_f and their derivatives are those of eq. (12) with
//    that input (the correction's own dependence on b_a, b_g is of order dt^2 and is left out
//    of F, like the Earth terms).
//  * The paper's Q (eq. 12, 19) is the covariance of w_k; we take white-noise densities and use
//    Q_k = dt G diag(sigma_a^2 I, sigma_g^2 I) G^T with G of eq. (11) (the 4x3 block is
//    1/2 Xi(q)), plus optional bias random walks (0 by default, eq. 7).
//
// Known limitation (docs/NAV13.md, "Consistency"): in straight, unaccelerated motion a horizontal
// accelerometer-bias error db_h is compensated by a tilt error and unobservable; the second-order
// term -C (dtheta x db_a) of eq. (1) then puts |db_h|^2 / (2 g) into the vertical channel, where it
// is taken for the vertical bias (4 ug on average for 2000 ug per axis). No Gaussian time update
// (EKF, the second-order mean of eq. 16-17, UKF) represents it: the vertical-bias one-sigma is
// optimistic by about that much while db_h is large and unobservable.
//
// Time updates (template parameter TU):
//  * TimeUpdate::Ekf          x+ = f_d(x), P+ = F P F^T + G Q G^T             (eq. 19-20)
//  * TimeUpdate::SecondOrder  x+ = f_d(x) + 1/2 sum_ij P_ij d2f_d/dx_i dx_j     (eq. 16-17)
//                             P+ as the EKF (eq. 19-20)
//  * TimeUpdate::Ukf          unscented transform (unscented.hpp) in a 12-dimensional error state
//                             [dv, dtheta, db_a, db_g] with q = q_mean * exp(dtheta) (body-frame
//                             rotation vector). Every sigma point is a unit quaternion; the
//                             propagated points are renormalized, their mean quaternion is the
//                             normalized weighted sum refined by one step of the mean rotation
//                             vector, and the covariance is mapped back to the 13-state form by
//                             dq = 1/2 Xi(q) dtheta. Why not sigma points on the 4 quaternion
//                             components directly: the 13x13 covariance is singular along q
//                             (|q| = 1), so its Cholesky factor does not exist, and points off the
//                             unit sphere are not attitudes. 2*12+1 = 25 points, fixed size.
#pragma once

#include <cmath>
#include <limits>
#include <cstddef>
#include <cstdint>

#include "../core/checks.hpp"
#include "../core/commit.hpp"
#include "../core/covariance.hpp"
#include "../core/earth.hpp"
#include "../core/fields.hpp"
#include "../core/kalman.hpp"
#include "../core/quat_block.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"
#include "../core/unscented.hpp"

namespace quatnav {

/// Which time update NavFilter13 uses.
enum class TimeUpdate : std::uint8_t { Ekf = 0, SecondOrder = 1, Ukf = 2 };

inline const char* to_string(TimeUpdate t) {
  switch (t) {
    case TimeUpdate::Ekf: return "ekf";
    case TimeUpdate::SecondOrder: return "second_order";
    case TimeUpdate::Ukf: return "ukf";
  }
  return "unknown";
}

/// Parameters of NavFilter13. Every field has its unit and default. The noise defaults are the
/// paper's section IV values: (30 ug)^2 and (0.3 deg/h)^2 per sample at 100 Hz, velocity
/// (0.1 ft/s)^2, yaw (2 deg)^2.
// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_NAV13_PARAMS(X)                                                                       \
  X(S, acc_noise, S(2.9420e-5), "m/s^2/sqrt(Hz)", "accelerometer white-noise density (velocity random walk)") \
  X(S, gyro_noise, S(1.4544e-7), "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)")      \
  X(S, acc_bias_noise, S(0), "m/s^3/sqrt(Hz)", "accelerometer-bias random-walk density")                \
  X(S, gyro_bias_noise, S(0), "rad/s^2/sqrt(Hz)", "gyro-bias random-walk density")                      \
  X(S, gps_vel_sigma, S(0.03048), "m/s", "one-sigma of each measured velocity component")               \
  X(S, yaw_sigma, S(0.034906585), "rad", "one-sigma of the measured yaw")                                \
  X(S, ukf_alpha, S(1), "1", "unscented transform: alpha")                                              \
  X(S, ukf_beta, S(2), "1", "unscented transform: beta")                                                \
  X(S, ukf_kappa, S(0), "1", "unscented transform: kappa (alpha^2 (12 + kappa) must be positive)")      \
  X(S, max_dt, S(1), "s", "longest accepted IMU step")                                                  \
  X(S, gyro_range, S(0), "rad/s",                                                                       \
    "gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited)")   \
  X(S, acc_range, S(0), "m/s^2", "accelerometer range per axis, as gyro_range (0: unlimited)")           \
  /* applied only when the 12x12 error-state covariance is not positive definite above it */           \
  X(S, cov_floor, S(0), "state units^2", "eigenvalue floor of the error covariance (0: off)")            \
  X(bool, earth_rotation, true, "-", "include the Earth rate, transport rate and Coriolis terms")

template <class S> struct NavFilter13Params {
  QUATNAV_FIELDS(NavFilter13Params, QUATNAV_NAV13_PARAMS)
};

// The carried position is double for every S (as GpsInsFilter's): a float latitude resolves
// 0.38 m and an increment v_N dt / (R_M + h) below 19 m/s at 100 Hz rounds away entirely.
#define QUATNAV_NAV13_STATE(X)                                                                        \
  X(Vec3<S>, v_n, Vec3<S>::Zero(), "m/s", "NED velocity")                                              \
  X(Quat<S>, q_nb, quat::identity<S>(), "1", "attitude q_nb [w, x, y, z]")                              \
  X(Vec3<S>, acc_bias, Vec3<S>::Zero(), "m/s^2", "accelerometer bias b_a")                             \
  X(Vec3<S>, gyro_bias, Vec3<S>::Zero(), "rad/s", "gyro bias b_g")                                     \
  X(Mat13, P, Mat13::Identity(), "state units^2", "covariance of [v_n, q_nb, b_a, b_g]")                \
  X(double, lat, 0.0, "rad", "carried geodetic latitude (not estimated: integrated from v_n)")          \
  X(double, lon, 0.0, "rad", "carried longitude")                                                       \
  X(double, h, 0.0, "m", "carried height above the ellipsoid")                                          \
  X(bool, initialized, false, "-", "the filter has a state")

/// The complete filter state; state()/set_state() round-trip exactly.
template <class S> struct NavFilter13State {
  using Mat13 = Mat<S, 13, 13>;
  QUATNAV_FIELDS(NavFilter13State, QUATNAV_NAV13_STATE)
};

/// The inputs of one Euler step: sensor readings, step length and the Earth terms.
template <class S> struct Nav13Input {
  Vec3<S> f_ib_b = Vec3<S>::Zero();      ///< measured specific force [m/s^2]
  Vec3<S> omega_ib_b = Vec3<S>::Zero();  ///< measured angular rate [rad/s]
  S dt = S(0);                           ///< step [s]
  Vec3<S> omega_ie_n = Vec3<S>::Zero();  ///< Earth rate in NED [rad/s]
  Vec3<S> omega_en_n = Vec3<S>::Zero();  ///< transport rate in NED [rad/s]
  Vec3<S> g_n = Vec3<S>::Zero();         ///< gravity in NED [m/s^2]
};

namespace detail {

template <class S> using Vec13 = Vec<S, 13>;
template <class S> using Mat13 = Mat<S, 13, 13>;
template <class S> using Vec12 = Vec<S, 12>;
template <class S> using Mat12 = Mat<S, 12, 12>;

/// Index of the first component of each block of the 13-state.
constexpr int kV = 0, kQ = 3, kBa = 7, kBg = 10;

/// Eq. (5) with every product q_i q_j replaced by M_ij (M symmetric 4x4): C(q) = quad_rotmat(q q^T).
/// Linear in M, so E[C(q)] = quad_rotmat(q_mean q_mean^T + P_qq) for a Gaussian q.
template <class S> Mat3<S> quad_rotmat(const Mat4<S>& M) {
  const S ww = M(0, 0), xx = M(1, 1), yy = M(2, 2), zz = M(3, 3);
  const S wx = M(0, 1), wy = M(0, 2), wz = M(0, 3), xy = M(1, 2), xz = M(1, 3), yz = M(2, 3);
  Mat3<S> c;
  c << ww + xx - yy - zz, S(2) * (xy - wz), S(2) * (xz + wy),
       S(2) * (xy + wz), ww - xx + yy - zz, S(2) * (yz - wx),
       S(2) * (xz - wy), S(2) * (yz + wx), ww - xx - yy + zz;
  return c;
}

/// C_nb(q) of eq. (5), the homogeneous quadratic form (equals to_rotmat for a unit q).
template <class S> Mat3<S> rotmat_hom(const Quat<S>& q) { return quad_rotmat<S>(q * q.transpose()); }

/// J(q, a) = d(C(q) a)/dq, 3x4 (eq. A.9, with f + delta f -> a). Linear in q and in a.
template <class S> Mat34<S> dCa_dq(const Quat<S>& q, const Vec3<S>& a) {
  const S w = q[0], x = q[1], y = q[2], z = q[3];
  const S ax = a[0], ay = a[1], az = a[2];
  Mat34<S> J;
  J << w * ax - z * ay + y * az, x * ax + y * ay + z * az, -y * ax + x * ay + w * az, -z * ax - w * ay + x * az,
       z * ax + w * ay - x * az, y * ax - x * ay - w * az, x * ax + y * ay + z * az, w * ax - z * ay + y * az,
       -y * ax + x * ay + w * az, z * ax + w * ay - x * az, -w * ax + z * ay - y * az, x * ax + y * ay + z * az;
  return S(2) * J;
}

/// The continuous-time right-hand side of eq. (1), (3), (7) for x = [v, q, b_a, b_g].
template <class S> Vec13<S> nav13_rhs(const Vec13<S>& x, const Nav13Input<S>& u) {
  const Vec3<S> v = x.template segment<3>(kV);
  const Quat<S> q = x.template segment<4>(kQ);
  const Vec3<S> a = u.f_ib_b - x.template segment<3>(kBa);
  const Vec3<S> w = u.omega_ib_b - x.template segment<3>(kBg);
  const Vec3<S> alpha = S(2) * u.omega_ie_n + u.omega_en_n;  // eq. (A.4)
  const Vec3<S> w_in = u.omega_ie_n + u.omega_en_n;
  Vec13<S> d = Vec13<S>::Zero();
  d.template segment<3>(kV) = rotmat_hom(q) * a - alpha.cross(v) + u.g_n;                    // (1)
  d.template segment<4>(kQ) = S(0.5) * (quat::xi(q) * w - quat::left(Quat<S>(S(0), w_in[0], w_in[1], w_in[2])) * q);  // (3)
  return d;                                                                                   // (7)
}

/// The measured specific force with the first-order rotation correction of the velocity
/// increment over a step of dt (see the header comment, eq. 12): f + dt/2 (w - b_g) x (f - b_a).
template <class S>
Vec3<S> nav13_rotation_correction(const Vec3<S>& f_ib_b, const Vec3<S>& omega_ib_b, const Vec3<S>& b_a,
                                  const Vec3<S>& b_g, S dt) {
  return f_ib_b + (dt / S(2)) * Vec3<S>(omega_ib_b - b_g).cross(Vec3<S>(f_ib_b - b_a));
}

/// f_d of eq. (12): one Euler step x + dt f(x, u) (no normalization).
template <class S> Vec13<S> nav13_f(const Vec13<S>& x, const Nav13Input<S>& u) {
  return x + u.dt * nav13_rhs(x, u);
}

/// F = df_d/dx (eq. 20; blocks eq. A.8-A.15 with our bias sign and the bilinear eq. 3).
template <class S> Mat13<S> nav13_jacobian(const Vec13<S>& x, const Nav13Input<S>& u) {
  const Quat<S> q = x.template segment<4>(kQ);
  const Vec3<S> a = u.f_ib_b - x.template segment<3>(kBa);
  const Vec3<S> w = u.omega_ib_b - x.template segment<3>(kBg);
  const Vec3<S> alpha = S(2) * u.omega_ie_n + u.omega_en_n;
  const Vec3<S> w_in = u.omega_ie_n + u.omega_en_n;
  const S dt = u.dt;
  Mat13<S> F = Mat13<S>::Identity();
  F.template block<3, 3>(kV, kV) -= dt * quat::skew(alpha);                     // (A.8)
  F.template block<3, 4>(kV, kQ) = dt * dCa_dq(q, a);                             // (A.9)
  F.template block<3, 3>(kV, kBa) = -dt * rotmat_hom(q);                          // (A.10)
  F.template block<4, 4>(kQ, kQ) +=                                               // (A.13)
      (dt / S(2)) * (quat::omega(w) - quat::left(Quat<S>(S(0), w_in[0], w_in[1], w_in[2])));
  F.template block<4, 3>(kQ, kBg) = (-dt / S(2)) * quat::xi(q);                  // (A.15)
  return F;
}

/// F P F^T (eq. 19) with only the nonzero blocks of F as nav13_jacobian builds it: the bias rows
/// are unit rows, the v rows have blocks in the v, q and b_a columns, the q rows in the q and b_g
/// columns. With T = the top 7 rows of F P:
///   T_v = F_vv P_v + F_vq P_q + F_vba P_ba,   T_q = F_qq P_q + F_qbg P_bg            (7 x 13)
///   Pn_{n,v} = T_v' F_vv^T + T_q' F_vq^T + T_ba' F_vba^T,  Pn_{n,q} = T_q' F_qq^T + T_bg' F_qbg^T
/// (T' = the columns of T), Pn_{n,b} = T_b, Pn_{b,n} = Pn_{n,b}^T, Pn_{b,b} = P_bb: 1,160
/// multiply-adds instead of the 4,394 of the dense products. Symmetric but for the rounding of
/// the 7 x 7 block (the caller symmetrizes); P must be symmetric (Pn_{b,n} is taken as Pn_{n,b}^T).
template <class S> Mat13<S> nav13_propagate(const Mat13<S>& F, const Mat13<S>& P) {
  constexpr int kN = 7;  // the rows of v and q
  const auto Fvv = F.template block<3, 3>(kV, kV);
  const auto Fvq = F.template block<3, 4>(kV, kQ);
  const auto Fvba = F.template block<3, 3>(kV, kBa);
  const auto Fqq = F.template block<4, 4>(kQ, kQ);
  const auto Fqbg = F.template block<4, 3>(kQ, kBg);
  Mat<S, kN, 13> T;
  T.template topRows<3>() = fixed_mul(Fvv, P.template middleRows<3>(kV)) + fixed_mul(Fvq, P.template middleRows<4>(kQ)) +
                            fixed_mul(Fvba, P.template middleRows<3>(kBa));
  T.template bottomRows<4>() = fixed_mul(Fqq, P.template middleRows<4>(kQ)) + fixed_mul(Fqbg, P.template middleRows<3>(kBg));
  Mat13<S> Pn;
  Pn.template block<kN, 3>(0, kV) = fixed_mul(T.template middleCols<3>(kV), Fvv.transpose()) +
                                    fixed_mul(T.template middleCols<4>(kQ), Fvq.transpose()) +
                                    fixed_mul(T.template middleCols<3>(kBa), Fvba.transpose());
  Pn.template block<kN, 4>(0, kQ) = fixed_mul(T.template middleCols<4>(kQ), Fqq.transpose()) +
                                    fixed_mul(T.template middleCols<3>(kBg), Fqbg.transpose());
  Pn.template topRightCorner<kN, 6>() = T.template rightCols<6>();
  Pn.template bottomLeftCorner<6, kN>() = T.template rightCols<6>().transpose();
  Pn.template bottomRightCorner<6, 6>() = P.template bottomRightCorner<6, 6>();
  return Pn;
}

/// 1/2 sum_ij P_ij d2f_d/dx_i dx_j (eq. 16-17), using only the non-zero blocks:
///   v rows:  dt [quad_rotmat(P_qq) a - sum_k J(q, e_k) P_{q, b_a,k}]
///   q rows: -dt/2 sum_k Xi(P_{q, b_g,k}) e_k
/// (the cross blocks appear twice in the double sum, hence no factor 1/2 on them).
template <class S> Vec13<S> nav13_second_order_term(const Vec13<S>& x, const Mat13<S>& P,
                                                    const Nav13Input<S>& u) {
  const Quat<S> q = x.template segment<4>(kQ);
  const Vec3<S> a = u.f_ib_b - x.template segment<3>(kBa);
  const S dt = u.dt;
  Vec13<S> s = Vec13<S>::Zero();
  Vec3<S> sv = quad_rotmat<S>(P.template block<4, 4>(kQ, kQ)) * a;
  for (int k = 0; k < 3; ++k) {
    sv -= dCa_dq(q, Vec3<S>(Vec3<S>::Unit(k))) * P.template block<4, 1>(kQ, kBa + k);
  }
  s.template segment<3>(kV) = dt * sv;
  Quat<S> sq = Quat<S>::Zero();
  for (int k = 0; k < 3; ++k) {
    sq += quat::xi(Quat<S>(P.template block<4, 1>(kQ, kBg + k))).col(k);
  }
  s.template segment<4>(kQ) = (-dt / S(2)) * sq;
  return s;
}

/// The dense Hessian of f_d: H[c](i, j) = d2 f_d,c / dx_i dx_j for every output component c
/// (used by the tests to check nav13_second_order_term; never on the hot path).
template <class S> void nav13_hessian(const Vec13<S>& x, const Nav13Input<S>& u, Mat13<S> (&H)[13]) {
  const Quat<S> q = x.template segment<4>(kQ);
  const Vec3<S> a = u.f_ib_b - x.template segment<3>(kBa);
  const S dt = u.dt;
  for (auto& h : H) h.setZero();
  for (int j = 0; j < 4; ++j) {
    // J(q, a) is linear in q: d/dq_j J(q, a) = J(e_j, a).
    const Mat34<S> Jj = dCa_dq(Quat<S>(Quat<S>::Unit(j)), a);
    for (int r = 0; r < 3; ++r)
      for (int i = 0; i < 4; ++i) H[kV + r](kQ + i, kQ + j) = dt * Jj(r, i);
  }
  for (int k = 0; k < 3; ++k) {
    const Mat34<S> Jk = dCa_dq(q, Vec3<S>(Vec3<S>::Unit(k)));
    for (int r = 0; r < 3; ++r)
      for (int i = 0; i < 4; ++i) {
        H[kV + r](kQ + i, kBa + k) = -dt * Jk(r, i);
        H[kV + r](kBa + k, kQ + i) = -dt * Jk(r, i);
      }
  }
  for (int i = 0; i < 4; ++i) {
    const Mat43<S> Xi = quat::xi(Quat<S>(Quat<S>::Unit(i)));
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 3; ++k) {
        H[kQ + r](kQ + i, kBg + k) = (-dt / S(2)) * Xi(r, k);
        H[kQ + r](kBg + k, kQ + i) = (-dt / S(2)) * Xi(r, k);
      }
  }
}

/// Process noise G Q G^T of eq. (11)-(12) for a step of dt, plus the bias random walks.
template <class S> Mat13<S> nav13_process_noise(const Quat<S>& q, S dt, const NavFilter13Params<S>& p) {
  Mat13<S> Q = Mat13<S>::Zero();
  const Mat3<S> C = rotmat_hom(q);
  const Mat43<S> X = quat::xi(q);
  Q.template block<3, 3>(kV, kV) = (dt * p.acc_noise * p.acc_noise) * C * C.transpose();
  Q.template block<4, 4>(kQ, kQ) = (dt * p.gyro_noise * p.gyro_noise / S(4)) * X * X.transpose();
  Q.template block<3, 3>(kBa, kBa).diagonal().setConstant(dt * p.acc_bias_noise * p.acc_bias_noise);
  Q.template block<3, 3>(kBg, kBg).diagonal().setConstant(dt * p.gyro_bias_noise * p.gyro_bias_noise);
  return Q;
}

/// Yaw of eq. (14), atan2 form: psi = atan2(2(q1 q2 + q0 q3), q0^2 + q1^2 - q2^2 - q3^2).
template <class S> S nav13_yaw(const Quat<S>& q) {
  return std::atan2(S(2) * (q[1] * q[2] + q[0] * q[3]), q[0] * q[0] + q[1] * q[1] - q[2] * q[2] - q[3] * q[3]);
}

/// d psi / dq (eq. 21), 1x4.
template <class S> Eigen::Matrix<S, 1, 4> nav13_yaw_jacobian(const Quat<S>& q) {
  const S n = S(2) * (q[1] * q[2] + q[0] * q[3]);
  const S d = q[0] * q[0] + q[1] * q[1] - q[2] * q[2] - q[3] * q[3];
  const Eigen::Matrix<S, 1, 4> dn(S(2) * q[3], S(2) * q[2], S(2) * q[1], S(2) * q[0]);
  const Eigen::Matrix<S, 1, 4> dd(S(2) * q[0], S(2) * q[1], S(-2) * q[2], S(-2) * q[3]);
  return (d * dn - n * dd) / (n * n + d * d);
}

/// The quaternion block of the state [v_n, q_nb, b_a, b_g] (core/quat_block.hpp).
template <class S> using Nav13Block = QuatBlock<S, 13, kQ>;

/// q <- q/|q| with the covariance projected by J = (I - q_hat q_hat^T)/|q| on the q rows/columns.
template <class S> void nav13_normalize(Vec13<S>& x, Mat13<S>& P) {
  Quat<S> q = x.template segment<4>(kQ);
  Nav13Block<S>::normalize(q, P);
  x.template segment<4>(kQ) = q;
}

/// A candidate state as the filter keeps it: finite, |q| = 1 to rounding (checked after the
/// normalization: a quaternion whose norm overflowed normalizes to zero) and P finite.
template <class S> bool nav13_state_ok(const Vec13<S>& x, const Mat13<S>& P) {
  return x.allFinite() && P.allFinite() && std::abs(x.template segment<4>(kQ).norm() - S(1)) <= S(1e-3);
}

/// T (12x13): the error-state map [dv, dtheta, db_a, db_g] = T [dv, dq, db_a, db_g] at a unit q,
/// dtheta = 2 Xi(q)^T dq (q_true = q * exp(dtheta), body-frame rotation vector).
template <class S> Mat<S, 12, 13> nav13_to_error(const Quat<S>& q) { return Nav13Block<S>::to_error(q); }

/// T' (13x12): dq = 1/2 Xi(q) dtheta; T T' = I (unit q), T' T projects dq onto the tangent space.
template <class S> Mat<S, 13, 12> nav13_from_error(const Quat<S>& q) { return Nav13Block<S>::from_error(q); }

/// The covariance floor of NavFilter13: the 13x13 P is singular along q by construction (|q| = 1),
/// so the floor (covariance.hpp) is applied to the error-state covariance Pe = T P T^T (12x12,
/// [dv, dtheta, db_a, db_g]) and, only when that changed it, mapped back P = T' Pe T'^T (T' T is
/// the projection the normalization already applies). A healthy P is left bit for bit. Returns
/// true when the floor was applied.
template <class S> bool nav13_floor_covariance(const Quat<S>& q, Mat13<S>& P, S floor) {
  return Nav13Block<S>::floor_error_covariance(q, P, floor);
}

/// Earth terms of eq. (2) and gravity at (lat, h) for the velocity v_n (earth.hpp, WGS-84).
template <class S> void nav13_earth_terms(S lat, S h, const Vec3<S>& v_n, bool earth_rotation, Nav13Input<S>& u) {
  const earth::Terms<S> e = earth::terms(lat, h, v_n, earth_rotation);
  u.g_n = e.g_n();
  u.omega_ie_n = e.omega_ie_n;
  u.omega_en_n = e.omega_en_n;
}

/// EKF / second-order time update (eq. 16-20) on a copy; false when the result is not finite.
template <class S, bool kSecondOrder>
bool nav13_predict_taylor(Vec13<S>& x, Mat13<S>& P, const Nav13Input<S>& u, const NavFilter13Params<S>& p) {
  Vec13<S> xn = nav13_f(x, u);
  if constexpr (kSecondOrder) xn += nav13_second_order_term(x, P, u);      // (16)-(17)
  const Mat13<S> F = nav13_jacobian(x, u);
  Mat13<S> Pn = nav13_propagate(F, P) + nav13_process_noise(Quat<S>(x.template segment<4>(kQ)), u.dt, p);  // (19)-(20)
  symmetrize(Pn);
  if (!xn.allFinite() || !Pn.allFinite() || !(xn.template segment<4>(kQ).norm() > S(0.5))) return false;
  nav13_normalize(xn, Pn);
  if (!nav13_state_ok(xn, Pn)) return false;  // |q| or P overflowed
  x = xn;
  P = Pn;
  return true;
}

/// Unscented time update in the 12-dimensional error state (see the file comment). Returns
/// Ok, SolveFailed (P not positive definite) or NumericalFailure; x, P change only on Ok. With
/// `cross`, also the cross-covariance of the error states before and after the step,
/// sum_i Wc_i (sigma offset i)(propagated deviation i)^T (the smoother's gain).
template <class S>
Status nav13_predict_ukf(Vec13<S>& x, Mat13<S>& P, const Nav13Input<S>& u, const NavFilter13Params<S>& p,
                         const UnscentedWeights<S, 12>& w, Mat12<S>* cross = nullptr) {
  constexpr int N = 12, L = 2 * N + 1;
  const Quat<S> q0 = x.template segment<4>(kQ);
  const Mat<S, 12, 13> T = nav13_to_error(q0);
  Mat12<S> P12 = Nav13Block<S>::error_covariance(q0, P);
  symmetrize(P12);
  Mat<S, N, L> off;
  if (!sigma_offsets<S, N>(P12, w.gamma, off)) return Status::SolveFailed;
  // Propagate every sigma point through f_d (eq. 12).
  Mat<S, 13, L> Y;
  for (int i = 0; i < L; ++i) {
    Vec13<S> yi = nav13_f(Vec13<S>(Nav13Block<S>::retract(x, off.col(i))), u);
    const S n = yi.template segment<4>(kQ).norm();
    if (!(n > S(0.5))) return Status::NumericalFailure;
    yi.template segment<4>(kQ) /= n;
    Y.col(i) = yi;
  }
  // Mean: Euclidean parts by the weighted sum; the quaternion by the normalized weighted sum of
  // sign-aligned points, refined by the weighted mean rotation vector about it.
  const Vec13<S> ysum = sigma_mean<S, N, 13>(Y, w);
  Quat<S> qm = Quat<S>::Zero();
  const Quat<S> qref = Y.template block<4, 1>(kQ, 0);
  for (int i = 0; i < L; ++i) {
    const Quat<S> qi = Y.template block<4, 1>(kQ, i);
    qm += w.wm(i) * (qi.dot(qref) < S(0) ? Quat<S>(-qi) : qi);
  }
  const S qn = qm.norm();
  if (!(qn > S(1e-3))) return Status::NumericalFailure;
  qm /= qn;
  Mat<S, N, L> D;
  for (int i = 0; i < L; ++i) {
    D.template block<3, 1>(0, i) = Y.template block<3, 1>(kV, i) - ysum.template segment<3>(kV);
    D.template block<3, 1>(3, i) = quat::to_rotvec(quat::mul(quat::conj(qm), Quat<S>(Y.template block<4, 1>(kQ, i))));
    D.template block<3, 1>(6, i) = Y.template block<3, 1>(kBa, i) - ysum.template segment<3>(kBa);
    D.template block<3, 1>(9, i) = Y.template block<3, 1>(kBg, i) - ysum.template segment<3>(kBg);
  }
  const Vec3<S> dmean = sigma_mean<S, N, N>(D, w).template segment<3>(3);
  qm = quat::mul(qm, quat::from_rotvec(dmean));
  qm /= qm.norm();
  for (int i = 0; i < L; ++i) D.template block<3, 1>(3, i) -= dmean;
  Mat12<S> Pn12 = sigma_covariance<S, N, N>(D, w) + fixed_mul(fixed_mul(T, nav13_process_noise(q0, u.dt, p)), T.transpose());
  symmetrize(Pn12);
  Vec13<S> xn = ysum;
  xn.template segment<4>(kQ) = qm;
  Mat13<S> Pn = Nav13Block<S>::from_error_covariance(qm, Pn12);
  symmetrize(Pn);
  if (!nav13_state_ok(xn, Pn)) return Status::NumericalFailure;
  // The offsets' column 0 is zero: the cross-covariance is wi * sum_{i>=1} off_i D_i^T.
  if (cross) *cross = w.wi * fixed_mul(off.template rightCols<2 * N>(), D.template rightCols<2 * N>().transpose());
  x = xn;
  P = Pn;
  return Status::Ok;
}

}  // namespace detail

/// The 13-state navigation filter of paper 002 with the time update chosen at compile time.
template <class S, TimeUpdate TU = TimeUpdate::Ekf> class NavFilter13 {
 public:
  using Scalar = S;
  using Params = NavFilter13Params<S>;
  using State = NavFilter13State<S>;
  using Vec13 = Vec<S, 13>;
  using Mat13 = Mat<S, 13, 13>;
  static constexpr int kStates = 13;
  static constexpr TimeUpdate kTimeUpdate = TU;

  NavFilter13() { set_params(Params{}); }
  explicit NavFilter13(const Params& p) { set_params(p); }

  const Params& params() const { return params_; }
  const State& state() const { return st_; }
  bool initialized() const { return st_.initialized; }
  /// The state as one 13-vector [v_n, q_nb, b_a, b_g].
  Vec13 x() const {
    Vec13 v;
    v << st_.v_n, st_.q_nb, st_.acc_bias, st_.gyro_bias;
    return v;
  }
  const Mat13& covariance() const { return st_.P; }
  /// Weights of the unscented transform (meaningful for TimeUpdate::Ukf).
  const UnscentedWeights<S, 12>& ukf_weights() const { return weights_; }
  bool params_valid() const { return params_ok_; }

  /// Covariance (12x12) of [dv, dtheta, db_a, db_g], dtheta the body-frame attitude error
  /// (q_true = q * exp(dtheta)); its attitude block is in rad^2.
  Mat<S, 12, 12> error_covariance() const {
    return detail::Nav13Block<S>::error_covariance(st_.q_nb, st_.P);
  }

  /// Start from a given state. P is the 13x13 covariance of [v_n, q_nb, b_a, b_g]; its quaternion
  /// block is projected onto the tangent space of the normalized q. lat, lon in rad, h in m.
  Status reset(const Vec3<S>& v_n, const Quat<S>& q_nb, const Vec3<S>& acc_bias, const Vec3<S>& gyro_bias,
               const Mat13& P, double lat, double lon, double h) {
    if (!v_n.allFinite() || !q_nb.allFinite() || !acc_bias.allFinite() || !gyro_bias.allFinite() ||
        !P.allFinite() || !std::isfinite(lat) || !std::isfinite(lon) || !std::isfinite(h))
      return Status::NonFinite;
    if (!(q_nb.norm() > S(0.5)) || !(std::abs(lat) < 1.5)) return Status::InvalidArgument;
    State s;
    Vec13 xv;
    xv << v_n, q_nb, acc_bias, gyro_bias;
    Mat13 Pn = P;
    symmetrize(Pn);
    detail::nav13_normalize(xv, Pn);
    // A P near the float maximum can overflow here, and a quaternion whose norm overflows
    // normalizes to zero (finite, so the check is on the normalized norm).
    if (!detail::nav13_state_ok(xv, Pn)) return Status::InvalidArgument;
    detail::nav13_floor_covariance<S>(xv.template segment<4>(detail::kQ), Pn, params_.cov_floor);
    // A negative variance, given or made by the projection of an indefinite P: a state set_state refuses.
    if (!detail::nonnegative_diagonal<S, 13>(Pn)) return Status::InvalidArgument;
    unpack(xv, s);
    s.P = Pn;
    s.lat = lat;
    s.lon = lon;
    s.h = h;
    s.initialized = true;
    st_ = s;
    return Status::Ok;
  }

  /// Restore a state read with state(). Refused when anything is non-finite or |q| != 1.
  Status set_state(const State& s) {
    if (!s.v_n.allFinite() || !s.q_nb.allFinite() || !s.acc_bias.allFinite() || !s.gyro_bias.allFinite() ||
        !s.P.allFinite() || !std::isfinite(s.lat) || !std::isfinite(s.lon) || !std::isfinite(s.h))
      return Status::NonFinite;
    if (std::abs(s.q_nb.norm() - S(1)) > S(1e-3)) return Status::InvalidArgument;
    if (!detail::acceptable_covariance<S, 13>(s.P) || !(std::abs(s.lat) < 1.5)) return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// Replace the carried position (e.g. from a GPS fix): lat, lon [rad], h [m].
  Status set_position(double lat, double lon, double h) {
    if (!std::isfinite(lat) || !std::isfinite(lon) || !std::isfinite(h)) return Status::NonFinite;
    if (!(std::abs(lat) < 1.5)) return Status::InvalidArgument;
    st_.lat = lat;
    st_.lon = lon;
    st_.h = h;
    return Status::Ok;
  }

  /// Time update with one IMU sample: omega_ib_b [rad/s] and f_ib_b [m/s^2] as measured (mean
  /// over the step; gyroscope first, as in every filter), dt [s]. The specific force gets the rotation correction of the velocity
  /// increment (nav13_rotation_correction). The Earth terms come from the carried position and the prior
  /// velocity; the position is then advanced with the mean of the prior and posterior velocity.
  /// The Earth terms and the geodetic rates are computed in S from the position rounded to S
  /// (their change over one ulp of a float latitude is far below float resolution); only the
  /// accumulation of the position is double, so a float build needs no double trigonometry.
  Status predict(const Vec3<S>& omega_ib_b, const Vec3<S>& f_ib_b, S dt) {
    if (!st_.initialized) return Status::NotInitialized;
    if (!params_ok_) return Status::InvalidArgument;
    if (!f_ib_b.allFinite() || !omega_ib_b.allFinite()) return Status::NonFinite;
    if (!(dt > S(0)) || !(dt <= params_.max_dt)) return Status::InvalidDt;
    if (detail::saturated(omega_ib_b, params_.gyro_range) || detail::saturated(f_ib_b, params_.acc_range))
      return Status::Saturated;
    const Nav13Input<S> u = step_input(omega_ib_b, f_ib_b, dt);
    Vec13 xv = x();
    Mat13 P = st_.P;
    if constexpr (TU == TimeUpdate::Ukf) {
      const Status s = detail::nav13_predict_ukf(xv, P, u, params_, weights_);
      if (s != Status::Ok) return s;
    } else {
      if (!detail::nav13_predict_taylor<S, TU == TimeUpdate::SecondOrder>(xv, P, u, params_))
        return Status::NumericalFailure;
    }
    const Vec3<S> v_mid = S(0.5) * (st_.v_n + xv.template segment<3>(detail::kV));
    const Vec3<S> rates = earth::geodetic_rates(S(st_.lat), S(st_.h), v_mid);
    const double lat = st_.lat + double(rates[0]) * double(dt), lon = st_.lon + double(rates[1]) * double(dt),
                 h = st_.h + double(rates[2]) * double(dt);
    // A velocity that carries the position past the pole (or overflows) is refused: the Earth
    // terms of the next step would not be finite.
    if (!std::isfinite(lon) || !std::isfinite(h) || !(std::abs(lat) < 1.5)) return Status::NumericalFailure;
    detail::nav13_floor_covariance<S>(xv.template segment<4>(detail::kQ), P, params_.cov_floor);
    // An indefinite P (set_state and reset take one) propagated without a floor can lose its
    // non-negative diagonal, a state set_state would refuse: refused, nothing changed.
    if (!detail::nonnegative_diagonal<S, 13>(P)) return Status::NumericalFailure;
    unpack(xv, st_);
    st_.P = P;
    st_.lat = lat;
    st_.lon = lon;
    st_.h = h;
    return Status::Ok;
  }

  /// The input of the Euler step (eq. 12) that predict(omega_ib_b, f_ib_b, dt) makes from the
  /// current state: the specific force with the rotation correction at the bias estimates, and
  /// the Earth terms at the carried position and the current velocity. (The smoother evaluates
  /// the step's transition nav13_jacobian(x(), step_input(...)) with it.)
  Nav13Input<S> step_input(const Vec3<S>& omega_ib_b, const Vec3<S>& f_ib_b, S dt) const {
    Nav13Input<S> u;
    u.f_ib_b = detail::nav13_rotation_correction(f_ib_b, omega_ib_b, st_.acc_bias, st_.gyro_bias, dt);
    u.omega_ib_b = omega_ib_b;
    u.dt = dt;
    detail::nav13_earth_terms(S(st_.lat), S(st_.h), st_.v_n, params_.earth_rotation, u);
    return u;
  }

  /// NED velocity measurement [m/s] (eq. 13, 21 rows 1-3).
  UpdateResult<S, 3> update_velocity(const Vec3<S>& v_meas, S gate = S(0)) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    if (!v_meas.allFinite()) {
      res.status = Status::NonFinite;
      return res;
    }
    Mat<S, 3, 13> H = Mat<S, 3, 13>::Zero();
    H.template block<3, 3>(0, detail::kV).setIdentity();
    const Mat3<S> R = Mat3<S>::Identity() * (params_.gps_vel_sigma * params_.gps_vel_sigma);
    apply_correction<3>(H, R, Vec3<S>(v_meas - st_.v_n), res, gate);
    return res;
  }

  /// Yaw measurement [rad] (eq. 13-14, 21 row 4); the innovation is wrapped to (-pi, pi].
  UpdateResult<S, 1> update_yaw(S yaw, S gate = S(0)) {
    UpdateResult<S, 1> res;
    if (!st_.initialized) return res;
    if (!std::isfinite(yaw)) {
      res.status = Status::NonFinite;
      return res;
    }
    Mat<S, 1, 13> H = Mat<S, 1, 13>::Zero();
    H.template block<1, 4>(0, detail::kQ) = detail::nav13_yaw_jacobian(st_.q_nb);
    Mat<S, 1, 1> R;
    R(0, 0) = params_.yaw_sigma * params_.yaw_sigma;
    Vec<S, 1> y;
    y[0] = quat::wrap_pi(yaw - detail::nav13_yaw(st_.q_nb));
    apply_correction<1>(H, R, y, res, gate);
    return res;
  }

  /// Joint velocity + yaw measurement y = [v_n, psi] of eq. (13), one 4-row correction (eq. 22).
  UpdateResult<S, 4> update_velocity_yaw(const Vec3<S>& v_meas, S yaw, S gate = S(0)) {
    UpdateResult<S, 4> res;
    if (!st_.initialized) return res;
    if (!v_meas.allFinite() || !std::isfinite(yaw)) {
      res.status = Status::NonFinite;
      return res;
    }
    Mat<S, 4, 13> H = Mat<S, 4, 13>::Zero();
    H.template block<3, 3>(0, detail::kV).setIdentity();
    H.template block<1, 4>(3, detail::kQ) = detail::nav13_yaw_jacobian(st_.q_nb);
    Mat<S, 4, 4> R = Mat<S, 4, 4>::Zero();
    R.diagonal() << Vec3<S>::Constant(params_.gps_vel_sigma * params_.gps_vel_sigma), params_.yaw_sigma * params_.yaw_sigma;
    Vec<S, 4> y;
    y << v_meas - st_.v_n, quat::wrap_pi(yaw - detail::nav13_yaw(st_.q_nb));
    apply_correction<4>(H, R, y, res, gate);
    return res;
  }

 private:
  void set_params(const Params& p) {
    params_ = p;
    params_ok_ = weights_.compute(UnscentedParams<S>{p.ukf_alpha, p.ukf_beta, p.ukf_kappa});
    params_ok_ = params_ok_ && p.acc_noise >= S(0) && p.gyro_noise >= S(0) && p.acc_bias_noise >= S(0) &&
                 p.gyro_bias_noise >= S(0) && p.gps_vel_sigma > S(0) && p.yaw_sigma > S(0) && p.max_dt > S(0) &&
                 p.gyro_range >= S(0) && p.acc_range >= S(0) && p.cov_floor >= S(0);
  }

  static void unpack(const Vec13& xv, State& s) {
    s.v_n = xv.template segment<3>(detail::kV);
    s.q_nb = xv.template segment<4>(detail::kQ);
    s.acc_bias = xv.template segment<3>(detail::kBa);
    s.gyro_bias = xv.template segment<3>(detail::kBg);
  }

  /// Eq. (22)-(23) through kalman_correct, then renormalize q (covariance projected).
  template <int M>
  void apply_correction(const Mat<S, M, 13>& H, const Mat<S, M, M>& R, const Vec<S, M>& y, UpdateResult<S, M>& res,
                        S gate) {
    Mat13 P = st_.P;
    Vec13 dx;
    // kalman_correct refuses an infinite NIS (NumericalFailure).
    kalman_correct<S, 13, M>(P, H, R, y, dx, res, gate);
    inject_and_commit(
        res, P, [&] { return Vec13(x() + dx); },  // (23)
        // A correction that moves the unit quaternion by more than about one unit is far outside
        // the linearization (and an overflowing norm would normalize to zero): refused, state
        // kept. Likewise a corrected speed above kMaxSpeed (an absurd but finite aid, e.g.
        // 1e38 m/s, would otherwise be accepted and make every later predict overflow).
        [](const Vec13& xv, const Mat13&) {
          const S qn = xv.template segment<4>(detail::kQ).norm();
          return xv.allFinite() && qn > S(0.5) && qn < S(2) && xv.template segment<3>(detail::kV).norm() < kMaxSpeed;
        },
        [&](Vec13& xv, Mat13& Pc) {
          detail::nav13_normalize(xv, Pc);
          if (!detail::nav13_state_ok(xv, Pc)) return false;
          detail::nav13_floor_covariance<S>(xv.template segment<4>(detail::kQ), Pc, params_.cov_floor);
          // A correction of an indefinite P can lose the non-negative diagonal: refused.
          return detail::nonnegative_diagonal<S, 13>(Pc);
        },
        [&](const Vec13& xv, const Mat13& Pc) {
          unpack(xv, st_);
          st_.P = Pc;
        });
  }

  /// Largest speed [m/s] a correction may produce (far above any vehicle near the Earth).
  static constexpr S kMaxSpeed = S(1e5);

  Params params_{};
  UnscentedWeights<S, 12> weights_{};
  bool params_ok_ = false;
  State st_{};
};

/// Batch run over IMU samples with velocity and yaw measurements at their own times, in C++.
///
/// IMU: n samples omega_ib_b (n x 3), f_ib_b (n x 3), row-major; t (n) the end time of each
/// sample and dt (n) its length, so the filter state (set by reset before the call) is at
/// t[0] - dt[0]. Measurements: vel (nv x 3) at vel_t (nv), yaw (ny) at yaw_t (ny), both sorted.
/// The times (t, vel_t, yaw_t) are double whatever S: they only order the measurements among the
/// samples, and a float time on a GPS or Unix clock (1e9 s) resolves 64-128 s, which would put
/// every measurement of a record on one sample.
/// A measurement at time tau is applied right after the predict of the first IMU sample with
/// t[k] >= tau (within 1e-4 dt). One before the filter's time t[0] - dt[0] (by more than
/// 1e-4 dt[0]) is older than the state and never applied (reported as below, NotInitialized).
/// One at the filter's time (within 1e-4 dt[0]) is applied before the first predict with
/// apply_at_start (a run from a reset state), else never (a run that continues a previous one,
/// which applied it after its last sample): so a record run in chunks, each given the whole aid
/// record and apply_at_start only for the first, applies each measurement once and gives the run
/// of the whole record bit for bit. When a
/// velocity and a yaw fall on the same sample the velocity is applied first (sequential updates of
/// independent measurements).
/// Outputs (any may be null): x (n x 13), sigma (n x 13), P (n x 169), att_sigma (n x 3, body
/// rotation-vector one-sigma, rad), flags (n); per measurement: innovation, NIS, status. Every
/// sample is reported to `obs` (core/checks.hpp's NoBatchObserver; the smoother's record).
template <class Filter, class S = typename Filter::Scalar, class Observer = NoBatchObserver>
void run_nav13_batch(Filter& f, const S* omega_ib_b, const S* f_ib_b, const double* t, const S* dt, std::size_t n,
                     const double* vel_t, const S* vel, std::size_t nv, const double* yaw_t, const S* yaw, std::size_t ny,
                     S gate_vel, S gate_yaw, S* x_out, S* sigma_out, S* P_out, S* att_sigma_out,
                     std::uint32_t* flags_out, S* vel_innov, S* vel_nis, std::uint8_t* vel_status, S* yaw_innov,
                     S* yaw_nis, std::uint8_t* yaw_status, bool apply_at_start = true, Observer&& obs = Observer{}) {
  std::size_t iv = 0, iy = 0;
  auto apply = [&](double t_now, std::uint32_t& fl) {
    while (iv < nv && vel_t[iv] <= t_now) {
      const UpdateResult<S, 3> r = f.update_velocity(Vec3<S>(Eigen::Map<const Vec3<S>>(vel + 3 * iv)), gate_vel);
      if (vel_innov) Eigen::Map<Vec3<S>>(vel_innov + 3 * iv) = r.innovation;
      if (vel_nis) vel_nis[iv] = r.nis;
      if (vel_status) vel_status[iv] = static_cast<std::uint8_t>(r.status);
      fl |= r.status == Status::Ok ? flags::kGpsVelUsed
                                   : update_flags(r, flags::kAidSkipped, flags::kGpsVelRejected);
      ++iv;
    }
    while (iy < ny && yaw_t[iy] <= t_now) {
      const UpdateResult<S, 1> r = f.update_yaw(yaw[iy], gate_yaw);
      if (yaw_innov) yaw_innov[iy] = r.innovation[0];
      if (yaw_nis) yaw_nis[iy] = r.nis;
      if (yaw_status) yaw_status[iy] = static_cast<std::uint8_t>(r.status);
      fl |= r.status == Status::Ok ? flags::kHeadingUsed
                                   : update_flags(r, flags::kAidSkipped, flags::kHeadingRejected);
      ++iy;
    }
  };
  const S nan = std::numeric_limits<S>::quiet_NaN();
  // A measurement never applied: NaN innovation and NIS, and the status of a filter that has no
  // state for it (NotInitialized), never left unwritten.
  auto vel_never = [&](std::size_t i) {
    if (vel_innov) Eigen::Map<Vec3<S>>(vel_innov + 3 * i).setConstant(nan);
    if (vel_nis) vel_nis[i] = nan;
    if (vel_status) vel_status[i] = static_cast<std::uint8_t>(Status::NotInitialized);
  };
  auto yaw_never = [&](std::size_t i) {
    if (yaw_innov) yaw_innov[i] = nan;
    if (yaw_nis) yaw_nis[i] = nan;
    if (yaw_status) yaw_status[i] = static_cast<std::uint8_t>(Status::NotInitialized);
  };
  std::uint32_t fl0 = 0;
  if (n > 0) {
    const double tol = 1e-4 * double(dt[0]), t_start = t[0] - double(dt[0]);
    for (; iv < nv && vel_t[iv] < t_start - tol; ++iv) vel_never(iv);  // older than the state
    for (; iy < ny && yaw_t[iy] < t_start - tol; ++iy) yaw_never(iy);
    if (apply_at_start) {
      apply(t_start + tol, fl0);
    } else {  // applied by the run this one continues
      for (; iv < nv && vel_t[iv] <= t_start + tol; ++iv) vel_never(iv);
      for (; iy < ny && yaw_t[iy] <= t_start + tol; ++iy) yaw_never(iy);
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    std::uint32_t fl = k == 0 ? fl0 : 0u;
    const Eigen::Map<const Vec3<S>> fk(f_ib_b + 3 * k), wk(omega_ib_b + 3 * k);
    const Status sp = f.predict(Vec3<S>(wk), Vec3<S>(fk), dt[k]);
    if (sp != Status::Ok) fl |= flags::kPredictSkipped | (sp == Status::Saturated ? flags::kSaturated : 0u);
    obs.after_predict(k, f);
    apply(t[k] + 1e-4 * double(dt[k]), fl);
    obs.after_sample(k, f);
    if (x_out) Eigen::Map<Vec<S, 13>>(x_out + 13 * k) = f.x();
    if (sigma_out) Eigen::Map<Vec<S, 13>>(sigma_out + 13 * k) = f.covariance().diagonal().cwiseMax(S(0)).cwiseSqrt();
    if (P_out) Eigen::Map<Mat<S, 13, 13>>(P_out + 169 * k) = f.covariance();
    if (att_sigma_out)
      Eigen::Map<Vec3<S>>(att_sigma_out + 3 * k) =
          f.error_covariance().template block<3, 3>(3, 3).diagonal().cwiseMax(S(0)).cwiseSqrt();
    if (flags_out) flags_out[k] = fl;
  }
  // Measurements after the last sample are never applied.
  for (; iv < nv; ++iv) vel_never(iv);
  for (; iy < ny; ++iy) yaw_never(iy);
}

}  // namespace quatnav
