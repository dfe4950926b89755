// quatnav: the Euler-angle EKF that paper 000 compares its quaternion EKF against.
//
// State x = [roll, pitch, yaw, bx, by, bz] (ZYX Euler angles of C_nb in rad, gyro bias in
// rad/s). Time update: Euler-rate kinematics (paper 004 eq. 1),
//   de/dt = E(roll, pitch) (w - b),
//   E = [[1, sin(roll) tan(pitch), cos(roll) tan(pitch)],
//        [0, cos(roll),            -sin(roll)],
//        [0, sin(roll)/cos(pitch),  cos(roll)/cos(pitch)]].
// The paper integrates it with one Euler step, e(k) = e(k-1) + T E (w - b) (exact_propagation =
// false, paper()). Its error is of second order in the rotation per step and, over a periodic
// swing at 300-500 deg/s, systematic: it turns the heading by degrees per minute. By default the
// angles are propagated exactly for a constant rate over the step, through the quaternion,
// e(k) = euler(q(e(k-1)) exp(T (w - b))), on the branch of the ZYX angles nearest the Euler
// step; the covariance keeps the Jacobian F of the Euler step (the exact map's Jacobian to first
// order in T). Where the parametrization is singular (below) both use the Euler step.
// Measurements: the same normalized accelerometer and magnetometer as the quaternion EKF,
// h = C_bn(e) [0, 0, -1] and C_bn(e) [m_x, 0, m_z] (paper 000 eq. 1 for C_bn).
//
// The singularity: E is unbounded at pitch = +/-90 deg. Where |cos(pitch)| < singular_cos the
// step still runs with cos(pitch) held at +/-singular_cos, and near_singularity() (batch flag
// kSingular) reports it: results there are not to be trusted. This is the parametrization's
// fault, not the data's; the quaternion EKF has no such point.
//
// The accelerometer update is the Schmidt-Kalman update of QuaternionEKF (quaternion_ekf.hpp:
// gravity carries no heading information): it corrects the attitude by a rotation about a
// horizontal axis of the navigation frame only, and the bias in the horizontal plane only. In
// ZYX angles a navigation-frame rotation by [a_x, a_y, a_z] changes them by cos(pitch) d_roll =
// cos(yaw) a_x + sin(yaw) a_y, d_pitch = -sin(yaw) a_x + cos(yaw) a_y, d_yaw = a_z +
// sin(pitch) d_roll: a tilt correction (a_z = 0) moves the yaw by sin(pitch) d_roll, so the
// gain's heading part a_z = k_yaw - sin(pitch) k_roll is removed by k_yaw <- sin(pitch) k_roll
// (along e_yaw, the rotation about the vertical); the bias gain is projected off the body-frame
// vertical, and off the directions that swung through it within the low-pass time
// (AccFilter::bias_weight, parts/acc_filter.hpp). h = C_bn(e) [0, 0, -1] does not depend on the yaw nor on the bias, so both removed
// directions are in the null space of H and the NIS is the optimal update's. acc_tilt_only =
// false (paper()) restores the optimal gain.
//
// The robustness parts (parts/*.hpp) as in QuaternionEKF: rest detection with its zero-rate
// measurement of the bias block (H = [0 I]), the accelerometer part (low-pass in a gyro-carried
// frame, norm rejection, adaptive noise, recovery; the low-pass time constant follows the
// largest gyro-bias variance) and the magnetometer part (reference field and disturbance tests).
// Their parameters and state fields carry the same names; paper() switches them off and gives
// paper 000's plain baseline.
#pragma once

#include <cmath>
#include <cstdint>

#include "attitude.hpp"
#include "parts/parts.hpp"
#include "../core/fields.hpp"
#include "../core/covariance.hpp"
#include "../core/kalman.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

