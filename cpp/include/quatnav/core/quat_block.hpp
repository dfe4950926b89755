// quatnav: the quaternion block of a filter state, once for every filter that carries one.
//
// A state x (N) holds a unit quaternion q at offset Q, x = [a (Q), q (4), r (N - Q - 4)], the
// other parts Euclidean. Its covariance P (N x N) is singular along q by construction (|q| = 1);
// the filter's error state (N - 1) replaces dq by the body-frame rotation vector dtheta with
// q_true = q * exp(dtheta):
//     dtheta = 2 Xi(q)^T dq     (T, to_error)        dq = 1/2 Xi(q) dtheta     (T', from_error)
// with Xi(q) v = q * [0, v] (quaternion.hpp). T T' = I at a unit q; T' T = diag(I, I - q q^T, I)
// is the projection that the normalization applies, so mapping a normalized P to the error state
// and back leaves it as it was.
//
// Here: the map to and from the error state, the normalization with the covariance projected by
// its Jacobian, the covariance floor applied in the error space (covariance.hpp's
// floor_covariance on T P T^T), the attitude covariance of dtheta, and the retraction of an
// error-state offset (the sigma points of an unscented transform).
//
// The normalization and the floor come in two arithmetic forms that give the same numbers up to
// rounding but not the same bits:
//  * normalize / floor_error_covariance: whole-matrix products, any offset Q (NavFilter13);
//  * normalize_symmetric / floor_symmetric_error_covariance: block by block, every symmetric
//    pair computed once so that P stays exactly symmetric without a symmetrization, with a cheap
//    LDL^T test of the error covariance before any repair (QuaternionEKFPaper, Q = 0). It is the
//    faster one; NavFilter13 keeps the other because moving it would change its results' bits
//    (tests/regression holds them).
#pragma once

#include <cmath>

#include "covariance.hpp"
#include "kalman.hpp"
#include "quaternion.hpp"
#include "types.hpp"

