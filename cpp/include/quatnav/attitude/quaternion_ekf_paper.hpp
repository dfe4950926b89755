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
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "attitude.hpp"
#include "quaternion_ekf_params.hpp"
#include "parts/parts.hpp"
#include "../core/commit.hpp"
#include "../core/covariance.hpp"
#include "../core/fields.hpp"
#include "../core/kalman.hpp"
#include "../core/quat_block.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

template <class S> struct QuaternionEKFPaperState {
  using MatP = Mat<S, 7, 7>;
  static constexpr const char* kCovarianceDoc = "covariance of [q_nb, gyro_bias]";
  QUATNAV_FIELDS(QuaternionEKFPaperState, QUATNAV_QEKF_STATE)
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

/// The time update f(x) and its Jacobian Phi = df/dx (eq. 9-10, exact discretization). Returns
/// the step's rotation dq = exp((w - b) T), q_out = q * dq.
template <class S>
Quat<S> qekf_propagate(const Quat<S>& q, const Vec3<S>& bias, const Vec3<S>& gyr, S dt, Quat<S>& q_out,
                       Mat<S, 7, 7>& Phi) {
  const Vec3<S> rv = (gyr - bias) * dt;  // rotation vector of the step, w~ T
  const Quat<S> dq = quat::from_rotvec(rv);
  q_out = quat::mul(q, dq);
  Phi.setIdentity();
  Phi.template topLeftCorner<4, 4>() = quat::right(dq);
  // d(q * dq)/db = left(q) d dq / d rv * d rv / db,  d rv / db = -dt I.
  Phi.template topRightCorner<4, 3>() = -dt * quat::left(q) * quat::from_rotvec_jacobian(rv);
  return dq;
}

/// The quaternion block of the state [q, b] (core/quat_block.hpp).
template <class S> using QekfBlock = QuatBlock<S, 7, 0>;

/// Covariance projection after q <- q/|q|: J = (I - q_hat q_hat^T)/|q| on the quaternion block,
/// written with J's rank-one structure so that P stays exactly symmetric
/// (QuatBlock::normalize_symmetric).
template <class S> void qekf_normalize(Quat<S>& q, Mat<S, 7, 7>& P) { QekfBlock<S>::normalize_symmetric(q, P); }

/// The covariance conditioning of QuaternionEKFPaper: P is made exactly symmetric (the
/// normalization's projection J P J^T is symmetric only up to rounding), then floored in its
/// error state [dtheta (3, rad, body frame), db (3, rad/s)] (QuatBlock's error-space floor):
/// a healthy P is unchanged and a repaired one keeps the structure. Returns true when the floor
/// was applied.
template <class S> bool qekf_floor_covariance(const Quat<S>& q, Mat<S, 7, 7>& P, S floor) {
  symmetrize(P);
  return QekfBlock<S>::floor_symmetric_error_covariance(q, P, floor);
}

/// qekf_floor_covariance for a P that is already exactly symmetric (as the filter keeps it:
/// its time update, Joseph update and normalization all produce symmetric blocks).
template <class S> bool qekf_floor_symmetric_covariance(const Quat<S>& q, Mat<S, 7, 7>& P, S floor) {
  return QekfBlock<S>::floor_symmetric_error_covariance(q, P, floor);
}

/// Heading-only magnetometer model. With m_n = C_nb(q) m (m the unit field in the body frame),
/// h(q) = atan2(m_n,y, m_n,x) is the heading of the field's horizontal projection (0 when the
/// attitude is right: the reference field points to x = magnetic north).
///
/// A navigation-frame rotation phi, q' = exp(phi) * q, changes q by dq = 1/2 R3 phi with
/// R3 = right(q).rightCols(3) (orthonormal columns). dh/dphi = [-y, x, 0]/(x^2+y^2) (-[m_n x]).
/// Its z part is 1 (a yaw rotation turns the field's heading one to one); its x, y parts (tilt)
/// are written to `J_tilt`. `H` (1x4, w.r.t. q) keeps the yaw part only: H = 2 R3.col(2)^T,
/// and `u` = R3.col(2) is the unit direction of a yaw change in quaternion space.
/// Returns false when the field is (nearly) vertical (no heading information).
template <class S>
bool heading_model(const Quat<S>& q, const Vec3<S>& m_unit, S& h, S& horiz2, Eigen::Matrix<S, 1, 4>& H,
                   Vec4<S>& u, Vec2<S>& J_tilt) {
  const Vec3<S> mn = quat::rotate(q, m_unit);
  horiz2 = mn[0] * mn[0] + mn[1] * mn[1];
  if (!(horiz2 > S(1e-6))) return false;
  h = std::atan2(mn[1], mn[0]);
  const Eigen::Matrix<S, 1, 3> dpsi_dmn(-mn[1] / horiz2, mn[0] / horiz2, S(0));
  const Eigen::Matrix<S, 1, 3> J = -dpsi_dmn * quat::skew(mn);
  J_tilt = Vec2<S>(J[0], J[1]);
  const Mat4<S> Rq = quat::right(q);
  u = Rq.col(3);
  H = S(2) * u.transpose();
  return true;
}

}  // namespace detail