/// Parameters of EulerEKF: paper 000's noise values with the robustness parts of QuaternionEKF
/// (the same fields and defaults); paper() switches the parts off. Every field has its unit and
/// default.
// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_EULER_PARAMS(X)                                                                         \
  X(S, gyro_noise, S(0.005), "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)")           \
  X(S, gyro_bias_noise, S(1e-5), "rad/s^2/sqrt(Hz)", "gyro-bias random-walk density")                    \
  X(S, acc_sigma, S(0.05), "1 (normalized)", "std of each component of the normalized accelerometer")    \
  X(S, mag_sigma, S(0.1), "1 (normalized)", "std of each component of the normalized magnetometer")      \
  X(S, init_att_sigma, S(0.05), "rad", "one-sigma of each Euler angle after initialize")                 \
  X(S, init_gyro_bias_sigma, S(0.01), "rad/s", "gyro-bias one-sigma after initialize")                   \
  X(S, max_dt, S(1), "s", "longest accepted IMU step")                                                   \
  X(S, singular_cos, S(0.02), "1",                                                                       \
    "the Euler parametrization is flagged singular where abs(cos(pitch)) is below it")                   \
  X(bool, exact_propagation, true, "-",                                                                  \
    "propagate the angles exactly through the quaternion (false: paper 004 eq. 1's Euler step)")         \
  X(S, gyro_range, S(0), "rad/s",                                                                        \
    "gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited)")    \
  X(S, acc_range, S(0), "m/s^2", "accelerometer range per axis, as gyro_range (0: unlimited)")            \
  /* here a floor on the eigenvalues of P itself (covariance.hpp) */                                  \
  X(S, cov_floor, S(1e-12), "state units^2", "eigenvalue floor of the error covariance (0: off)")         \
  X(bool, acc_tilt_only, true, "-",                                                                      \
    "the accelerometer corrects the tilt and the horizontal gyro bias only (false: the optimal gain)")    \
  X(AccFilterParams<S>, acc, detail::euler_acc_defaults<S>(), "-", "accelerometer low-pass, rejection, adaptive noise") \
  X(MagDisturbanceParams<S>, mag, MagDisturbanceParams<S>(), "-", "reference field and disturbance tests") \
  X(RestParams<S>, rest, RestParams<S>(), "-", "rest detection and zero-rate measurement")

namespace detail {
/// The accelerometer part's defaults in EulerEKF: a 1 s low-pass instead of QuaternionEKF's 3 s.
/// EulerEKF learns its gyro bias more slowly, and over acc_lp_tau the low-pass frame drifts by
/// the bias error; on BROAD 1 s is also better (mean total 3.88 deg against 4.64 with 3 s; docs/broad.md,
/// "The accelerometer low-pass of EulerEKF and MargFilter").
template <class S> AccFilterParams<S> euler_acc_defaults() {
  AccFilterParams<S> p;
  p.acc_lp_tau = S(1);
  return p;
}
}  // namespace detail

template <class S> struct EulerEKFParams {
  QUATNAV_FIELDS(EulerEKFParams, QUATNAV_EULER_PARAMS)

  /// The plain baseline of paper 000: the same noise values, every robustness part off.
  static EulerEKFParams paper() {
    EulerEKFParams p;
    p.acc_tilt_only = false;
    p.exact_propagation = false;
    AccFilter<S>::off(p.acc);
    MagDisturbance<S>::off(p.mag);
    Rest<S>::off(p.rest);
    return p;
  }
};

#define QUATNAV_EULER_STATE(X)                                                                          \
  X(Vec3<S>, euler, Vec3<S>::Zero(), "rad", "ZYX Euler angles [roll, pitch, yaw] of C_nb")               \
  X(Vec3<S>, gyro_bias, Vec3<S>::Zero(), "rad/s", "gyro bias")                                          \
  X(Mat6, P, Mat6::Identity(), "state units^2", "covariance of [euler, gyro_bias]")                      \
  X(bool, initialized, false, "-", "the filter has a state")                                            \
  X(S, dt_last, S(0), "s", "step of the last predict")                                                  \
  X(MagDisturbanceState<S>, mag, MagDisturbanceState<S>(), "-", "reference field and disturbance tests") \
  X(AccFilterState<S>, acc, AccFilterState<S>(), "-", "accelerometer low-pass and rejection timer")      \
  X(RestState<S>, rest, RestState<S>(), "-", "rest detection")

/// The complete state of EulerEKF; state()/set_state() round-trip exactly.
template <class S> struct EulerEKFState {
  using Mat6 = Mat<S, 6, 6>;
  QUATNAV_FIELDS(EulerEKFState, QUATNAV_EULER_STATE)
};