namespace quatnav {

template <class S, int N, int Q> struct QuatBlock {
  static_assert(Q >= 0 && Q + 4 <= N, "QuatBlock: the quaternion must lie inside the state");
  static constexpr int kN = N;      ///< state dimension
  static constexpr int kE = N - 1;  ///< error-state dimension
  static constexpr int kQ = Q;      ///< offset of q in the state, of dtheta in the error state
  static constexpr int kR = N - Q - 4;  ///< states after q
  using MatN = Mat<S, N, N>;
  using MatE = Mat<S, kE, kE>;

  /// T (N-1 x N): [da, dtheta, dr] = T [da, dq, dr] at a unit q, dtheta = 2 Xi(q)^T dq.
  static Mat<S, kE, N> to_error(const Quat<S>& q) {
    Mat<S, kE, N> T = Mat<S, kE, N>::Zero();
    if constexpr (Q > 0) T.template block<Q, Q>(0, 0).setIdentity();
    T.template block<3, 4>(Q, Q) = S(2) * quat::xi(q).transpose();
    if constexpr (kR > 0) T.template block<kR, kR>(Q + 3, Q + 4).setIdentity();
    return T;
  }

  /// T' (N x N-1): dq = 1/2 Xi(q) dtheta; T T' = I (unit q), T' T projects dq onto the tangent space.
  static Mat<S, N, kE> from_error(const Quat<S>& q) {
    Mat<S, N, kE> T = Mat<S, N, kE>::Zero();
    if constexpr (Q > 0) T.template block<Q, Q>(0, 0).setIdentity();
    T.template block<4, 3>(Q, Q) = S(0.5) * quat::xi(q);
    if constexpr (kR > 0) T.template block<kR, kR>(Q + 4, Q + 3).setIdentity();
    return T;
  }

  /// The error-state covariance T P T^T ((N-1) x (N-1)).
  static MatE error_covariance(const Quat<S>& q, const MatN& P) {
    const Mat<S, kE, N> T = to_error(q);
    return fixed_mul(fixed_mul(T, P), T.transpose());  // fixed_mul: no GEMM, no malloc linked
  }

  /// The state covariance T' Pe T'^T of an error-state covariance Pe.
  static MatN from_error_covariance(const Quat<S>& q, const MatE& Pe) {
    const Mat<S, N, kE> Tb = from_error(q);
    return fixed_mul(fixed_mul(Tb, Pe), Tb.transpose());
  }

  /// Attitude covariance (3x3, rad^2) of dtheta from the quaternion block: 4 Xi^T P_qq Xi.
  static Mat3<S> attitude_covariance(const Quat<S>& q, const MatN& P) {
    const Mat43<S> X = quat::xi(q);
    const Mat4<S> Pqq = P.template block<4, 4>(Q, Q);
    return S(4) * X.transpose() * Pqq * X;
  }

  /// The diagonal of attitude_covariance() (rad^2), without forming the off-diagonal terms.
  static Vec3<S> attitude_variance(const Quat<S>& q, const MatN& P) {
    const Mat43<S> X = quat::xi(q);
    Mat43<S> PX;
    PX.noalias() = P.template block<4, 4>(Q, Q) * X;
    return S(4) * (X.array() * PX.array()).colwise().sum().transpose();
  }

  /// x [+] dx: the state at the error-state offset dx ((N-1)) from x: a + da, q exp(dtheta), r + dr.
  template <class Dx> static Vec<S, N> retract(const Vec<S, N>& x, const Eigen::MatrixBase<Dx>& dx) {
    Vec<S, N> y = x;
    if constexpr (Q > 0) y.template head<Q>() += dx.template head<Q>();
    y.template segment<4>(Q) =
        quat::mul(Quat<S>(x.template segment<4>(Q)), quat::from_rotvec(Vec3<S>(dx.template segment<3>(Q))));
    if constexpr (kR > 0) y.template tail<kR>() += dx.template tail<kR>();
    return y;
  }

  /// q <- q/|q| with the covariance projected by J = (I - q_hat q_hat^T)/|q| on the q rows and
  /// columns (whole-matrix products), then P symmetrized.
  static void normalize(Quat<S>& q, MatN& P) {
    const S n = q.norm();
    const Quat<S> qh = q / n;
    const Mat4<S> J = (Mat4<S>::Identity() - qh * qh.transpose()) / n;
    P.template middleRows<4>(Q) = (J * P.template middleRows<4>(Q)).eval();
    P.template middleCols<4>(Q) = (P.template middleCols<4>(Q) * J.transpose()).eval();
    symmetrize(P);
    q = qh;
  }

  /// The covariance floor in the error space: Pe = T P T^T (symmetrized) is floored
  /// (floor_covariance) and, only when that changed it, mapped back P = T' Pe T'^T. A healthy P
  /// is left bit for bit. Returns true when the floor was applied.
  static bool floor_error_covariance(const Quat<S>& q, MatN& P, S floor) {
    if (!(floor > S(0))) return false;
    MatE Pe = error_covariance(q, P);
    symmetrize(Pe);
    if (!floor_covariance<S, kE>(Pe, floor)) return false;
    MatN Pn = from_error_covariance(q, Pe);
    symmetrize(Pn);
    if (!Pn.allFinite()) return false;
    P = Pn;
    return true;
  }

  // ---- block-by-block forms for a state [q, r] (Q = 0) whose P is kept exactly symmetric ----

  /// normalize() by blocks: with v = A q_hat (A = P_qq), s = q_hat^T v, w = v - s/2 q_hat,
  ///     P_qq <- (A - q_hat w^T - w q_hat^T) / n^2,   P_qr <- (P_qr - q_hat (q_hat^T P_qr)) / n,
  /// each symmetric pair computed once (P stays exactly symmetric). The scalings by 1/n and 1/n^2
  /// multiply by the reciprocals (1 division instead of 26; the results differ from dividing by one
  /// rounding at most).
  static void normalize_symmetric(Quat<S>& q, MatN& P) {
    static_assert(Q == 0 && kR > 0, "normalize_symmetric: a state [q, r]");
    const S n = q.norm();
    const S inv_n = S(1) / n;
    const Quat<S> qh = q * inv_n;
    const Mat4<S> A = P.template topLeftCorner<4, 4>();
    const Vec4<S> v = A * qh;
    const S s = qh.dot(v);
    const Vec4<S> w = v - (s / S(2)) * qh;  // A - qh v^T - v qh^T + s qh qh^T = A - qh w^T - w qh^T
    const S inv_n2 = inv_n * inv_n;
    for (int j = 0; j < 4; ++j)  // computed once per pair: the block stays exactly symmetric
      for (int i = 0; i <= j; ++i) P(i, j) = P(j, i) = (A(i, j) - qh[i] * w[j] - w[i] * qh[j]) * inv_n2;
    const Eigen::Matrix<S, 1, kR> qC = qh.transpose() * P.template topRightCorner<4, kR>();
    P.template topRightCorner<4, kR>() = (P.template topRightCorner<4, kR>() - qh * qC) * inv_n;
    P.template bottomLeftCorner<kR, 4>() = P.template topRightCorner<4, kR>().transpose();
    q = qh;
  }

  /// True when Pe - floor I has a Cholesky factor (Pe = T P T^T), i.e. when the floor has nothing
  /// to do. Only the lower triangle of Pe - floor I is formed, coefficient by coefficient on local
  /// arrays (the attitude block as 4 X_i^T (P_qq X_j), the cross block as 2 P_qr^T X), and its
  /// LDL^T pivots are tested (has_cholesky). A P for which this is false goes through the full
  /// path, which forms Pe again, symmetrized, and tests it once more before any repair: this test
  /// only decides how soon a healthy P is left alone.
  static bool error_cov_above_floor(const Quat<S>& q, const MatN& P, S floor) {
    static_assert(Q == 0 && kR > 0, "error_cov_above_floor: a state [q, r]");
    const S x[4][3] = {{-q[1], -q[2], -q[3]}, {q[0], -q[3], q[2]}, {q[3], q[0], -q[1]}, {-q[2], q[1], q[0]}};
    S ax[4][3];  // P_qq X
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 3; ++j)
        ax[k][j] = P(k, 0) * x[0][j] + P(k, 1) * x[1][j] + P(k, 2) * x[2][j] + P(k, 3) * x[3][j];
    MatE E;  // lower triangle of Pe - floor I
    for (int j = 0; j < 3; ++j) {
      for (int i = j; i < 3; ++i)
        E(i, j) = S(4) * (x[0][i] * ax[0][j] + x[1][i] * ax[1][j] + x[2][i] * ax[2][j] + x[3][i] * ax[3][j]);
      for (int r = 0; r < kR; ++r)
        E(3 + r, j) = S(2) * (P(0, 4 + r) * x[0][j] + P(1, 4 + r) * x[1][j] + P(2, 4 + r) * x[2][j] +
                              P(3, 4 + r) * x[3][j]);
    }
    for (int j = 0; j < kR; ++j)
      for (int i = j; i < kR; ++i) E(3 + i, 3 + j) = P(4 + i, 4 + j);
    for (int i = 0; i < kE; ++i) E(i, i) -= floor;
    return detail::has_cholesky<S, kE>(E);
  }

