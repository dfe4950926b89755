// quatnav: the quaternion EKF of paper 000 as a 6-state multiplicative error-state filter.
//
// Same measurements (normalized accelerometer against gravity, magnetometer: 3-row field or
// heading only), same parameters (QuaternionEKFParams) and the same robustness parts as
// QuaternionEKFPaper (quaternion_ekf_paper.hpp), but the covariance is that of the error state
//     dx = [dtheta (3, rad), db (3, rad/s)],   q_true = q * exp(dtheta),  b_true = b + db,
// with dtheta a rotation vector in the BODY frame. The nominal quaternion is kept unit length
// (q <- q * exp(dtheta) after each correction), so there is no normalization Jacobian and no
// singular direction in P.
//
// Time update (exact for a constant rate w~ = w - b over dt, dq = exp(w~ dt)):
//     dtheta+ = C(dq)^T dtheta - dt db,   db+ = db,
// i.e. Phi = [F -dt I; 0 I], F = C(dq)^T (the transpose of dq's rotation matrix); the right
// Jacobian of exp that multiplies -dt db exactly is taken as I (its error is O(|w~| dt), 0.2 %
// at 0.8 rad/s and 200 Hz). Q = diag(dt sigma_g^2 I, dt sigma_b^2 I): the same densities as the
// 7-state filter (there Q_qq = dt sigma_g^2 / 4 Xi Xi^T is this Q_aa mapped to the quaternion).
// Q_aa also has the tilt noise that grows with the rate, dt (k |w~|)^2 (I - u u^T) for
// k = gyro_rate_noise and u the body-frame vertical (detail::tilt_rate_noise, attitude.hpp): the
// gyro's scale-factor and misalignment errors in fast motion, which the accelerometer corrects.
//
// Measurement Jacobians: h(q) = C_bn(q) r (r = [0, 0, -1] for gravity, the reference field for
// the magnetometer); C_bn(q exp(dtheta)) = (I - [dtheta x]) C_bn(q), so dh/ddtheta = [h x]
// and dh/ddb = 0: each row has 2 nonzero coefficients out of 6. The rows are uncorrelated and
// processed as scalar sequential updates (kalman_correct_diagonal_in_place, RowShape::Cross): in
// the Joseph form where the gain is not optimal (the Schmidt gains below) or the row is so strong
// that the symmetric form's rounding would matter, in the symmetric form P - k (P h)^T, one
// multiply-add per coefficient of the lower triangle, elsewhere (RowForm::SymmetricWhereOptimal:
// the zero-rate rows at rest, the 3-row magnetometer). The accelerometer's three rows are one
// 2-row block in the tangent plane of h instead (detail::eskf_gravity_correct): with R = sigma^2 I
// and a unit h, H = [h x] has rank 2 (H h = 0), and the rows along an orthonormal basis of the
// plane normal to h are the same measurement, exactly; the third row, along h, has a zero
// Jacobian and only adds its NIS term. After injecting dtheta the covariance is reset to the new
// nominal attitude (G = I - [dtheta/2 x]).
//
// The accelerometer carries no heading information: gravity is the vertical, and a rotation
// about it (u = C_bn e_z, the vertical in the body frame) leaves h unchanged (H u = 0). Its
// optimal gain still turns the heading and the earth-vertical gyro bias through the
// correlations of P (the heading error grows from the vertical bias; the tilt errors from the
// horizontal bias), and every linear acceleration the model takes for gravity then moves the
// heading and invents a vertical bias: on BROAD's 6D runs the accelerometer updates turned the
// heading by 6-20 deg over a trial. The accelerometer update is therefore a Schmidt-Kalman
// ("consider") update: its gain is projected off u in both blocks, k <- [(I - u u^T) k_a;
// W k_b], so it corrects the tilt and the horizontal bias only (as VQF, which estimates the bias
// in motion in the horizontal plane of the earth frame). W = I - u u^T while the body does not
// turn; under fast rotation W (AccFilter::bias_weight, parts/acc_filter.hpp) also leaves out the
// body directions that swung through the vertical within the low-pass time, whose bias the
// accelerometer sees only through the motion's own acceleration errors. The Joseph form
// keeps P the covariance of the error for this gain, and since u is in the null space of H the
// innovation, its covariance and the NIS are those of the optimal update. The heading and the
// vertical bias are corrected by the magnetometer, by the zero-rate measurement at rest, and
// as the body turns (the bias part that was vertical becomes horizontal). acc_tilt_only = false
// (paper()) restores the optimal gain.
//
// Covariance health: after every time update P - cov_floor I is positive definite. It is either
// proven or tested (an LDL^T of P - cov_floor I, floored only when that fails: covariance.hpp).
// The proof (detail::eskf_floor_implied): every step between two time updates keeps P positive
// semi-definite up to rounding (the scalar Joseph updates, P+ = (I - k h^T) P (I - k h^T)^T +
// r k k^T for any gain; the symmetric form, the same matrix for the optimal gain, with a rounding
// of a few eps |P| per coefficient too, |k_i a_j| <= sqrt(P_ii P_jj); and the reset's congruence
// G P G^T), and the time update adds
// Q = diag(qa I, qb I) (plus the tilt noise, positive semi-definite); so if P was positive
// semi-definite at the last time update, the new P - cov_floor I has no eigenvalue below
// min(qa, qb) - cov_floor - (the rounding of one sample). When that margin exceeds a generous
// bound of the rounding (a multiple of eps trace(P), trace(P) >= |P|_2), the test is skipped: it
// could only pass. The premise holds
// after initialize() (a diagonal P) and after every time update that tested or proved P; after
// reset() and set_state() (a P from outside) and after a failed floor, the next time update
// tests. With the defaults at 200 Hz (qb = 5e-11 against a floor of 1e-12) the test is skipped
// in float64 once the covariance has settled; in float32 the rounding bound is larger than the
// margin and the test runs every sample, as before. A skipped test never changes a result: the
// LDL^T it replaces would have passed. The updates keep P symmetric by construction
// (joseph_update_scalar mirrors the triangle it computes).
#pragma once

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <limits>