namespace detail {

/// C_bn(roll, pitch, yaw) and its three partial derivatives.
template <class S> void euler_cbn(const Vec3<S>& e, Mat3<S>& C, Mat3<S>* dC) {
  const S cr = std::cos(e[0]), sr = std::sin(e[0]), cp = std::cos(e[1]), sp = std::sin(e[1]);
  const S cy = std::cos(e[2]), sy = std::sin(e[2]);
  Mat3<S> Rx, Ry, Rz;  // transposed elementary rotations (navigation to body)
  Rx << S(1), S(0), S(0), S(0), cr, sr, S(0), -sr, cr;
  Ry << cp, S(0), -sp, S(0), S(1), S(0), sp, S(0), cp;
  Rz << cy, sy, S(0), -sy, cy, S(0), S(0), S(0), S(1);
  C = Rx * Ry * Rz;
  if (dC) {
    Mat3<S> dRx, dRy, dRz;
    dRx << S(0), S(0), S(0), S(0), -sr, cr, S(0), -cr, -sr;
    dRy << -sp, S(0), -cp, S(0), S(0), S(0), cp, S(0), -sp;
    dRz << -sy, cy, S(0), -cy, -sy, S(0), S(0), S(0), S(0);
    dC[0] = dRx * Ry * Rz;
    dC[1] = Rx * dRy * Rz;
    dC[2] = Rx * Ry * dRz;
  }
}

/// Euler-rate matrix E of paper 004 eq. (1), with cos(pitch) held away from zero.
template <class S> Mat3<S> euler_rate_matrix(S roll, S cp_safe, S sp) {
  const S cr = std::cos(roll), sr = std::sin(roll), tp = sp / cp_safe;
  Mat3<S> E;
  E << S(1), sr * tp, cr * tp, S(0), cr, -sr, S(0), sr / cp_safe, cr / cp_safe;
  return E;
}

template <class S> S safe_cos(S pitch, S min_cos, bool& singular) {
  const S c = std::cos(pitch);
  singular = std::abs(c) < min_cos;
  return singular ? (c < S(0) ? -min_cos : min_cos) : c;
}

/// Of the two ZYX triples of one rotation, e = [roll, pitch, yaw] (to_euler's, pitch in
/// [-pi/2, pi/2]) and [roll + pi, pi - pitch, yaw + pi], the one nearest `near` (angle
/// differences wrapped to (-pi, pi]); the other triple has its angles wrapped to (-pi, pi].
template <class S> Vec3<S> euler_nearest_branch(const Vec3<S>& e, const Vec3<S>& near) {
  const S pi = S(3.14159265358979323846);
  const Vec3<S> alt(quat::wrap_pi(e[0] + pi), quat::wrap_pi(pi - e[1]), quat::wrap_pi(e[2] + pi));
  const auto dist2 = [&](const Vec3<S>& a) {
    S d2 = S(0);
    for (int i = 0; i < 3; ++i) {
      const S d = quat::wrap_pi(a[i] - near[i]);
      d2 += d * d;
    }
    return d2;
  };
  return dist2(alt) < dist2(e) ? alt : e;
}

/// Time update and its Jacobian (6x6): e' = e + T E (w - b) (paper 004 eq. 1, one Euler step)
/// or, with `exact` and away from the singularity, e' = euler(q(e) exp(T (w - b))) on the
/// branch nearest the Euler step; F is the Euler step's Jacobian either way.
template <class S>
void euler_propagate(const Vec3<S>& e, const Vec3<S>& bias, const Vec3<S>& gyr, S dt, S min_cos, bool exact,
                     Vec3<S>& e_out, Mat<S, 6, 6>& F, Mat3<S>& E, bool& singular) {
  const S cp = safe_cos(e[1], min_cos, singular), sp = std::sin(e[1]);
  const S cr = std::cos(e[0]), sr = std::sin(e[0]);
  E = euler_rate_matrix(e[0], cp, sp);
  const Vec3<S> w = gyr - bias;
  e_out = e + dt * E * w;
  const S a = w[1] * sr + w[2] * cr;  // q sin(roll) + r cos(roll)
  const S b = w[1] * cr - w[2] * sr;  // q cos(roll) - r sin(roll)
  F.setIdentity();
  // d/droll
  F(0, 0) += dt * b * sp / cp;
  F(1, 0) += dt * (-a);
  F(2, 0) += dt * b / cp;
  // d/dpitch (zero while held at the singular bound)
  if (!singular) {
    F(0, 1) += dt * a / (cp * cp);
    F(2, 1) += dt * a * sp / (cp * cp);
  }
  F.template topRightCorner<3, 3>() = -dt * E;
  if (exact && !singular) {
    const Quat<S> q = quat::mul(quat::from_euler(e), quat::from_rotvec(Vec3<S>(dt * w)));
    e_out = euler_nearest_branch(quat::to_euler(Quat<S>(q / q.norm())), e_out);
  }
}

/// Measurement h(e) = C_bn(e) r for r = [r_x, 0, r_z] and its Jacobian in the Euler angles
/// (3x3: the gyro-bias columns of the 3x6 Jacobian are zero).
template <class S> void euler_measurement(const Vec3<S>& e, S rx, S rz, Vec3<S>& h, Mat3<S>& H) {
  Mat3<S> C, dC[3];
  euler_cbn(e, C, dC);
  const Vec3<S> r(rx, S(0), rz);
  h = C * r;
  for (int i = 0; i < 3; ++i) H.col(i) = dC[i] * r;
}

}  // namespace detail

