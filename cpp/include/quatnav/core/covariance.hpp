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
// Filters whose state has a constraint (a unit quaternion) apply the floor to the covariance
// of their error state (the tangent space), not to P itself, whose null direction along the
// constraint is structural (quat_block.hpp).
//
// The eigen-decomposition is a cyclic Jacobi iteration on fixed-size matrices
// (detail::symmetric_eigen) rather than Eigen::SelfAdjointEigenSolver, whose Householder
// tridiagonalization instantiates dynamic-size temporaries: harmless on a host, but on a
// bare-metal target it links malloc into the image even though fixed sizes never reach it.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "kalman.hpp"
#include "types.hpp"

namespace quatnav {
namespace detail {

/// Eigen-decomposition of a symmetric fixed-size matrix by cyclic Jacobi rotations:
/// A = V diag(lam) V^T with orthonormal V. Only the upper triangle's mirror is assumed (A is
/// symmetrized first). At most `max_sweeps` sweeps over all (p, q) pairs; stops when the
/// off-diagonal mass is below machine precision relative to the diagonal. No heap, no
/// exceptions; returns false if it did not converge (lam and V then hold the last iterate).
template <class S, int N>
bool symmetric_eigen(const Mat<S, N, N>& A_in, Vec<S, N>& lam, Mat<S, N, N>* V_out = nullptr,
                     int max_sweeps = 50) {
  Mat<S, N, N> A = (A_in + A_in.transpose()) * S(0.5);
  Mat<S, N, N> V = Mat<S, N, N>::Identity();
  const S eps = std::numeric_limits<S>::epsilon();
  bool converged = false;
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    S off = S(0), diag = S(0);
    for (int p = 0; p < N; ++p) {
      diag += A(p, p) * A(p, p);
      for (int q = p + 1; q < N; ++q) off += A(p, q) * A(p, q);
    }
    if (off <= eps * eps * diag || off == S(0)) {
      converged = true;
      break;
    }
    for (int p = 0; p < N - 1; ++p) {
      for (int q = p + 1; q < N; ++q) {
        const S apq = A(p, q);
        if (apq == S(0)) continue;
        // Rotation J (J_pp = J_qq = c, J_pq = s, J_qp = -s) with (J^T A J)_pq = 0:
        // cot(2 phi) = (a_qq - a_pp) / (2 a_pq), t = tan(phi) the smaller root.
        const S theta = (A(q, q) - A(p, p)) / (S(2) * apq);
        const S t = (theta >= S(0) ? S(1) : S(-1)) / (std::abs(theta) + std::sqrt(theta * theta + S(1)));
        const S c = S(1) / std::sqrt(t * t + S(1));
        const S s = t * c;
        for (int k = 0; k < N; ++k) {  // A <- A J
          const S akp = A(k, p), akq = A(k, q);
          A(k, p) = c * akp - s * akq;
          A(k, q) = s * akp + c * akq;
        }
        for (int k = 0; k < N; ++k) {  // A <- J^T A
          const S apk = A(p, k), aqk = A(q, k);
          A(p, k) = c * apk - s * aqk;
          A(q, k) = s * apk + c * aqk;
        }
        A(p, q) = A(q, p) = S(0);
        for (int k = 0; k < N; ++k) {  // V <- V J
          const S vkp = V(k, p), vkq = V(k, q);
          V(k, p) = c * vkp - s * vkq;
          V(k, q) = s * vkp + c * vkq;
        }
      }
    }
  }
  lam = A.diagonal();
  if (V_out) *V_out = V;
  return converged;
}

/// True when the symmetric matrix A (its lower triangle is read) is positive definite up to
/// rounding: every pivot of its LDL^T factorization A = L D L^T (L unit lower triangular) is
/// positive. The pivots d_j are the squares of the Cholesky factor's diagonal, so this is the
/// test "A has a Cholesky factor" without a single square root: one division per pivot, plain
/// inline loops on fixed sizes (the serial chain of square roots and divisions of a Cholesky
/// factorization cost more time than its instruction count says). W holds L D (unscaled rows),
/// so that each off-diagonal coefficient costs one multiply-add per k. False at the first pivot
/// that is not positive (or is NaN).
template <class S, int N> bool has_cholesky(const Mat<S, N, N>& A) {
  Mat<S, N, N> W, L;  // W(i, k) = L(i, k) d_k
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 8
#endif
  for (int j = 0; j < N; ++j) {
    S d = A(j, j);
    for (int k = 0; k < j; ++k) d -= W(j, k) * L(j, k);
    if (!(d > S(0))) return false;
    const S inv = S(1) / d;
    for (int i = j + 1; i < N; ++i) {
      S w = A(i, j);
      for (int k = 0; k < j; ++k) w -= W(i, k) * L(j, k);
      W(i, j) = w;
      L(i, j) = w * inv;
    }
  }
  return true;
}

}  // namespace detail

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
  Vec<S, N> lam;
  detail::symmetric_eigen<S, N>(Ps, lam);
  h.min_eig = lam.minCoeff();
  h.max_eig = lam.maxCoeff();
  return h;
}

/// The covariance floor: if the symmetric P has an eigenvalue below `floor` (or is not
/// positive definite), raise every eigenvalue below `floor` to `floor` and return true.
/// A P that passes (P - floor I has a Cholesky factor) is left bit-for-bit as it was.
/// floor <= 0 disables the repair. Non-finite P is left alone (returns false): callers
/// refuse such results before they reach the state.
template <class S, int N> bool floor_covariance(Mat<S, N, N>& P, S floor) {
  if (!(floor > S(0)) || !all_finite(P)) return false;
  Mat<S, N, N> shifted = P;
  shifted.diagonal().array() -= floor;
  if (detail::has_cholesky<S, N>(shifted)) return false;
  const Mat<S, N, N> Ps = (P + P.transpose()) * S(0.5);
  Vec<S, N> lam;
  Mat<S, N, N> V;
  if (!detail::symmetric_eigen<S, N>(Ps, lam, &V)) return false;
  // Raise to the floor plus a rounding margin (a few ulps of the largest eigenvalue), so the
  // rebuilt P passes the Cholesky test above instead of sitting exactly on its edge.
  const S margin = S(8 * N) * std::numeric_limits<S>::epsilon() * lam.cwiseAbs().maxCoeff();
  lam = lam.cwiseMax(floor + margin);
  // fixed_mul: no GEMM kernel (and the malloc it links on bare metal) for the 12- and 15-state filters.
  P = fixed_mul(Mat<S, N, N>(V * lam.asDiagonal()), V.transpose());
  P = (P + P.transpose()).eval() * S(0.5);
  return true;
}

namespace detail {

/// A covariance a filter accepts from set_state(): finite, exactly symmetric (as every filter
/// keeps it), non-negative diagonal.
template <class S, int N> bool acceptable_covariance(const Mat<S, N, N>& P) {
  return P.allFinite() && P == P.transpose() && (P.diagonal().array() >= S(0)).all();
}

/// What a step checks of the covariance it commits, beside its finiteness (which it checks
/// anyway) and its symmetry (which every filter keeps by construction): a non-negative diagonal
/// (a NaN fails), so that set_state (acceptable_covariance) takes the state back. N comparisons,
/// against about 3 N^2 operations for acceptable_covariance.
template <class S, int N> bool nonnegative_diagonal(const Mat<S, N, N>& P) {
  for (int i = 0; i < N; ++i)
    if (!(P(i, i) >= S(0))) return false;
  return true;
}

}  // namespace detail
}  // namespace quatnav