#include "attitude.hpp"
#include "parts/parts.hpp"
#include "quaternion_ekf_params.hpp"
#include "../core/commit.hpp"
#include "../core/covariance.hpp"
#include "../core/kalman.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

/// The complete state of QuaternionEKF; state()/set_state() round-trip exactly. The fields of
/// QuaternionEKFPaperState (one table, QUATNAV_QEKF_STATE) with the 6x6 error-state covariance.
template <class S> struct QuaternionEKFState {
  using MatP = Mat<S, 6, 6>;
  static constexpr const char* kCovarianceDoc = "covariance of the error state [dtheta (body, rad), d gyro_bias]";
  QUATNAV_FIELDS(QuaternionEKFState, QUATNAV_QEKF_STATE)
};

namespace detail {

/// The error-state time update: nominal q+ = q * exp((w - b) dt) and F = C(dq)^T, the
/// attitude-error block of Phi = [F -dt I; 0 I]. Returns the step's rotation dq.
template <class S> Quat<S> eskf_propagate(const Quat<S>& q, const Vec3<S>& rate, S dt, Quat<S>& q_out, Mat3<S>& F) {
  const Quat<S> dq = quat::from_rotvec(Vec3<S>(rate * dt));
  q_out = quat::mul(q, dq);
  F = quat::to_rotmat(dq).transpose();
  return dq;
}

/// The same for a gyro sample and the bias estimate: rate = gyr - bias.
template <class S>
Quat<S> eskf_propagate(const Quat<S>& q, const Vec3<S>& bias, const Vec3<S>& gyr, S dt, Quat<S>& q_out, Mat3<S>& F) {
  return eskf_propagate<S>(q, Vec3<S>(gyr - bias), dt, q_out, F);
}

/// P+ = Phi P Phi^T + Q for Phi = [F -dt I; 0 I], Q = diag(qa I, qb I), by blocks (P = [A C; C^T D]):
///   P+_aa = F A F^T - dt (F C + (F C)^T) + dt^2 D + qa I,  P+_ab = F C - dt D,  P+_bb = D + qb I.
/// Every block is written exactly symmetric (the attitude block by its lower triangle). Writes
/// P_new (not aliasing P).
template <class S> void eskf_predict_covariance(const Mat<S, 6, 6>& P, const Mat3<S>& F, S dt, S qa, S qb,
                                                Mat<S, 6, 6>& P_new) {
  const auto A = P.template topLeftCorner<3, 3>();
  const auto C = P.template topRightCorner<3, 3>();
  const auto D = P.template bottomRightCorner<3, 3>();
  Mat3<S> FC;
  FC.noalias() = F * C;
  Mat3<S> FA;
  FA.noalias() = F * A;
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i) {
      const S v = FA.row(i).dot(F.row(j)) - dt * (FC(i, j) + FC(j, i)) + dt * dt * D(i, j) + (i == j ? qa : S(0));
      P_new(i, j) = P_new(j, i) = v;
    }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) P_new(i, 3 + j) = P_new(3 + j, i) = FC(i, j) - dt * D(i, j);  // top-right block
  P_new.template bottomRightCorner<3, 3>() = D;
  P_new.template bottomRightCorner<3, 3>().diagonal().array() += qb;
}

/// In place: the same update through a copy.
template <class S> void eskf_predict_covariance(Mat<S, 6, 6>& P, const Mat3<S>& F, S dt, S qa, S qb) {
  const Mat<S, 6, 6> P0 = P;
  eskf_predict_covariance<S>(P0, F, dt, qa, qb, P);
}

/// True when P_new - floor I is positive definite by the argument at the top of this file, for
/// P_new = Phi P Phi^T + diag(qa I, qb I) computed from a P that was positive semi-definite up
/// to rounding: the margin min(qa, qb) - floor exceeds 256 N eps trace(P_new). That bound covers
/// with room the rounding of one sample (the time update, up to a few scalar Joseph updates and
/// covariance resets, each within a few eps |P| per coefficient, |a_i k_j| <= sqrt(P_ii P_jj)
/// for the gains used, N of them per row for the 2-norm) and of the LDL^T test it replaces.
template <class S, int N> bool eskf_floor_implied(const Mat<S, N, N>& P_new, S qa, S qb, S floor) {
  const S margin = std::min(qa, qb) - floor;
  return margin > S(256 * N) * std::numeric_limits<S>::epsilon() * P_new.trace();
}

/// The direction model h = C_bn(q) r_n and its error-state Jacobian [[h x], 0] (3 x 6): Ha is
/// the attitude block [h x]; the bias block is zero.
template <class S> void eskf_direction_model(const Quat<S>& q, const Vec3<S>& r_n, Vec3<S>& h, Mat3<S>& Ha) {
  h = quat::rotate_inv(q, r_n);
  Ha = quat::skew(h);
}