template <class S> class EulerEKF {
 public:
  using Scalar = S;
  using Params = EulerEKFParams<S>;
  using State = EulerEKFState<S>;
  using Mat6 = Mat<S, 6, 6>;
  static constexpr int kStates = 6;

  EulerEKF() = default;
  explicit EulerEKF(const Params& p) : params_(p) {}

  const Params& params() const { return params_; }
  const State& state() const { return st_; }
  const Vec3<S>& euler() const { return st_.euler; }
  Quat<S> quat() const { return quat::from_euler(st_.euler); }
  const Vec3<S>& bias() const { return st_.gyro_bias; }
  const Mat6& covariance() const { return st_.P; }
  bool initialized() const { return st_.initialized; }
  /// True when the last predict ran with |cos(pitch)| below singular_cos.
  bool near_singularity() const { return singular_; }
  /// Flags of the last sample beyond the update statuses (kSingular, kAtRest, kAccRejected, kMagRejected).
  std::uint32_t extra_flags() const { return flags_ | (singular_ ? flags::kSingular : 0u); }
  bool at_rest() const { return Rest<S>::at_rest(params_.rest, st_.rest); }

  Status set_state(const State& s) {
    if (!detail::fields_finite(s)) return Status::NonFinite;
    if (!detail::acceptable_covariance<S, 6>(s.P)) return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// The diagonal of attitude_covariance() (rad^2).
  Vec3<S> attitude_variance() const { return attitude_covariance().diagonal(); }

  /// Covariance of the body-frame rotation vector (q_true = q * exp(dtheta)): W P_ee W^T with
  /// W = E^-1 the map from Euler-angle to body-rate perturbations.
  Mat3<S> attitude_covariance() const {
    const S cr = std::cos(st_.euler[0]), sr = std::sin(st_.euler[0]);
    const S cp = std::cos(st_.euler[1]), sp = std::sin(st_.euler[1]);
    Mat3<S> W;
    W << S(1), S(0), -sp, S(0), cr, sr * cp, S(0), -sr, cr * cp;
    return W * st_.P.template topLeftCorner<3, 3>() * W.transpose();
  }

  void set_mag_dip(S dip) { st_.mag.ref.fix(dip); }

  Status initialize(const Vec3<S>& acc) { return init_impl(acc, nullptr); }
  Status initialize(const Vec3<S>& acc, const Vec3<S>& mag) { return init_impl(acc, &mag); }

  Status reset(const Vec3<S>& euler, const Vec3<S>& bias, const Mat6& P) {
    if (!euler.allFinite() || !bias.allFinite() || !P.allFinite()) return Status::NonFinite;
    if (!(P.diagonal().array() >= S(0)).all()) return Status::InvalidArgument;
    Mat6 P_sym = P;
    symmetrize(P_sym);  // may overflow for huge finite entries: refuse those
    if (!P_sym.allFinite()) return Status::InvalidArgument;
    st_.euler = euler;
    st_.gyro_bias = bias;
    st_.P = P_sym;
    st_.initialized = true;
    return Status::Ok;
  }

  Status predict(const Vec3<S>& gyr, S dt) {
    if (!st_.initialized) return Status::NotInitialized;
    if (!all_finite(gyr)) return Status::NonFinite;
    if (!(dt > S(0)) || !(dt <= params_.max_dt)) return Status::InvalidDt;
    if (detail::saturated(gyr, params_.gyro_range)) return Status::Saturated;
    Vec3<S> e;
    Mat6 F;
    Mat3<S> E;
    bool singular = false;
    detail::euler_propagate(st_.euler, st_.gyro_bias, gyr, dt, params_.singular_cos, params_.exact_propagation, e,
                            F, E, singular);
    // P = F P F^T + Q by blocks, F = [G B; 0 I] (predict_covariance_fb).
    const Mat3<S> G = F.template topLeftCorner<3, 3>();
    const Mat3<S> B = F.template topRightCorner<3, 3>();
    Mat6 P;
    predict_covariance_fb<S, 3, 3>(st_.P, G, B, (dt * params_.gyro_noise * params_.gyro_noise) * E * E.transpose(),
                                   S(dt * params_.gyro_bias_noise * params_.gyro_bias_noise), P);
    symmetrize(P);
    if (!all_finite(P) || !all_finite(e)) return Status::NumericalFailure;
    floor_covariance<S, 6>(P, params_.cov_floor);
    // An indefinite P (set_state and reset take one) propagated without a floor can lose its
    // non-negative diagonal, a state set_state would refuse: refused, nothing changed.
    if (!detail::nonnegative_diagonal<S, 6>(P)) return Status::NumericalFailure;
    e[0] = quat::wrap_pi(e[0]);
    e[2] = quat::wrap_pi(e[2]);
    // The accelerometer part's frame turns by (w - b) dt: a rate that overflows that rotation
    // (the Euler angles wrap, the quaternion of the frame does not) is refused, nothing changed.
    AccFilterState<S> acc = st_.acc;
    AccFilter<S>::predict_rate(params_.acc, acc, Vec3<S>(gyr - st_.gyro_bias), dt);
    if (!all_finite(acc.q_i)) return Status::NumericalFailure;
    st_.acc = acc;
    st_.euler = e;
    st_.P = P;
    singular_ = singular;
    flags_ = 0;
    st_.dt_last = dt;
    Rest<S>::predict(params_.rest, st_.rest, gyr, dt);
    return Status::Ok;
  }

  /// Accelerometer update: the rest test (at rest the zero-rate measurement of the bias), then
  /// the accelerometer part (low-pass, rejection, adaptive noise, recovery) and the 3-row update.
  UpdateResult<S, 3> update_acc(const Vec3<S>& acc, S gate = S(0)) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    if (detail::saturated(acc, params_.acc_range)) {
      res.status = Status::Saturated;
      return res;
    }
    Vec3<S> a;
    res.status = detail::unit_vector(acc, a);
    if (res.status != Status::Ok) return res;
    // As QuaternionEKF::update_acc: a failed update leaves the rest test and the low-pass too.
    const State before = st_;
    if (Rest<S>::update(params_.rest, st_.rest, acc, st_.gyro_bias, st_.dt_last)) update_zero_rate();
    const S bias_var = st_.P.diagonal().template tail<3>().maxCoeff();
    res = AccFilter<S>::update(params_.acc, st_.acc, acc, st_.dt_last, bias_var, flags_, [&](const AccSample<S>& in) {
      const Vec3<S> up = quat::rotate_inv(quat(), Vec3<S>(S(0), S(0), S(1)));  // the vertical, body frame
      const S sin_pitch = std::sin(st_.euler[1]);
      const Mat3<S> W = AccFilter<S>::bias_weight(params_.acc, st_.acc, up);  // I - up up^T without rotation
      return update3(in.acc, S(0), S(-1), params_.acc_sigma + in.sigma_add, in.gate(gate, S(0)),
                     [&](int, Vec<S, 6>& k) {
                       if (!params_.acc_tilt_only) return;
                       k[2] = sin_pitch * k[0];
                       k.template tail<3>() = (W * k.template tail<3>()).eval();
                     });
    });
    if (res.status != Status::Ok && res.status != Status::Rejected) st_ = before;
    return res;
  }

  /// Magnetometer update: the magnetometer part (reference field, disturbance tests), then the
  /// 3-row update against the reference [m_x, 0, m_z].
  UpdateResult<S, 3> update_mag(const Vec3<S>& mag, S gate = S(0)) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    Vec3<S> m;
    res.status = detail::unit_vector(mag, m);
    if (res.status != Status::Ok) return res;
    const auto field_n = [&] { return Vec3<S>(quat::rotate(quat(), m)); };
    // The dip test's tolerance grows with the filter's own dip variance (parts/mag_disturbance.hpp).
    const S dip_var = MagDisturbance<S>::widened(params_.mag)
                          ? MagDisturbance<S>::dip_variance(params_.mag, quat::to_rotmat(quat()), field_n(),
                                                            attitude_covariance())
                          : S(0);
    return MagDisturbance<S>::update(
        params_.mag, st_.mag, mag.norm(), field_n, st_.dt_last, flags_,
        [&] {
          const Vec3<S>& r = MagDisturbance<S>::reference(st_.mag);
          return update3(mag, r[0], r[2], params_.mag_sigma, gate);
        },
        dip_var);
  }

 private:
  /// At rest (parts/rest.hpp): the zero-rate measurement of the bias, z = w - b = 0 + noise.
  void update_zero_rate() {
    flags_ |= flags::kAtRest;
    const S r = Rest<S>::zero_rate_variance(params_.rest, params_.gyro_noise, st_.dt_last);
    UpdateResult<S, 3> res;
    correct<3, 3, 3>(Mat3<S>::Identity(), Vec3<S>::Constant(r), Rest<S>::zero_rate_innovation(st_.rest, st_.gyro_bias),
                     res, S(0));
  }

  Status init_impl(const Vec3<S>& acc, const Vec3<S>* mag) {
    if (!acc.allFinite() || (mag && !mag->allFinite())) return Status::NonFinite;
    Quat<S> q;
    Vec3<S> mref;
    if (!detail::attitude_from_acc_mag(acc, mag, q, mref)) return Status::ZeroNorm;
    st_.euler = quat::to_euler(q);
    st_.gyro_bias.setZero();
    st_.dt_last = S(0);
    // The parts start afresh; the reference field is learned from this sample (unless the user fixed it).
    restart_parts<S>(params_, st_, mag, mref);
    flags_ = 0;
    st_.P.setZero();
    st_.P.template topLeftCorner<3, 3>().diagonal().setConstant(params_.init_att_sigma * params_.init_att_sigma);
    st_.P.template bottomRightCorner<3, 3>().diagonal().setConstant(params_.init_gyro_bias_sigma *
                                                                    params_.init_gyro_bias_sigma);
    st_.initialized = true;
    return Status::Ok;
  }

  template <class Gain = OptimalGain>
  UpdateResult<S, 3> update3(const Vec3<S>& v, S rx, S rz, S sigma, S gate, const Gain& gain = Gain{}) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    Vec3<S> u;
    res.status = detail::unit_vector(v, u);
    if (res.status != Status::Ok) return res;
    Vec3<S> h;
    Mat3<S> H;
    detail::euler_measurement(st_.euler, rx, rz, h, H);
    correct<3, 0, 3>(H, Vec3<S>::Constant(sigma * sigma), Vec3<S>(u - h), res, gate, gain);
    return res;
  }

  /// The correction by the rows of H, given by its NC nonzero columns from C0 on, with R =
  /// diag(r): every measurement of this filter has uncorrelated components, so the rows are
  /// scalar sequential Joseph updates (kalman_correct_diagonal: the joint update of
  /// kalman_correct up to rounding, the same NIS), on one working copy of P; then the state.
  template <int M, int C0, int NC, class Gain = OptimalGain>
  void correct(const Mat<S, M, NC>& Hc, const Vec<S, M>& r, const Vec<S, M>& y, UpdateResult<S, M>& res, S gate,
               const Gain& gain = Gain{}) {
    Mat6 P = st_.P;
    Vec<S, 6> dx;
    if (kalman_correct_diagonal_in_place<S, 6, M, C0, NC>(P, Hc, r, y, dx, res, gate, gain) != Status::Ok) return;
    // An accepted update reports a finite innovation, innovation covariance and NIS (a P near the
    // float limit set by set_state can overflow H P H^T while the gain stays finite).
    if (!all_finite(P) || !all_finite(dx) || !all_finite(res.innovation) || !all_finite(res.innovation_cov) ||
        !std::isfinite(res.nis)) {
      res.status = Status::NumericalFailure;
      return;
    }
    floor_covariance<S, 6>(P, params_.cov_floor);
    // The floor's eigendecomposition of a covariance near the overflow limit can fail, a state
    // near it can overflow, and a correction of an indefinite P (set_state and reset take one)
    // can lose the non-negative diagonal: refused, nothing changed.
    if (!all_finite(P) || !detail::nonnegative_diagonal<S, 6>(P) ||
        !all_finite(Vec<S, 6>(dx + (Vec<S, 6>() << st_.euler, st_.gyro_bias).finished()))) {
      res.status = Status::NumericalFailure;
      return;
    }
    st_.euler += dx.template head<3>();
    st_.euler[0] = quat::wrap_pi(st_.euler[0]);
    st_.euler[2] = quat::wrap_pi(st_.euler[2]);
    st_.gyro_bias += dx.template tail<3>();
    st_.P = P;
  }

  Params params_{};
  State st_{};
  bool singular_ = false;
  std::uint32_t flags_ = 0;
};

}  // namespace quatnav