template <class S> class QuaternionEKFPaper {
 public:
  using Scalar = S;
  using Params = QuaternionEKFParams<S>;
  using State = QuaternionEKFPaperState<S>;
  using Mat7 = Mat<S, 7, 7>;
  static constexpr int kStates = 7;

  QuaternionEKFPaper() = default;
  explicit QuaternionEKFPaper(const Params& p) : params_(p) {}

  const Params& params() const { return params_; }
  const State& state() const { return st_; }
  const Quat<S>& quat() const { return st_.q_nb; }
  const Vec3<S>& bias() const { return st_.gyro_bias; }
  const Mat7& covariance() const { return st_.P; }
  bool initialized() const { return st_.initialized; }
  /// Flags of the last sample (predict + updates) beyond the update statuses: kAtRest while rest
  /// is detected, kAccRejected / kMagRejected when the robustness tests rejected a measurement.
  std::uint32_t extra_flags() const { return flags_; }
  /// True while rest is detected (rest_detection on).
  bool at_rest() const { return Rest<S>::at_rest(params_.rest, st_.rest); }

  /// Restore a state previously read with state(). Refused (InvalidArgument) when the
  /// quaternion is not unit length or anything is non-finite.
  Status set_state(const State& s) {
    if (!detail::fields_finite(s)) return Status::NonFinite;
    if (std::abs(s.q_nb.norm() - S(1)) > S(1e-3)) return Status::InvalidArgument;
    if (!detail::acceptable_covariance<S, 7>(s.P)) return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// The diagonal of attitude_covariance() (rad^2), without the off-diagonal terms.
  Vec3<S> attitude_variance() const { return detail::QekfBlock<S>::attitude_variance(st_.q_nb, st_.P); }

  /// Attitude (4x4 quaternion block) as a 3x3 covariance of a body-frame rotation vector.
  Mat3<S> attitude_covariance() const {
    return detail::QekfBlock<S>::attitude_covariance(st_.q_nb, st_.P);
  }

  /// Set the normalized reference field from the dip (inclination) angle, positive down [rad].
  void set_mag_dip(S dip) { st_.mag.ref.fix(dip); }

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
    st_.q_nb = q / n;
    st_.gyro_bias = bias;
    st_.P = P_sym;
    st_.initialized = true;
    return Status::Ok;
  }

  /// Time update with one gyro sample [rad/s] over dt [s] (eq. 9, 13, 14).
  Status predict(const Vec3<S>& gyr, S dt) {
    if (!st_.initialized) return Status::NotInitialized;
    if (!all_finite(gyr)) return Status::NonFinite;
    if (!(dt > S(0)) || !(dt <= params_.max_dt)) return Status::InvalidDt;
    if (detail::saturated(gyr, params_.gyro_range)) return Status::Saturated;
    Quat<S> q_new;
    Mat7 Phi;
    const Quat<S> dq = detail::qekf_propagate(st_.q_nb, st_.gyro_bias, gyr, dt, q_new, Phi);
    // P = Phi P Phi^T + Q (eq. 13-14) by blocks, Phi = [F B; 0 I] (predict_covariance_fb).
    const Mat4<S> F = Phi.template topLeftCorner<4, 4>();
    const Mat43<S> B = Phi.template topRightCorner<4, 3>();
    const Mat43<S> X = quat::xi(q_new);
    Mat7 P_new;
    Mat4<S> Qqq = (dt * params_.gyro_noise * params_.gyro_noise / S(4)) * X * X.transpose();
    if (params_.gyro_rate_noise > S(0)) {  // the tilt noise of quaternion_ekf.hpp, mapped by X / 2
      const Mat3<S> Qt = detail::tilt_rate_noise<S>(Quat<S>(q_new / q_new.norm()), Vec3<S>(gyr - st_.gyro_bias),
                                                    params_.gyro_rate_noise, dt);
      Qqq += (X * Qt * X.transpose()) / S(4);
    }
    GyroClipState<S> clip = st_.clip;  // parts/gyro_clip.hpp, mapped by X / 2 as the tilt noise
    const Vec3<S> clip_var = GyroClip<S>::step(params_.clip, clip, gyr, dt);
    if ((clip_var.array() > S(0)).any()) Qqq += (X * clip_var.asDiagonal() * X.transpose()) / S(4);
    predict_covariance_fb<S, 4, 3>(st_.P, F, B, Qqq, S(dt * params_.gyro_bias_noise * params_.gyro_bias_noise), P_new);
    auto P_qq = P_new.template topLeftCorner<4, 4>();
    symmetrize(P_qq);  // the other blocks are symmetric by construction
    if (!all_finite(P_new) || !all_finite(q_new)) return Status::NumericalFailure;
    const Quat<S> q_unit = q_new / q_new.norm();
    detail::qekf_floor_symmetric_covariance(q_unit, P_new, params_.cov_floor);
    // An indefinite P (set_state and reset take one) propagated without a floor can lose its
    // non-negative diagonal, a state set_state would refuse: refused, nothing changed.
    if (!detail::nonnegative_diagonal<S, 7>(P_new)) return Status::NumericalFailure;
    st_.q_nb = q_unit;
    st_.P = P_new;
    flags_ = 0;
    st_.dt_last = dt;
    AccFilter<S>::predict(params_.acc, st_.acc, dq);
    if ((clip_var.array() > S(0)).any()) AccFilter<S>::restart(st_.acc);
    st_.clip = clip;
    Rest<S>::predict(params_.rest, st_.rest, gyr, dt);
    return Status::Ok;
  }

  /// Accelerometer update (rows 1-3 of eq. 12); acc normalized here (m/s^2 when the robustness
  /// parts are on). First the rest test (parts/rest.hpp): at rest, a zero-rate update of the bias
  /// precedes the acc update. Then the accelerometer part (parts/acc_filter.hpp): the low-passed
  /// sample, its rejection (status Rejected, kAccRejected) and adaptive noise; the NIS gate is
  /// `gate`, else acc_gate. A Rejected update leaves q, bias and P untouched but advances the
  /// parts' low-passes and timers: those follow the input signal.
  UpdateResult<S, 3> update_acc(const Vec3<S>& acc, S gate = S(0)) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    if (detail::saturated(acc, params_.acc_range)) return saturated_result<3>();
    Vec3<S> a;
    res.status = detail::unit_vector(acc, a);
    if (res.status != Status::Ok) return res;
    // As QuaternionEKF::update_acc: a failed update leaves the rest test and the low-pass too.
    const State before = st_;
    if (Rest<S>::update(params_.rest, st_.rest, acc, st_.gyro_bias, st_.dt_last)) update_zero_rate();
    // The 7-state filter keeps acc_lp_tau whatever its bias variance (max_bias_var 0).
    res = AccFilter<S>::update(params_.acc, st_.acc, acc, st_.dt_last, S(0), flags_, [&](const AccSample<S>& in) {
      return update3(in.acc, detail::qekf_h(st_.q_nb, S(0), S(-1)), detail::qekf_H(st_.q_nb, S(0), S(-1)),
                     params_.acc_sigma + in.sigma_add, in.gate(gate, params_.acc_gate));
    });
    if (res.status != Status::Ok && res.status != Status::Rejected) st_ = before;
    return res;
  }

  /// Magnetometer update; mag in any unit, normalized here.
  ///
  /// mag_heading_only (default): one row, the heading of the field (heading_model); the
  /// result's innovation[0] is the heading innovation [rad], innovation_cov(0,0) its variance
  /// (other rows zero). Otherwise rows 4-6 of eq. (12). Before either: the magnetometer part's
  /// disturbance tests (parts/mag_disturbance.hpp) may reject (status Rejected, kMagRejected);
  /// then the NIS gate (gate, else mag_gate). While accepted, the reference norm and dip follow
  /// the field with time constant mag_ref_tau.
  UpdateResult<S, 3> update_mag(const Vec3<S>& mag, S gate = S(0)) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    Vec3<S> m;
    res.status = detail::unit_vector(mag, m);
    if (res.status != Status::Ok) return res;
    const S gt = gate > S(0) ? gate : params_.mag_gate;
    const auto field_n = [&] { return Vec3<S>(quat::rotate(st_.q_nb, m)); };
    // The dip test's tolerance grows with the filter's own dip variance (parts/mag_disturbance.hpp).
    const S dip_var = MagDisturbance<S>::widened(params_.mag)
                          ? MagDisturbance<S>::dip_variance(params_.mag, quat::to_rotmat(st_.q_nb), field_n(),
                                                            attitude_covariance())
                          : S(0);
    return MagDisturbance<S>::update(
        params_.mag, st_.mag, mag.norm(), field_n, st_.dt_last, flags_,
        [&] {
          if (params_.mag_heading_only) return update_heading(m, gt);
          Vec3<S> h;
          Mat34<S> Hm;
          mag_model(h, Hm);
          return update3(mag, h, Hm, params_.mag_sigma, gt);
        },
        dip_var);
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
    const MagRef<S> ref_before = st_.mag.ref;
    st_.mag.ref.learn(quat::rotate(st_.q_nb, m), params_.mag.mag_ref_samples);
    Vec<S, 6> z, h;
    z << a, m;
    Mat<S, 6, 7> H = Mat<S, 6, 7>::Zero();
    Vec3<S> hm;
    Mat34<S> Hm;
    mag_model(hm, Hm);
    h << detail::qekf_h(st_.q_nb, S(0), S(-1)), hm;
    H.template block<3, 4>(0, 0) = detail::qekf_H(st_.q_nb, S(0), S(-1));
    H.template block<3, 4>(3, 0) = Hm;
    Vec<S, 6> r;
    r << Vec3<S>::Constant(params_.acc_sigma * params_.acc_sigma),
        Vec3<S>::Constant(params_.mag_sigma * params_.mag_sigma);
    apply_correction<6, 0, 4>(H, r, Vec<S, 6>(z - h), res, gate);
    if (res.status != Status::Ok) st_.mag.ref = ref_before;  // a refused update changes nothing
    return res;
  }

 private:
  /// At rest (parts/rest.hpp): the zero-rate measurement of the bias, z = w - b = 0 + noise.
  void update_zero_rate() {
    flags_ |= flags::kAtRest;
    Mat<S, 3, 7> H = Mat<S, 3, 7>::Zero();
    H.template rightCols<3>().setIdentity();
    const S r = Rest<S>::zero_rate_variance(params_.rest, params_.gyro_noise, st_.dt_last);
    UpdateResult<S, 3> res;
    apply_correction<3, 4, 3>(H, Vec3<S>::Constant(r), Rest<S>::zero_rate_innovation(st_.rest, st_.gyro_bias), res, S(0));
  }

  /// Heading-only magnetometer update (see heading_model): Kalman gain projected on the yaw
  /// direction, Joseph form with the projected gain (valid for any gain), R inflated by the
  /// tilt uncertainty seen through the field's dip: R = mag_noise^2 / h^2 + J_t Sigma_tilt J_t^T.
  UpdateResult<S, 3> update_heading(const Vec3<S>& m_unit, S gate) {
    UpdateResult<S, 3> res;
    S h, horiz2;
    Eigen::Matrix<S, 1, 4> Hq;
    Vec4<S> u;
    Vec2<S> Jt;
    if (!detail::heading_model(st_.q_nb, m_unit, h, horiz2, Hq, u, Jt)) {
      res.status = Status::ZeroNorm;
      return res;
    }
    // Tilt block of the navigation-frame attitude covariance (phi with q_true = exp(phi) * q,
    // phi = 2 R3^T dq, R3 = right(q).rightCols(3)): 4 R2^T P_qq R2 with R2 the x and y columns of R3; J_t Sigma J_t^T = 4 |P^1/2 R2 J_t|^2
    // evaluated as 4 v^T P_qq v with v = R2 J_t.
    const Vec4<S> v = quat::right(st_.q_nb).template middleCols<2>(1) * Jt;
    const S R = params_.mag_sigma * params_.mag_sigma / horiz2 +
                S(4) * v.dot(st_.P.template topLeftCorner<4, 4>() * v);
    // The field's heading is the declination (0: the frame's x is magnetic north).
    const S y = quat::wrap_pi(params_.declination == S(0) ? -h : params_.declination - h);
    Vec<S, 7> PHt;  // P H^T, H = [Hq 0]
    PHt.noalias() = st_.P.template leftCols<4>() * Hq.transpose();
    const S Sv = Hq.dot(PHt.template head<4>()) + R;
    res.innovation[0] = y;
    res.innovation_cov(0, 0) = Sv;
    if (!std::isfinite(Sv) || !std::isfinite(y)) {
      res.status = Status::NumericalFailure;
      return res;
    }
    if (!(Sv > S(0))) {
      res.status = Status::SolveFailed;
      return res;
    }
    res.nis = y * y / Sv;
    if (gate > S(0) && !(res.nis <= gate)) {
      res.status = Status::Rejected;
      return res;
    }
    Vec<S, 7> K = PHt / Sv;
    K.template head<4>() = (u * u.dot(K.template head<4>())).eval();  // yaw direction only
    Mat7 P = st_.P;
    joseph_update_scalar<S, 7>(P, K, PHt, Sv);  // Joseph form: valid for the projected gain
    const Vec<S, 7> dx = K * y;
    res.status = Status::Ok;
    inject_and_commit(
        res, P, [&] { return Quat<S>(st_.q_nb + dx.template head<4>()); },
        [&](const Quat<S>& q, const Mat7& Pc) { return all_finite(Pc) && all_finite(dx) && q.norm() > S(0.5); },
        [&](Quat<S>& q, Mat7& Pc) { return condition_candidate(q, Pc); },
        [&](const Quat<S>& q, const Mat7& Pc) { commit_candidate(q, Vec3<S>(dx.template tail<3>()), Pc); });
    return res;
  }

  Status init_impl(const Vec3<S>& acc, const Vec3<S>* mag) {
    if (!acc.allFinite() || (mag && !mag->allFinite())) return Status::NonFinite;
    Quat<S> q;
    Vec3<S> mref;
    if (!detail::attitude_from_acc_mag(acc, mag, q, mref)) return Status::ZeroNorm;
    if (mag && params_.declination != S(0)) {
      // Magnetic heading + declination = true heading (a rotation about the navigation down axis).
      q = quat::mul(quat::from_rotvec(Vec3<S>(S(0), S(0), params_.declination)), q);
    }
    st_.q_nb = q;
    st_.gyro_bias.setZero();
    st_.dt_last = S(0);
    // The parts start afresh; the reference field is learned from this sample (unless the user fixed it).
    restart_parts<S>(params_, st_, mag, mref);
    flags_ = 0;
    // Attitude sigma s (rad) on each body axis -> quaternion block (s/2)^2 Xi Xi^T.
    st_.P.setZero();
    const Mat43<S> X = quat::xi(st_.q_nb);
    const S sa = params_.init_att_sigma / S(2);
    st_.P.template topLeftCorner<4, 4>() = sa * sa * X * X.transpose();
    symmetrize(st_.P);  // X X^T is symmetric only up to rounding
    st_.P.template bottomRightCorner<3, 3>().diagonal().setConstant(params_.init_gyro_bias_sigma *
                                                                    params_.init_gyro_bias_sigma);
    st_.initialized = true;
    return Status::Ok;
  }

  /// Field model of the 3-row magnetometer update (eq. 12 rows 4-6) and its Jacobian w.r.t. q.
  /// The reference [rx, 0, rz] lies in the magnetic frame; with a declination d the filter's
  /// frame is true north and h(q) = C_bn(q) Rz(d) r = C_bn(q_m) r with q_m = Rz(-d) * q, so
  /// h and H are those of the paper at q_m, and H picks up the constant factor
  /// d q_m / d q = left(Rz(-d)) (chain rule).
  void mag_model(Vec3<S>& h, Mat34<S>& H) const {
    const S rx = st_.mag.ref.mag_ref[0], rz = st_.mag.ref.mag_ref[2];
    if (params_.declination == S(0)) {
      h = detail::qekf_h(st_.q_nb, rx, rz);
      H = detail::qekf_H(st_.q_nb, rx, rz);
      return;
    }
    const Quat<S> qd = quat::from_rotvec(Vec3<S>(S(0), S(0), -params_.declination));
    const Quat<S> qm = quat::mul(qd, st_.q_nb);
    h = detail::qekf_h(qm, rx, rz);
    H = detail::qekf_H(qm, rx, rz) * quat::left(qd);
  }

  /// One 3-row direction update: the unit vector of v against the model h(q) with Jacobian Hq.
  UpdateResult<S, 3> update3(const Vec3<S>& v, const Vec3<S>& h, const Mat34<S>& Hq, S sigma, S gate) {
    UpdateResult<S, 3> res;
    if (!st_.initialized) return res;
    Vec3<S> u;
    res.status = detail::unit_vector(v, u);
    if (res.status != Status::Ok) return res;
    Mat<S, 3, 7> H = Mat<S, 3, 7>::Zero();
    H.template leftCols<4>() = Hq;
    apply_correction<3, 0, 4>(H, Vec3<S>::Constant(sigma * sigma), Vec3<S>(u - h), res, gate);
    return res;
  }

  template <int M> static UpdateResult<S, M> saturated_result() {
    UpdateResult<S, M> r;
    r.status = Status::Saturated;
    return r;
  }

  /// H is nonzero only in its NC columns from C0 on (the quaternion or the bias block). Every
  /// measurement of this filter has uncorrelated components (R = diag(r)), so the rows are
  /// processed as sequential scalar updates (kalman_correct_diagonal: the joint update up to
  /// rounding, same NIS).
  template <int M, int C0, int NC>
  void apply_correction(const Mat<S, M, 7>& H, const Vec<S, M>& r, const Vec<S, M>& y,
                        UpdateResult<S, M>& res, S gate) {
    Mat7 P = st_.P;  // the one working copy; its finiteness is tested in the check step
    Vec<S, 7> dx;
    const Mat<S, M, NC> Hc = H.template middleCols<NC>(C0);
    kalman_correct_diagonal_in_place<S, 7, M, C0, NC>(P, Hc, r, y, dx, res, gate);
    inject_and_commit(
        res, P, [&] { return Quat<S>(st_.q_nb + dx.template head<4>()); },
        [](const Quat<S>& q, const Mat7& Pc) { return all_finite(Pc) && q.norm() > S(0.5); },
        [&](Quat<S>& q, Mat7& Pc) { return condition_candidate(q, Pc); },
        [&](const Quat<S>& q, const Mat7& Pc) { commit_candidate(q, Vec3<S>(dx.template tail<3>()), Pc); });
  }

  /// The conditioning of a corrected candidate (core/commit.hpp): q renormalized with P
  /// projected, then the error-state floor; refused when P is not one set_state takes (a
  /// correction of an indefinite P, or of one ill-conditioned beyond the precision, can lose the
  /// non-negative diagonal).
  bool condition_candidate(Quat<S>& q, Mat7& P) const {
    detail::qekf_normalize(q, P);
    detail::qekf_floor_symmetric_covariance(q, P, params_.cov_floor);
    return detail::nonnegative_diagonal<S, 7>(P);
  }

  void commit_candidate(const Quat<S>& q, const Vec3<S>& dbias, const Mat7& P) {
    st_.q_nb = q;
    st_.gyro_bias += dbias;
    st_.P = P;
  }

  Params params_{};
  State st_{};
  std::uint32_t flags_ = 0;  ///< flags of the current sample (diagnostic, not part of the state)
};

}  // namespace quatnav
