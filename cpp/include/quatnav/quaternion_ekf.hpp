// quatnav: quaternion EKF with gyro-bias states (Kim & Jang 2019, "An attitude determination
// method using a quaternion-based extended Kalman filter"; called paper 000 in the docs).
//
// State x = [q0 q1 q2 q3 bx by bz]^T (eq. 7): q = q_nb (body to navigation, Hamilton, scalar
// first) and the gyro bias b in rad/s. The navigation frame is the paper's: x = magnetic north,
// z = down (NED with magnetic north). Measurements: the normalized accelerometer (eq. 11-12,
// rows 1-3) and the normalized magnetometer (rows 4-6), each available as its own update.
//
// Deviations from the paper, each deliberate:
//  * eq. (6) integrates q with one Euler step, q(k) = (I + T/2 Omega) q(k-1). We use the exact
//    solution for a rate that is constant over the step, q(k) = q(k-1) * exp(w~ T / 2), and its
//    exact Jacobian. To first order in T both reduce to eq. (6) and eq. (10) (tested); the Euler
//    step loses 2 atan(a/2) - a per step (a = |w~| T), about 0.5 deg/s at 10 rad/s and 100 Hz.
//  * The algorithm listing (Section 2.3) never applies the state correction
//    x(k) = x(k,k-1) + K(k)[z(k) - h(x(k,k-1))]; we apply it and renormalize q afterwards, with
//    the covariance projected by the normalization's Jacobian.
//  * eq. (16) P = (I - K H) P is replaced by the Joseph form (kalman.hpp).
//  * Q "the integrated process noise" is not given in the paper; we derive it from a gyro white
//    noise density and a bias random-walk density:
//      Q_qq = T sigma_g^2 / 4 * Xi(q) Xi(q)^T,  Q_bb = T sigma_b^2 I.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "attitude.hpp"
#include "covariance.hpp"
#include "kalman.hpp"
#include "quaternion.hpp"
#include "types.hpp"