/// Heading model in the error state: with m_n = C_nb m, h = atan2(m_n,y, m_n,x). A body-frame
/// error dtheta is the navigation-frame rotation phi = C_nb dtheta; dh/dphi = [J_tilt, 1].
/// `u` (body frame) = C_nb^T e_z, the direction of a yaw change in the error space, so that
/// H (yaw part only) = u^T; `v_tilt` = C_nb^T [J_tilt, 0] maps the tilt part. False for a
/// (nearly) vertical field. Given C = C_nb(q) and the unit field in the navigation frame
/// mn = C m_unit (shared with the magnetometer part's tests); the overload on q below computes both.
template <class S>
bool eskf_heading_model(const Mat3<S>& C, const Vec3<S>& mn, S& h, S& horiz2, Vec3<S>& u, Vec3<S>& v_tilt) {
  horiz2 = mn[0] * mn[0] + mn[1] * mn[1];
  if (!(horiz2 > S(1e-6))) return false;
  h = quat::atan2_small(mn[1], mn[0]);  // near 0 while the heading tracks (no declination)
  // J_tilt = -(dpsi/dmn) [mn x] = (mn x dpsi/dmn)^T for dpsi/dmn = [-mn_y, mn_x, 0] / horiz2:
  // its first two components -mn_z [mn_x, mn_y] / horiz2 (the third is 1, the yaw's own).
  const S g = -mn[2] / horiz2;
  u = C.row(2).transpose();
  v_tilt = C.row(0).transpose() * (g * mn[0]) + C.row(1).transpose() * (g * mn[1]);
  return true;
}

/// The heading model at the attitude q for the unit body-frame field m_unit.
template <class S>
bool eskf_heading_model(const Quat<S>& q, const Vec3<S>& m_unit, S& h, S& horiz2, Vec3<S>& u, Vec3<S>& v_tilt) {
  const Mat3<S> C = quat::to_rotmat(q);  // C_nb
  return eskf_heading_model<S>(C, Vec3<S>(C * m_unit), h, horiz2, u, v_tilt);
}

/// The gain of the accelerometer rows (the top of the file): the first `rows` rows' gains
/// projected off the body-frame vertical `u` (unit) in the attitude block and weighted by `W`
/// (AccFilter::bias_weight: I - u u^T, or less for directions that swung through the vertical)
/// in the bias block, so that they turn neither the heading nor the earth-vertical gyro bias;
/// later rows (the magnetometer's in a joint update) keep theirs.
template <class S> struct HeadingFreeRows {
  Vec3<S> u;
  Mat3<S> W;
  int rows;
  bool optimal(int row) const { return row >= rows; }
  void operator()(int row, Vec<S, 6>& k) const {
    if (row >= rows) return;
    k.template head<3>() -= u * u.dot(k.template head<3>());
    k.template tail<3>() = (W * k.template tail<3>()).eval();
  }
};

/// The columns J, J+1, ... of joseph_update_block's lower triangle, as joseph_columns
/// (core/kalman.hpp) does the scalar form's: whole SIMD packets from the packet boundary below
/// the diagonal (the few coefficients above it are overwritten by the mirror).
template <class S, int N, int M, int J>
void joseph_block_columns(Mat<S, N, N>& P, const Mat<S, N, M>& A, const Mat<S, N, M>& K, const Mat<S, N, M>& B) {
  if constexpr (J < N) {
    constexpr int kPacket = Eigen::internal::packet_traits<S>::Vectorizable ? Eigen::internal::packet_traits<S>::size : 1;
    constexpr int I0 = J - J % kPacket;
    constexpr int L = N - I0;
    auto col = P.col(J).template segment<L>(I0);
    for (int m = 0; m < M; ++m)
      col = col - A.col(m).template segment<L>(I0) * K(J, m) - K.col(m).template segment<L>(I0) * B(J, m);
    joseph_block_columns<S, N, M, J + 1>(P, A, K, B);
  }
}

/// The Joseph-form update of an M-row block for any gain K (N x M), given A = P H^T (N x M)
/// and the innovation covariance Sm = H P H^T + R (M x M, symmetric):
///   P+ = (I - K H) P (I - K H)^T + K R K^T = P - A K^T - K A^T + K Sm K^T = P - A K^T - K B^T,
/// B = A - K Sm (as joseph_update_scalar's b: rounding noise for the optimal gain K = A Sm^-1).
/// One pass over the lower triangle, 2 M multiply-adds per coefficient, P+(i, j) = P(i, j) -
/// sum_m (A(i, m) K(j, m) + K(i, m) B(j, m)), mirrored (exactly symmetric). In place. Columns as
/// vector expressions where there is SIMD, one loop writing both halves where there is none.
/// (Here, not in core/kalman.hpp, while the gravity rows below are its only user.)
template <class S, int N, int M>
void joseph_update_block(Mat<S, N, N>& P, const Mat<S, N, M>& K, const Mat<S, N, M>& A, const Mat<S, M, M>& Sm) {
  Mat<S, N, M> B = A;
  B.noalias() -= K.lazyProduct(Sm);
  if constexpr (Eigen::internal::packet_traits<S>::Vectorizable && Eigen::internal::packet_traits<S>::size > 1) {
    joseph_block_columns<S, N, M, 0>(P, A, K, B);
    mirror_lower<S, N, 0>(P);
  } else {
    S* p = P.data();  // column-major: P(i, j) = p[i + N j]
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 16
#endif
    for (int j = 0; j < N; ++j) {
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 16
#endif
      for (int i = j; i < N; ++i) {
        S v = p[i + N * j];
        for (int m = 0; m < M; ++m) v = v - A(i, m) * K(j, m) - K(i, m) * B(j, m);
        p[i + N * j] = v;
        p[j + N * i] = v;
      }
    }
  }
}