  /// floor_error_covariance() by blocks for a P that is already exactly symmetric: the cheap test
  /// first (error_cov_above_floor); otherwise Pe = [4 X^T P_qq X, 2 X^T P_qr; ., P_rr] (X = Xi(q))
  /// is floored and, when that changed it, P = T' Pe T'^T. Returns true when the floor was applied.
  static bool floor_symmetric_error_covariance(const Quat<S>& q, MatN& P, S floor) {
    static_assert(Q == 0 && kR > 0, "floor_symmetric_error_covariance: a state [q, r]");
    if (!(floor > S(0))) return false;
    if (error_cov_above_floor(q, P, floor)) return false;  // the common case: nothing to do
    const Mat43<S> X = quat::xi(q);
    MatE Pe;
    Mat43<S> PqqX;
    PqqX.noalias() = P.template topLeftCorner<4, 4>() * X;
    Pe.template topLeftCorner<3, 3>().noalias() = S(4) * X.transpose() * PqqX;
    Pe.template topRightCorner<3, kR>().noalias() = S(2) * X.transpose() * P.template topRightCorner<4, kR>();
    Pe.template bottomLeftCorner<kR, 3>() = Pe.template topRightCorner<3, kR>().transpose();
    Pe.template bottomRightCorner<kR, kR>() = P.template bottomRightCorner<kR, kR>();
    auto Pe_aa = Pe.template topLeftCorner<3, 3>();
    symmetrize(Pe_aa);  // the other blocks are symmetric by construction
    if (!floor_covariance<S, kE>(Pe, floor)) return false;
    Mat<S, N, kE> Tp = Mat<S, N, kE>::Zero();
    Tp.template topLeftCorner<4, 3>() = quat::xi(q) / S(2);
    Tp.template bottomRightCorner<kR, kR>().setIdentity();
    P = Tp * Pe * Tp.transpose();
    P = (P + P.transpose()).eval() * S(0.5);
    return true;
  }
};

}  // namespace quatnav