namespace quatnav {

/// Parameters of QuaternionEKF. Every field has its unit and default.
template <class S> struct QuaternionEKFParams {
  S gyro_noise = S(0.005);        ///< gyro white-noise density [rad/s/sqrt(Hz)]
  S gyro_bias_noise = S(1e-5);    ///< gyro bias random-walk density [rad/s^2/sqrt(Hz)]
  S acc_noise = S(0.05);          ///< std of each component of the normalized accelerometer [-]
  S mag_noise = S(0.1);           ///< std of each component of the normalized magnetometer [-]
  S init_att_sigma = S(0.05);     ///< initial attitude one-sigma after initialize() [rad]
  S init_bias_sigma = S(0.01);    ///< initial gyro-bias one-sigma [rad/s]
  std::uint32_t mag_ref_samples = 100;  ///< magnetometer samples averaged to learn the dip [-]
  S max_dt = S(1);                ///< a predict with dt above this is refused [s]
  S gyro_range = S(0);            ///< gyro range per axis; |w_i| >= it is Saturated [rad/s]; 0: unlimited
  S acc_range = S(0);             ///< accelerometer range per axis, unit of acc [m/s^2]; 0: unlimited
  S cov_floor = S(1e-12);         ///< eigenvalue floor of the error-state covariance (covariance.hpp) [rad^2, (rad/s)^2]; 0: off
};

/// The complete filter state; get_state()/set_state() round-trip exactly.
template <class S> struct QuaternionEKFState {
  Quat<S> q = quat::identity<S>();                ///< q_nb [w, x, y, z]
  Vec3<S> bias = Vec3<S>::Zero();                 ///< gyro bias [rad/s]
  Mat<S, 7, 7> P = Mat<S, 7, 7>::Identity();      ///< covariance of [q, bias]
  MagRef<S> mag;                                  ///< reference field, learned or given
  bool initialized = false;
};

namespace detail {

/// Paper 000 eq. (11)-(12): h(q) = C_bn(q) r for a reference vector r = [r_x, 0, r_z] in the
/// paper's own quadratic form (1 - 2q2^2 - 2q3^2, ...), with H = dh/dq as printed in the paper
/// (acceleration rows: r = [0, 0, -1]).
template <class S> Vec3<S> qekf_h(const Quat<S>& q, S rx, S rz) {
  const S q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
  return Vec3<S>(rx * (S(1) - S(2) * q2 * q2 - S(2) * q3 * q3) + S(2) * rz * (q1 * q3 - q0 * q2),
                 S(2) * rx * (q1 * q2 - q0 * q3) + S(2) * rz * (q2 * q3 + q0 * q1),
                 S(2) * rx * (q1 * q3 + q0 * q2) + rz * (S(1) - S(2) * q1 * q1 - S(2) * q2 * q2));
}

template <class S> Mat34<S> qekf_H(const Quat<S>& q, S rx, S rz) {
  const S q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
  Mat34<S> H;
  H << -S(2) * rz * q2, S(2) * rz * q3, -S(4) * rx * q2 - S(2) * rz * q0, -S(4) * rx * q3 + S(2) * rz * q1,
       -S(2) * rx * q3 + S(2) * rz * q1, S(2) * rx * q2 + S(2) * rz * q0, S(2) * rx * q1 + S(2) * rz * q3,
       -S(2) * rx * q0 + S(2) * rz * q2,
       S(2) * rx * q2, S(2) * rx * q3 - S(4) * rz * q1, S(2) * rx * q0 - S(4) * rz * q2, S(2) * rx * q1;
  return H;
}

/// The time update f(x) and its Jacobian Phi = df/dx (eq. 9-10, exact discretization).
template <class S>
void qekf_propagate(const Quat<S>& q, const Vec3<S>& bias, const Vec3<S>& gyr, S dt, Quat<S>& q_out,
                    Mat<S, 7, 7>& Phi) {
  const Vec3<S> rv = (gyr - bias) * dt;  // rotation vector of the step, w~ T
  const Quat<S> dq = quat::from_rotvec(rv);
  q_out = quat::mul(q, dq);
  Phi.setIdentity();
  Phi.template topLeftCorner<4, 4>() = quat::right(dq);
  // d(q * dq)/db = left(q) d dq / d rv * d rv / db,  d rv / db = -dt I.
  Phi.template topRightCorner<4, 3>() = -dt * quat::left(q) * quat::from_rotvec_jacobian(rv);
}

/// Covariance projection after q <- q/|q|: J = (I - q_hat q_hat^T)/|q| on the quaternion block.
template <class S> void qekf_normalize(Quat<S>& q, Mat<S, 7, 7>& P) {
  const S n = q.norm();
  const Quat<S> qh = q / n;
  const Mat4<S> J = (Mat4<S>::Identity() - qh * qh.transpose()) / n;
  P.template topLeftCorner<4, 4>() = (J * P.template topLeftCorner<4, 4>() * J.transpose()).eval();
  P.template topRightCorner<4, 3>() = (J * P.template topRightCorner<4, 3>()).eval();
  P.template bottomLeftCorner<3, 4>() = P.template topRightCorner<4, 3>().transpose();
  q = qh;
}

/// Attitude covariance (3x3, rad^2) of the body-frame rotation vector dtheta with
/// q_true = q * exp(dtheta), from the quaternion block: 4 Xi^T P_qq Xi.
template <class S> Mat3<S> quat_cov_to_angle_cov(const Quat<S>& q, const Mat4<S>& Pqq) {
  const Mat43<S> X = quat::xi(q);
  return S(4) * X.transpose() * Pqq * X;
}

}  // namespace detail

template <class S> class QuaternionEKF {
 public:
  using Scalar = S;
  using Params = QuaternionEKFParams<S>;
  using State = QuaternionEKFState<S>;
  using Mat7 = Mat<S, 7, 7>;
  static constexpr int kStates = 7;

  QuaternionEKF() = default;
  explicit QuaternionEKF(const Params& p) : params_(p) {}

  const Params& params() const { return params_; }
  const State& state() const { return st_; }
  const Quat<S>& quat() const { return st_.q; }
  const Vec3<S>& bias() const { return st_.bias; }
  const Mat7& covariance() const { return st_.P; }
  bool initialized() const { return st_.initialized; }
  /// Flags describing the last step beyond its update statuses (none for this filter).
  std::uint32_t extra_flags() const { return 0; }

  /// Restore a state previously read with state(). Refused (InvalidArgument) when the
  /// quaternion is not unit length or anything is non-finite.
  Status set_state(const State& s) {
    if (!s.q.allFinite() || !s.bias.allFinite() || !s.P.allFinite() || !s.mag.finite())
      return Status::NonFinite;
    if (std::abs(s.q.norm() - S(1)) > S(1e-3)) return Status::InvalidArgument;
    if (!detail::acceptable_covariance<S, 7>(s.P)) return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// Attitude (4x4 quaternion block) as a 3x3 covariance of a body-frame rotation vector.
  Mat3<S> attitude_covariance() const {
    return detail::quat_cov_to_angle_cov(st_.q, Mat4<S>(st_.P.template topLeftCorner<4, 4>()));
  }

  /// Set the normalized reference field from the dip (inclination) angle, positive down [rad].
  void set_mag_dip(S dip) {
    st_.mag.fix(dip);
  }

  /// Initialize from one accelerometer (and optionally magnetometer) sample: tilt from gravity,
  /// heading from the field (heading 0 without one); covariance from the parameters. The
  /// reference field is learned from this sample unless set_mag_dip() was called.
  Status initialize(const Vec3<S>& acc) { return init_impl(acc, nullptr); }
  Status initialize(const Vec3<S>& acc, const Vec3<S>& mag) { return init_impl(acc, &mag); }

  /// Start from a given attitude, bias and covariance.
  Status reset(const Quat<S>& q, const Vec3<S>& bias, const Mat7& P) {
    if (!q.allFinite() || !bias.allFinite() || !P.allFinite()) return Status::NonFinite;
    const S n = q.norm();
    if (!(n > S(0.5)) || !std::isfinite(n)) return Status::InvalidArgument;
    if (!(P.diagonal().array() >= S(0)).all()) return Status::InvalidArgument;
    Mat7 P_sym = P;
    symmetrize(P_sym);  // may overflow for huge finite entries: refuse those
    if (!P_sym.allFinite()) return Status::InvalidArgument;
    st_.q = q / n;
    st_.bias = bias;
    st_.P = P_sym;
    st_.initialized = true;
    return Status::Ok;
  }

  /// Time update with one gyro sample [rad/s] over dt [s] (eq. 9, 13, 14).
  Status predict(const Vec3<S>& gyr, S dt) {
    if (!st_.initialized) return Status::NotInitialized;
    if (!gyr.allFinite()) return Status::NonFinite;
    if (!(dt > S(0)) || !(dt <= params_.max_dt)) return Status::InvalidDt;
    if (detail::saturated(gyr, params_.gyro_range)) return Status::Saturated;
    Quat<S> q_new;
    Mat7 Phi;
    detail::qekf_propagate(st_.q, st_.bias, gyr, dt, q_new, Phi);
    Mat7 Q = Mat7::Zero();
    const Mat43<S> X = quat::xi(q_new);
    Q.template topLeftCorner<4, 4>() =
        (dt * params_.gyro_noise * params_.gyro_noise / S(4)) * X * X.transpose();
    Q.template bottomRightCorner<3, 3>().diagonal().setConstant(dt * params_.gyro_bias_noise *
                                                                params_.gyro_bias_noise);
    Mat7 P_new = Phi * st_.P * Phi.transpose() + Q;
    symmetrize(P_new);
    if (!P_new.allFinite() || !q_new.allFinite()) return Status::NumericalFailure;
    st_.q = q_new / q_new.norm();
    detail::qekf_floor_covariance(st_.q, P_new, params_.cov_floor);
    st_.P = P_new;
    return Status::Ok;
  }

  /// Accelerometer update (rows 1-3 of eq. 12); acc in any unit, normalized here.
  UpdateResult<S, 3> update_acc(const Vec3<S>& acc, S gate = S(0)) {
    if (st_.initialized && detail::saturated(acc, params_.acc_range)) return saturated_result<3>();
    return update3(acc, S(0), S(-1), params_.acc_noise, gate);
  }

  /// Magnetometer update (rows 4-6 of eq. 12); mag in any unit, normalized here.
  UpdateResult<S, 3> update_mag(const Vec3<S>& mag, S gate = S(0)) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    Vec3<S> m;
    res.status = detail::unit_vector(mag, m);
    if (res.status != Status::Ok) return res;
    const MagRef<S> mag_before = st_.mag;
    st_.mag.learn(quat::rotate(st_.q, m), params_.mag_ref_samples);
    res = update3(mag, st_.mag.ref[0], st_.mag.ref[2], params_.mag_noise, gate);
    if (res.status != Status::Ok) st_.mag = mag_before;  // a refused update changes nothing
    return res;
  }

  /// Joint accelerometer + magnetometer update, eq. (11)-(12) as one 6-vector.
  UpdateResult<S, 6> update_acc_mag(const Vec3<S>& acc, const Vec3<S>& mag, S gate = S(0)) {
    UpdateResult<S, 6> res;
    if (!st_.initialized) return res;
    if (detail::saturated(acc, params_.acc_range)) return saturated_result<6>();
    Vec3<S> a, m;
    res.status = detail::unit_vector(acc, a);
    if (res.status != Status::Ok) return res;
    res.status = detail::unit_vector(mag, m);
    if (res.status != Status::Ok) return res;
    const MagRef<S> mag_before = st_.mag;
    st_.mag.learn(quat::rotate(st_.q, m), params_.mag_ref_samples);
    Vec<S, 6> z, h;
    z << a, m;
    h << detail::qekf_h(st_.q, S(0), S(-1)), detail::qekf_h(st_.q, st_.mag.ref[0], st_.mag.ref[2]);
    Mat<S, 6, 7> H = Mat<S, 6, 7>::Zero();
    H.template block<3, 4>(0, 0) = detail::qekf_H(st_.q, S(0), S(-1));
    H.template block<3, 4>(3, 0) = detail::qekf_H(st_.q, st_.mag.ref[0], st_.mag.ref[2]);
    Mat<S, 6, 6> R = Mat<S, 6, 6>::Zero();
    R.diagonal() << Vec3<S>::Constant(params_.acc_noise * params_.acc_noise),
        Vec3<S>::Constant(params_.mag_noise * params_.mag_noise);
    apply_correction<6>(H, R, Vec<S, 6>(z - h), res, gate);
    if (res.status != Status::Ok) st_.mag = mag_before;  // a refused update changes nothing
    return res;
  }

 private:
  Status init_impl(const Vec3<S>& acc, const Vec3<S>* mag) {
    if (!acc.allFinite() || (mag && !mag->allFinite())) return Status::NonFinite;
    Quat<S> q;
    Vec3<S> mref;
    if (!detail::attitude_from_acc_mag(acc, mag, q, mref)) return Status::ZeroNorm;
    st_.q = q;
    st_.bias.setZero();
    if (mag) {
      // Start learning the reference afresh from this sample (unless the user fixed it).
      if (!st_.mag.fixed) st_.mag = MagRef<S>();
      st_.mag.learn(Vec3<S>(mref / mref.norm()), params_.mag_ref_samples);
    }
    // Attitude sigma s (rad) on each body axis -> quaternion block (s/2)^2 Xi Xi^T.
    st_.P.setZero();
    const Mat43<S> X = quat::xi(st_.q);
    const S sa = params_.init_att_sigma / S(2);
    st_.P.template topLeftCorner<4, 4>() = sa * sa * X * X.transpose();
    symmetrize(st_.P);  // X X^T is symmetric only up to rounding
    st_.P.template bottomRightCorner<3, 3>().diagonal().setConstant(params_.init_bias_sigma *
                                                                    params_.init_bias_sigma);
    st_.initialized = true;
    return Status::Ok;
  }

  UpdateResult<S, 3> update3(const Vec3<S>& v, S rx, S rz, S sigma, S gate) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    Vec3<S> u;
    res.status = detail::unit_vector(v, u);
    if (res.status != Status::Ok) return res;
    Mat<S, 3, 7> H = Mat<S, 3, 7>::Zero();
    H.template leftCols<4>() = detail::qekf_H(st_.q, rx, rz);
    const Mat3<S> R = Mat3<S>::Identity() * (sigma * sigma);
    apply_correction<3>(H, R, Vec3<S>(u - detail::qekf_h(st_.q, rx, rz)), res, gate);
    return res;
  }

  template <int M> static UpdateResult<S, M> saturated_result() {
    UpdateResult<S, M> r;
    r.status = Status::Saturated;
    return r;
  }

  template <int M>
  void apply_correction(const Mat<S, M, 7>& H, const Mat<S, M, M>& R, const Vec<S, M>& y,
                        UpdateResult<S, M>& res, S gate) {
    Mat7 P = st_.P;
    Vec<S, 7> dx;
    if (kalman_correct<S, 7, M>(P, H, R, y, dx, res, gate) != Status::Ok) return;
    Quat<S> q = st_.q + dx.template head<4>();
    if (!(q.norm() > S(0.5))) {
      res.status = Status::NumericalFailure;
      return;
    }
    detail::qekf_normalize(q, P);
    detail::qekf_floor_covariance(q, P, params_.cov_floor);
    st_.q = q;
    st_.bias += dx.template tail<3>();
    st_.P = P;
  }

  Params params_{};
  State st_{};
};

}  // namespace quatnav
