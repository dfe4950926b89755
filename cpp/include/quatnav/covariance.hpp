// quatnav: covariance health and the one covariance repair every filter uses.
//
// A Kalman covariance must stay symmetric and positive definite. The Joseph form and the
// symmetrization in kalman.hpp keep it so in exact arithmetic; in float32, with very small
// measurement noise or over millions of steps, rounding can still push an eigenvalue to zero
// or below. The repair here is an eigenvalue floor:
//
//   P <- V max(Lambda, floor) V^T      (P = V Lambda V^T, symmetric eigen-decomposition)
//
// applied only when P fails the cheap test "P - floor I has a Cholesky factor", so that a
// healthy covariance is never touched (not even rounded). Fixed-size Eigen only: no heap.
//
// Filters whose state has a constraint (the unit quaternion of QuaternionEKF) apply the floor
// to the covariance of their error state (the tangent space), not to P itself, whose null
// direction along the constraint is structural (see detail::qekf_floor_covariance).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "quaternion.hpp"
#include "types.hpp"

namespace quatnav {

/// Health figures of a covariance matrix.
template <class S> struct CovarianceHealth {
  bool finite = true;       ///< every coefficient finite
  S min_eig = S(0);         ///< smallest eigenvalue of the symmetric part
  S max_eig = S(0);         ///< largest eigenvalue of the symmetric part
  S asymmetry = S(0);       ///< max |P - P^T| / max |P| (0 when P is zero)
  /// Finite, exactly symmetric and positive definite.
  bool ok() const { return finite && asymmetry == S(0) && min_eig > S(0); }
};

/// Eigenvalues and asymmetry of a square matrix (the eigenvalues of its symmetric part).
template <class S, int N> CovarianceHealth<S> covariance_health(const Mat<S, N, N>& P) {
  CovarianceHealth<S> h;
  h.finite = P.allFinite();
  if (!h.finite) return h;
  const S scale = P.cwiseAbs().maxCoeff();
  h.asymmetry = scale > S(0) ? (P - P.transpose()).cwiseAbs().maxCoeff() / scale : S(0);
  const Mat<S, N, N> Ps = (P + P.transpose()) * S(0.5);
  const Eigen::SelfAdjointEigenSolver<Mat<S, N, N>> es(Ps, Eigen::EigenvaluesOnly);
  h.min_eig = es.eigenvalues().minCoeff();
  h.max_eig = es.eigenvalues().maxCoeff();
  return h;
}

/// The covariance floor: if the symmetric P has an eigenvalue below `floor` (or is not
/// positive definite), raise every eigenvalue below `floor` to `floor` and return true.
/// A P that passes (P - floor I has a Cholesky factor) is left bit-for-bit as it was.
/// floor <= 0 disables the repair. Non-finite P is left alone (returns false): callers
/// refuse such results before they reach the state.
template <class S, int N> bool floor_covariance(Mat<S, N, N>& P, S floor) {
  if (!(floor > S(0)) || !P.allFinite()) return false;
  const Mat<S, N, N> shifted = P - floor * Mat<S, N, N>::Identity();
  const Eigen::LLT<Mat<S, N, N>> llt(shifted);
  if (llt.info() == Eigen::Success) return false;
  const Mat<S, N, N> Ps = (P + P.transpose()) * S(0.5);
  const Eigen::SelfAdjointEigenSolver<Mat<S, N, N>> es(Ps);
  if (es.info() != Eigen::Success) return false;
  const Vec<S, N> lam = es.eigenvalues().cwiseMax(floor);
  P = es.eigenvectors() * lam.asDiagonal() * es.eigenvectors().transpose();
  P = (P + P.transpose()).eval() * S(0.5);
  return true;
}

namespace detail {

/// The covariance conditioning of QuaternionEKF: P is made exactly symmetric (the
/// normalization's projection J P J^T is symmetric only up to rounding), then floored in its
/// error state [dtheta (3, rad, body frame), db (3, rad/s)]: with T = diag(2 Xi(q)^T, I3) (6x7)
/// and T+ = diag(Xi(q)/2, I3) (7x6), Pe = T P T^T is floored (floor_covariance) and, when that
/// changed it, P = T+ Pe T+^T. T+ T = diag(I - q q^T, I3) is the projection that the
/// normalization (qekf_normalize) already applies, so a healthy P is unchanged and a repaired
/// one keeps the structure. Returns true when the floor was applied.
template <class S> bool qekf_floor_covariance(const Quat<S>& q, Mat<S, 7, 7>& P, S floor) {
  P = (P + P.transpose()).eval() * S(0.5);
  if (!(floor > S(0))) return false;
  Mat<S, 6, 7> T = Mat<S, 6, 7>::Zero();
  T.template topLeftCorner<3, 4>() = S(2) * quat::xi(q).transpose();
  T.template bottomRightCorner<3, 3>().setIdentity();
  Mat<S, 6, 6> Pe = T * P * T.transpose();
  Pe = (Pe + Pe.transpose()).eval() * S(0.5);
  if (!floor_covariance<S, 6>(Pe, floor)) return false;
  Mat<S, 7, 6> Tp = Mat<S, 7, 6>::Zero();
  Tp.template topLeftCorner<4, 3>() = quat::xi(q) / S(2);
  Tp.template bottomRightCorner<3, 3>().setIdentity();
  P = Tp * Pe * Tp.transpose();
  P = (P + P.transpose()).eval() * S(0.5);
  return true;
}

/// A covariance a filter accepts from set_state(): finite, exactly symmetric (as every filter
/// keeps it), non-negative diagonal.
template <class S, int N> bool acceptable_covariance(const Mat<S, N, N>& P) {
  return P.allFinite() && P == P.transpose() && (P.diagonal().array() >= S(0)).all();
}

}  // namespace detail
}  // namespace quatnav