/// The three gravity rows, H = [h x] for the unit direction h and R = r I, as two rows in the
/// tangent plane of h (the top of this file). For an orthonormal body-frame basis (c1, c2, h),
/// T = [c1 c2 h]^T is orthogonal and T R T^T = R, so the rows T y = T H dtheta + T n are the same
/// measurement; since c^T [h x] dtheta = (c x h)^T dtheta, they are
///   c1 . y = (c1 x h)^T dtheta,   c2 . y = (c2 x h)^T dtheta,   h . y = 0 (+ noise):
/// the third has a zero Jacobian and adds only its term (h . y)^2 / r to the NIS. With b1 the unit
/// vector along e_k x h (k the axis least aligned with h) and b2 = h x b1: c1 = b2, c2 = -b1, whose
/// rows are G = [b1^T; b2^T]. The two rows are one block: A = P G^T, Sm = G A_top + r I (2 x 2,
/// inverted in closed form), K = A Sm^-1 mapped by `gain` (HeadingFreeRows: the projection off
/// the vertical u = -h, which lies in the null space of G, so the innovations, Sm and the NIS
/// are those of the optimal update), dx = K y', and the Joseph form for that gain in one pass
/// (detail::joseph_update_block). Exactly the sequential three rows of kalman_correct_diagonal_in_place
/// (the same gain, the same covariance; the rows' projected gains give the projected joint
/// gain), up to rounding, in two rows' work; a gated sample is refused before P is touched. The
/// result's innovation is y and its covariance H P H^T + r I in body axes, rebuilt as
/// r I + C2 (Sm - r I) C2^T with C2 = [c1 c2]. Statuses and the contract on Pw as
/// kalman_correct_diagonal_in_place (Pw is written only for Ok; the caller tests it for finiteness).
template <class S, class Gain>
Status eskf_gravity_correct(Mat<S, 6, 6>& Pw, const Vec3<S>& h, const Vec3<S>& y, S r, Vec<S, 6>& dx,
                            UpdateResult<S, 3>& res, S gate, const Gain& gain) {
  res.innovation = y;
  if (!all_finite(h) || !std::isfinite(r) || !all_finite(y)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  const Vec3<S> ah = h.cwiseAbs();
  const int k = ah[0] <= ah[1] ? (ah[0] <= ah[2] ? 0 : 2) : (ah[1] <= ah[2] ? 1 : 2);
  Vec3<S> b1 = Vec3<S>::Zero();  // e_k x h
  b1[(k + 1) % 3] = -h[(k + 2) % 3];
  b1[(k + 2) % 3] = h[(k + 1) % 3];
  b1 /= b1.norm();  // |e_k x h|^2 = 1 - h_k^2 >= 2/3
  const Vec3<S> b2 = h.cross(b1);
  Mat<S, 6, 2> A;
  A.col(0).noalias() = Pw.template leftCols<3>() * b1;
  A.col(1).noalias() = Pw.template leftCols<3>() * b2;
  Mat<S, 2, 2> D;  // G P_aa G^T
  D(0, 0) = b1.dot(A.col(0).template head<3>());
  D(1, 1) = b2.dot(A.col(1).template head<3>());
  D(0, 1) = D(1, 0) = b1.dot(A.col(1).template head<3>());
  Mat<S, 2, 2> Sm = D;
  Sm.diagonal().array() += r;
  // C2 D C2^T for C2 = [b2, -b1]: the body-axes innovation covariance beside r I.
  const Vec3<S> w0 = b2 * D(0, 0) - b1 * D(0, 1), w1 = b2 * D(0, 1) - b1 * D(1, 1);
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i)
      res.innovation_cov(i, j) = res.innovation_cov(j, i) = w0[i] * b2[j] - w1[i] * b1[j] + (i == j ? r : S(0));
  if (!all_finite(Sm)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  const S det = Sm(0, 0) * Sm(1, 1) - Sm(0, 1) * Sm(0, 1);
  if (!(Sm(0, 0) > S(0)) || !(det > S(0))) {
    res.status = Status::SolveFailed;
    return res.status;
  }
  const Vec<S, 2> yt(b2.dot(y), -b1.dot(y));
  const S y3 = h.dot(y);
  const S inv_det = S(1) / det;
  Mat<S, 2, 2> Si;
  Si << Sm(1, 1) * inv_det, -Sm(0, 1) * inv_det, -Sm(0, 1) * inv_det, Sm(0, 0) * inv_det;
  const Vec<S, 2> z = Si * yt;
  res.nis = yt.dot(z) + y3 * y3 / r;
  if (gate > S(0) && !(res.nis <= gate)) {
    res.status = Status::Rejected;
    return res.status;
  }
  Mat<S, 6, 2> K;
  K.noalias() = A * Si;
  for (int m = 0; m < 2; ++m) {
    Vec<S, 6> km = K.col(m);
    gain(0, km);
    K.col(m) = km;
  }
  const Vec<S, 6> dxw = K * yt;
  if (!all_finite(dxw) || !std::isfinite(res.nis)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  joseph_update_block<S, 6, 2>(Pw, K, A, Sm);
  dx = dxw;
  res.status = Status::Ok;
  return res.status;
}

/// The covariance reset after injecting dtheta: the error of q+ = q * exp(dtheta) is
/// dtheta+ = G (dtheta_true - dtheta), G = I - [dtheta/2 x] to first order, so
/// P_aa <- G P_aa G^T and P_ab <- G P_ab (the bias block is unchanged). In place, symmetric.
template <class S> void eskf_reset_covariance(Mat<S, 6, 6>& P, const Vec3<S>& dtheta) {
  const Mat3<S> G = Mat3<S>::Identity() - quat::skew(Vec3<S>(dtheta * S(0.5)));
  const Mat3<S> A = P.template topLeftCorner<3, 3>();
  Mat3<S> GA;
  GA.noalias() = G * A;
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i) P(i, j) = P(j, i) = GA.row(i).dot(G.row(j));
  const Mat3<S> C = G * P.template topRightCorner<3, 3>();
  P.template topRightCorner<3, 3>() = C;
  P.template bottomLeftCorner<3, 3>() = C.transpose();
}

}  // namespace detail

/// Quaternion EKF with gyro-bias states in error-state form (see the top of this file).
/// Parameters: QuaternionEKFParams (the same fields, meanings and defaults).
template <class S> class QuaternionEKF {
 public:
  using Scalar = S;
  using Params = QuaternionEKFParams<S>;
  using State = QuaternionEKFState<S>;
  using Mat6 = Mat<S, 6, 6>;
  static constexpr int kStates = 6;

  QuaternionEKF() = default;
  explicit QuaternionEKF(const Params& p) : params_(p) {}

  const Params& params() const { return params_; }
  const State& state() const { return st_; }
  const Quat<S>& quat() const { return st_.q_nb; }
  const Vec3<S>& bias() const { return st_.gyro_bias; }
  const Mat6& covariance() const { return st_.P; }
  bool initialized() const { return st_.initialized; }
  /// Flags of the last sample beyond the update statuses (kAtRest, kAccRejected, kMagRejected).
  std::uint32_t extra_flags() const { return flags_; }
  bool at_rest() const { return Rest<S>::at_rest(params_.rest, st_.rest); }

  Status set_state(const State& s) {
    if (!detail::fields_finite(s)) return Status::NonFinite;
    if (std::abs(s.q_nb.norm() - S(1)) > S(1e-3)) return Status::InvalidArgument;
    if (!detail::acceptable_covariance<S, 6>(s.P)) return Status::InvalidArgument;
    st_ = s;
    cov_psd_ = false;  // a covariance from outside: the next time update tests it
    return Status::Ok;
  }

  /// Attitude covariance of dtheta (body frame, rad^2): the top-left block of P.
  Mat3<S> attitude_covariance() const { return st_.P.template topLeftCorner<3, 3>(); }
  Vec3<S> attitude_variance() const { return st_.P.diagonal().template head<3>(); }

  void set_mag_dip(S dip) { st_.mag.ref.fix(dip); }

  Status initialize(const Vec3<S>& acc) { return init_impl(acc, nullptr); }
  Status initialize(const Vec3<S>& acc, const Vec3<S>& mag) { return init_impl(acc, &mag); }

  /// Start from a given attitude, bias and 6x6 error-state covariance.
  Status reset(const Quat<S>& q, const Vec3<S>& bias, const Mat6& P) {
    if (!q.allFinite() || !bias.allFinite() || !P.allFinite()) return Status::NonFinite;
    const S n = q.norm();
    if (!(n > S(0.5)) || !std::isfinite(n)) return Status::InvalidArgument;
    if (!(P.diagonal().array() >= S(0)).all()) return Status::InvalidArgument;
    Mat6 P_sym = P;
    symmetrize(P_sym);
    if (!P_sym.allFinite()) return Status::InvalidArgument;
    st_.q_nb = q / n;
    st_.gyro_bias = bias;
    st_.P = P_sym;
    st_.initialized = true;
    cov_psd_ = false;
    return Status::Ok;
  }

  /// Time update with one gyro sample [rad/s] over dt [s]; the covariance health of the sample,
  /// proven or tested (the top of this file).
  Status predict(const Vec3<S>& gyr, S dt) {
    if (!st_.initialized) return Status::NotInitialized;
    if (!all_finite(gyr)) return Status::NonFinite;
    if (!(dt > S(0)) || !(dt <= params_.max_dt)) return Status::InvalidDt;
    if (detail::saturated(gyr, params_.gyro_range)) return Status::Saturated;
    const Vec3<S> rate = gyr - st_.gyro_bias;
    Quat<S> q_new;
    Mat3<S> F;
    const Quat<S> dq = detail::eskf_propagate<S>(st_.q_nb, rate, dt, q_new, F);
    q_new /= q_new.norm();
    Mat6 P_new;
    const S qa = dt * params_.gyro_noise * params_.gyro_noise;
    const S qb = dt * params_.gyro_bias_noise * params_.gyro_bias_noise;
    detail::eskf_predict_covariance<S>(st_.P, F, dt, qa, qb, P_new);
    GyroClipState<S> clip = st_.clip;  // parts/gyro_clip.hpp: a clipped axis's step is distrusted
    const Vec3<S> clip_var = GyroClip<S>::step(params_.clip, clip, gyr, dt);
    P_new.diagonal().template head<3>() += clip_var;
    if (params_.gyro_rate_noise > S(0)) {  // positive semi-definite: the floor's argument holds
      P_new.template topLeftCorner<3, 3>() += detail::tilt_rate_noise<S>(q_new, rate, params_.gyro_rate_noise, dt);
    }
    if (!all_finite(P_new) || !all_finite(q_new)) return Status::NumericalFailure;
    bool psd = true;
    if (params_.cov_floor > S(0) && !(cov_psd_ && detail::eskf_floor_implied<S, 6>(P_new, qa, qb, params_.cov_floor))) {
      Mat6 shifted = P_new;
      shifted.diagonal().array() -= params_.cov_floor;
      if (!detail::has_cholesky<S, 6>(shifted)) {
        psd = floor_covariance<S, 6>(P_new, params_.cov_floor);
        // The floor's eigendecomposition of a covariance near the overflow limit (one given by
        // set_state or reset) can fail: refused, nothing changed.
        if (!all_finite(P_new)) return Status::NumericalFailure;
      }
    }
    // A P given by set_state or reset may be indefinite: propagated (without a floor) it can
    // lose its non-negative diagonal, a state set_state would refuse: refused, nothing changed.
    if (!detail::nonnegative_diagonal<S, 6>(P_new)) return Status::NumericalFailure;
    st_.q_nb = q_new;
    cov_psd_ = psd;
    st_.P = P_new;
    flags_ = 0;
    st_.dt_last = dt;
    AccFilter<S>::predict(params_.acc, st_.acc, dq);
    if ((clip_var.array() > S(0)).any()) AccFilter<S>::restart(st_.acc);
    st_.clip = clip;
    Rest<S>::predict(params_.rest, st_.rest, gyr, dt);
    return Status::Ok;
  }

  /// Accelerometer update: the rest test and the accelerometer part as in QuaternionEKFPaper::update_acc,
  /// the low-pass time constant following the gyro-bias variance (acc_lp_bias_sigma); then 3
  /// scalar rows.
  UpdateResult<S, 3> update_acc(const Vec3<S>& acc, S gate = S(0)) {
    if (!st_.initialized) return status_result<3>(Status::NotInitialized);
    if (detail::saturated(acc, params_.acc_range)) return status_result<3>(Status::Saturated);
    Vec3<S> a;
    const Status ua = detail::unit_vector(acc, a);
    if (ua != Status::Ok) return status_result<3>(ua);
    // The rest test (and its zero-rate update) and the low-pass take the sample before the
    // update; an update that fails (SolveFailed, NumericalFailure) leaves all of it as it was:
    // the two parts' states, and q, b and P where the zero-rate update changed them (the gravity
    // update changes them only when it succeeds).
    const RestState<S> rest_before = st_.rest;
    const AccFilterState<S> acc_before = st_.acc;
    Quat<S> q_before;
    Vec3<S> b_before;
    Mat6 P_before;
    const bool zero_rate = Rest<S>::update(params_.rest, st_.rest, acc, st_.gyro_bias, st_.dt_last);
    if (zero_rate) {
      q_before = st_.q_nb;
      b_before = st_.gyro_bias;
      P_before = st_.P;
      update_zero_rate();
    }
    const S bias_var = st_.P.diagonal().template tail<3>().maxCoeff();
    const Vec3<S> up = quat::rotate_inv(st_.q_nb, Vec3<S>(S(0), S(0), S(1)));  // the vertical, body frame
    UpdateResult<S, 3> res = AccFilter<S>::update(
        params_.acc, st_.acc, acc, st_.dt_last, bias_var, flags_,
        [&](const AccSample<S>& in) {
          return update_gravity(in.acc, params_.acc_sigma + in.sigma_add, in.gate(gate, params_.acc_gate));
        },
        up);
    if (res.status != Status::Ok && res.status != Status::Rejected) {
      st_.rest = rest_before;
      st_.acc = acc_before;
      if (zero_rate) {
        st_.q_nb = q_before;
        st_.gyro_bias = b_before;
        st_.P = P_before;
      }
    }
    return res;
  }

  /// Magnetometer update: the magnetometer part as in QuaternionEKFPaper::update_mag, then the
  /// heading-only or the 3-row update.
  UpdateResult<S, 3> update_mag(const Vec3<S>& mag, S gate = S(0)) {
    if (!st_.initialized) return status_result<3>(Status::NotInitialized);
    Vec3<S> m;
    const Status um = detail::unit_vector(mag, m);
    if (um != Status::Ok) return status_result<3>(um);
    const S gt = gate > S(0) ? gate : params_.mag_gate;
    // One rotation of the field for the part's tests and the heading model at the attitude before
    // the update; the part's tests after it rotate again.
    const Quat<S> q0 = st_.q_nb;
    const Mat3<S> C = quat::to_rotmat(q0);
    const Vec3<S> mn = C * m;
    const auto field_n = [&] { return st_.q_nb == q0 ? mn : Vec3<S>(quat::rotate(st_.q_nb, m)); };
    // The dip test compares the field's dip at the estimated attitude with the reference's, so
    // the filter's own tilt error enters it: its tolerance grows with the dip's variance from P.
    const S dip_var = MagDisturbance<S>::widened(params_.mag)
                          ? MagDisturbance<S>::dip_variance(params_.mag, C, mn, st_.P.template topLeftCorner<3, 3>())
                          : S(0);
    return MagDisturbance<S>::update(
        params_.mag, st_.mag, mag.norm(), field_n, st_.dt_last, flags_,
        [&] {
          return params_.mag_heading_only ? update_heading(C, mn, gt)
                                          : update3(mag, mag_reference(), params_.mag_sigma, gt);
        },
        dip_var);
  }

  /// Joint accelerometer + magnetometer update (6 scalar rows).
  UpdateResult<S, 6> update_acc_mag(const Vec3<S>& acc, const Vec3<S>& mag, S gate = S(0)) {
    UpdateResult<S, 6> res;
    if (!st_.initialized) return res;
    if (detail::saturated(acc, params_.acc_range)) return status_result<6>(Status::Saturated);
    Vec3<S> a, m;
    res.status = detail::unit_vector(acc, a);
    if (res.status != Status::Ok) return res;
    res.status = detail::unit_vector(mag, m);
    if (res.status != Status::Ok) return res;
    const MagRef<S> ref_before = st_.mag.ref;
    st_.mag.ref.learn(quat::rotate(st_.q_nb, m), params_.mag.mag_ref_samples);
    Vec3<S> ha, hm;
    Mat3<S> Ha, Hm;
    detail::eskf_direction_model(st_.q_nb, Vec3<S>(S(0), S(0), S(-1)), ha, Ha);
    detail::eskf_direction_model(st_.q_nb, mag_reference(), hm, Hm);
    Mat<S, 6, 3> H;
    H << Ha, Hm;
    Vec<S, 6> y, r;
    y << a - ha, m - hm;
    r << Vec3<S>::Constant(params_.acc_sigma * params_.acc_sigma),
        Vec3<S>::Constant(params_.mag_sigma * params_.mag_sigma);
    apply_correction<6, 0, 3, RowShape::Cross>(H, r, y, res, gate, heading_free(Vec3<S>(-ha)));
    if (res.status != Status::Ok) st_.mag.ref = ref_before;
    return res;
  }

 private:
  /// At rest (parts/rest.hpp): the zero-rate measurement of the bias, z = w - b = 0 + noise.
  void update_zero_rate() {
    flags_ |= flags::kAtRest;
    const Mat3<S> H = Mat3<S>::Identity();
    const S r = Rest<S>::zero_rate_variance(params_.rest, params_.gyro_noise, st_.dt_last);
    UpdateResult<S, 3> res;
    apply_correction<3, 3, 3, RowShape::Unit>(H, Vec3<S>::Constant(r), Rest<S>::zero_rate_innovation(st_.rest, st_.gyro_bias),
                                              res, S(0));
  }

  /// The reference field in the filter's frame: [m_x, 0, m_z] turned by the declination.
  Vec3<S> mag_reference() const {
    const Vec3<S> r(st_.mag.ref.mag_ref[0], S(0), st_.mag.ref.mag_ref[2]);
    if (params_.declination == S(0)) return r;
    return quat::rotate(quat::from_rotvec(Vec3<S>(S(0), S(0), params_.declination)), r);
  }

  /// Heading-only magnetometer update (as QuaternionEKFPaper::update_heading, in the error space):
  /// H = [u^T 0], the gain's attitude part projected on u, R inflated by the tilt uncertainty.
  /// C = C_nb at the current attitude, mn = C m_unit.
  UpdateResult<S, 3> update_heading(const Mat3<S>& C, const Vec3<S>& mn, S gate) {
    UpdateResult<S, 3> res;
    S h, horiz2;
    Vec3<S> u, vt;
    if (!detail::eskf_heading_model<S>(C, mn, h, horiz2, u, vt)) {
      res.status = Status::ZeroNorm;
      return res;
    }
    const Mat3<S> A = st_.P.template topLeftCorner<3, 3>();
    const S R = params_.mag_sigma * params_.mag_sigma / horiz2 + vt.dot(A * vt);
    // Without a declination, -h itself: atan2 lies in [-pi, pi], and wrap_pi maps -pi (h = pi)
    // to pi; its fmod would only round the small innovation to the resolution of pi.
    const S pi = S(3.14159265358979323846);
    const S y = params_.declination == S(0) ? (h < pi ? -h : h) : quat::wrap_pi(params_.declination - h);
    Vec<S, 6> PHt;
    PHt.noalias() = st_.P.template leftCols<3>() * u;
    const S Sv = u.dot(PHt.template head<3>()) + R;
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
    Vec<S, 6> K = PHt / Sv;
    K.template head<3>() = (u * u.dot(K.template head<3>())).eval();
    Mat6 P = st_.P;
    joseph_update_scalar<S, 6>(P, K, PHt, Sv);
    const Vec<S, 6> dx = K * y;
    res.status = Status::Ok;
    commit(res, P, dx);
    return res;
  }

  /// The gain of the accelerometer rows for the body-frame vertical u (the top of this file).
  detail::HeadingFreeRows<S> heading_free(const Vec3<S>& u) const {
    return {u, AccFilter<S>::bias_weight(params_.acc, st_.acc, u), params_.acc_tilt_only ? 3 : 0};
  }

  /// The accelerometer's gravity update (the top of this file): the direction model of
  /// r = [0, 0, -1] with the gain projected off the vertical u = -h (one rotation for both, by
  /// the last row of C_nb).
  UpdateResult<S, 3> update_gravity(const Vec3<S>& v, S sigma, S gate) {
    if constexpr (!(Eigen::internal::packet_traits<S>::Vectorizable && Eigen::internal::packet_traits<S>::size > 1)) {
      // Without SIMD (a Cortex-M4) the three scalar rows of the same measurement and gain
      // (EskfGravity.TangentPlaneRowsAreTheThreeRows) cost fewer instructions than the 2-row
      // block, whose one pass saves no multiply-adds there while its basis, 2 x 2 algebra and
      // body-axes covariance are extra: 7,626 -> 7,042 per step on the Cortex-M4 at -O2
      // (bench/README.md, 2026-12-06).
      const Vec3<S> u = quat::nav_z_in_body(st_.q_nb);
      const Vec3<S> h = -u;
      return update3_model(v, h, Mat3<S>(quat::skew(h)), sigma, gate, heading_free(u));
    }
    UpdateResult<S, 3> res;
    Vec3<S> a;
    res.status = detail::unit_vector(v, a);
    if (res.status != Status::Ok) return res;
    const Vec3<S> u = quat::nav_z_in_body(st_.q_nb);  // h = C_bn [0, 0, -1] = -u
    const Vec3<S> h = -u;
    Mat6 P = st_.P;
    Vec<S, 6> dx;
    detail::eskf_gravity_correct<S>(P, h, Vec3<S>(a - h), sigma * sigma, dx, res, gate, heading_free(u));
    commit(res, P, dx);
    return res;
  }

  /// The 3-row direction update of v (normalized here) against the reference r_n, with the
  /// optimal gain.
  UpdateResult<S, 3> update3(const Vec3<S>& v, const Vec3<S>& r_n, S sigma, S gate) {
    Vec3<S> h;
    Mat3<S> H;
    detail::eskf_direction_model(st_.q_nb, r_n, h, H);
    return update3_model(v, h, H, sigma, gate, OptimalGain{});
  }

  /// The 3-row direction update of v (normalized here) for the model h, H = [h x] of
  /// eskf_direction_model, with the gain map `gain` (kalman.hpp).
  template <class Gain>
  UpdateResult<S, 3> update3_model(const Vec3<S>& v, const Vec3<S>& h, const Mat3<S>& H, S sigma, S gate,
                                   const Gain& gain) {
    UpdateResult<S, 3> res;
    Vec3<S> u;
    res.status = detail::unit_vector(v, u);
    if (res.status != Status::Ok) return res;
    apply_correction<3, 0, 3, RowShape::Cross>(H, Vec3<S>::Constant(sigma * sigma), Vec3<S>(u - h), res, gate, gain);
    return res;
  }

  Status init_impl(const Vec3<S>& acc, const Vec3<S>* mag) {
    if (!acc.allFinite() || (mag && !mag->allFinite())) return Status::NonFinite;
    Quat<S> q;
    Vec3<S> mref;
    if (!detail::attitude_from_acc_mag(acc, mag, q, mref)) return Status::ZeroNorm;
    if (mag && params_.declination != S(0)) q = quat::mul(quat::from_rotvec(Vec3<S>(S(0), S(0), params_.declination)), q);
    st_.q_nb = q;
    st_.gyro_bias.setZero();
    st_.dt_last = S(0);
    // The parts start afresh; the reference field is learned from this sample (unless the user fixed it).
    restart_parts<S>(params_, st_, mag, mref);
    flags_ = 0;
    st_.P.setZero();
    st_.P.diagonal().template head<3>().setConstant(params_.init_att_sigma * params_.init_att_sigma);
    st_.P.diagonal().template tail<3>().setConstant(params_.init_gyro_bias_sigma * params_.init_gyro_bias_sigma);
    st_.initialized = true;
    cov_psd_ = true;  // diagonal, non-negative
    return Status::Ok;
  }

  template <int M> static UpdateResult<S, M> status_result(Status status) {
    UpdateResult<S, M> r;
    r.status = status;
    return r;
  }

  /// Scalar sequential updates of the rows of H, given by its NC nonzero columns from C0 on
  /// (their structure: Shape), on one working copy of P (tested for finiteness once, in
  /// commit()): the symmetric form for a row with the optimal gain that is not too strong, the
  /// Joseph form otherwise (RowForm::SymmetricWhereOptimal, kalman.hpp).
  template <int M, int C0, int NC, RowShape Shape, class Gain = OptimalGain>
  void apply_correction(const Mat<S, M, NC>& Hc, const Vec<S, M>& r, const Vec<S, M>& y, UpdateResult<S, M>& res,
                        S gate, const Gain& gain = Gain{}) {
    Mat6 P = st_.P;
    Vec<S, 6> dx;
    kalman_correct_diagonal_in_place<S, 6, M, C0, NC, Shape, RowForm::SymmetricWhereOptimal>(P, Hc, r, y, dx, res,
                                                                                              gate, gain);
    commit(res, P, dx);
  }

  /// inject (q * exp(dtheta), b + db) -> check (finite) -> commit (core/commit.hpp). P is the
  /// working copy, reset in place.
  template <int M> void commit(UpdateResult<S, M>& res, Mat6& P, const Vec<S, 6>& dx) {
    if (res.status == Status::Ok) detail::eskf_reset_covariance<S>(P, Vec3<S>(dx.template head<3>()));
    inject_and_commit(
        res, P,
        [&] {
          const Quat<S> q = quat::mul(st_.q_nb, quat::from_rotvec(Vec3<S>(dx.template head<3>())));
          return Quat<S>(q / q.norm());
        },
        // P as set_state takes it: a correction of an indefinite P (as set_state and reset take
        // it) or of one ill-conditioned beyond the precision can lose the non-negative diagonal.
        [&](const Quat<S>& q, const Mat6& Pk) {
          return all_finite(Pk) && detail::nonnegative_diagonal<S, 6>(Pk) && all_finite(dx) && all_finite(q);
        },
        Always{},
        [&](const Quat<S>& q, const Mat6& Pk) {
          st_.q_nb = q;
          st_.gyro_bias += dx.template tail<3>();
          st_.P = Pk;
        });
  }

  Params params_{};
  State st_{};
  std::uint32_t flags_ = 0;
  /// P was tested, floored or proven at the last time update (or set by initialize()), so the
  /// next one may prove instead of testing. Not part of State: a restored filter tests once, and
  /// that test passes wherever this one's proof holds, so the results are the same.
  bool cov_psd_ = true;
};

/// The name of this filter before 0.2 (when QuaternionEKF was the 7-state form, now QuaternionEKFPaper).
template <class S>
using QuaternionESKF [[deprecated("QuaternionESKF is now QuaternionEKF")]] = QuaternionEKF<S>;

}  // namespace quatnav
