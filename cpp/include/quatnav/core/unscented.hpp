// quatnav: sigma-point machinery of the unscented transform (Julier & Uhlmann 2004, "Unscented
// filtering and nonlinear estimation", Proc. IEEE 92(3); scaled form of Wan & van der Merwe).
//
// For an N-dimensional Gaussian (mean m, covariance P) the 2N+1 sigma points are
//     X_0 = m,   X_i = m + gamma L_i,   X_{N+i} = m - gamma L_i   (i = 1..N),
// with L L^T = P (Cholesky), lambda = alpha^2 (N + kappa) - N and gamma = sqrt(N + lambda).
// Mean weights Wm_0 = lambda / (N + lambda), covariance weight Wc_0 = Wm_0 + 1 - alpha^2 + beta,
// and Wm_i = Wc_i = 1 / (2 (N + lambda)).
//
// Only the offsets gamma L_i are produced here (an N x (2N+1) fixed-size matrix, column 0 zero):
// a filter whose state lives on a manifold (a unit quaternion) applies them through its own
// retraction and maps the propagated points back to a tangent space itself. Fixed-size Eigen,
// no heap.
#pragma once

#include <cmath>
#include <limits>

#include "covariance.hpp"
#include "kalman.hpp"
#include "types.hpp"

namespace quatnav {

/// Parameters of the scaled unscented transform.
///  * alpha (spread of the points about the mean; 0 < alpha <= 1), default 1;
///  * beta (prior knowledge of the distribution; 2 is optimal for a Gaussian), default 2;
///  * kappa (secondary scaling), default 0.
/// The defaults give lambda = 0: no point sits at the mean for the mean weights (Wm_0 = 0), every
/// other weight is positive, so the predicted covariance is positive semidefinite by construction
/// and a weighted mean of unit quaternions is a convex combination.
template <class S> struct UnscentedParams {
  S alpha = S(1);
  S beta = S(2);
  S kappa = S(0);
};

/// Weights of the 2N+1 sigma points.
template <class S, int N> struct UnscentedWeights {
  S lambda = S(0);
  S gamma = S(0);  ///< sqrt(N + lambda): the offsets are +/- gamma times the columns of L
  S wm0 = S(0);    ///< mean weight of the central point
  S wc0 = S(0);    ///< covariance weight of the central point
  S wi = S(0);     ///< weight of every other point (mean and covariance)

  /// Compute the weights; false when N + lambda <= 0 (the parameters are unusable).
  bool compute(const UnscentedParams<S>& p) {
    lambda = p.alpha * p.alpha * (S(N) + p.kappa) - S(N);
    const S nl = S(N) + lambda;
    if (!(nl > S(0))) return false;
    gamma = std::sqrt(nl);
    wm0 = lambda / nl;
    wc0 = wm0 + S(1) - p.alpha * p.alpha + p.beta;
    wi = S(1) / (S(2) * nl);
    return true;
  }
  S wm(int i) const { return i == 0 ? wm0 : wi; }
  S wc(int i) const { return i == 0 ? wc0 : wi; }
};

/// Lower-triangular L with L L^T = P (+ a repair of round-off, below) for a symmetric P,
/// computed on the correlation scale: C = D^-1 P D^-1 with D = diag(sqrt(P_ii)), C = L_c L_c^T,
/// L = D L_c.
///
/// The repair. A float32 covariance whose smallest correlation eigenvalue is small loses
/// definiteness over many steps. In NavFilter13 (paper 002 input, 100 Hz, velocity and yaw
/// aiding) a level tilt and the horizontal accelerometer bias that mimics it (g dtheta_x and
/// b_a,y; g dtheta_y and b_a,x) become well-determined combinations while each stays uncertain:
/// two eigenvalues of C fall to 1e-5..3e-5 after 20-30 s (double). In float32 the time updates
/// and corrections move them by about float epsilon per step, and the errors add up instead of
/// averaging out: one of them reaches zero after a few hundred to a few thousand steps, at a step
/// that depends on the last bits (FMA contraction on a Cortex-M4F moves it by tens of steps). The
/// EKF's float32 P goes indefinite the same way but never factorizes it; a Cholesky of P (or of C)
/// then fails, and refused every later time update. Because the unscented covariance is rebuilt
/// from this factor at every time update, repairing C here removes the accumulated round-off
/// before it grows: when C - kLow I has no Cholesky factor (kLow = 16 eps), the eigenvalues of C
/// are raised to kFloor = 64 eps (C = V max(Lambda, kFloor) V^T, detail::symmetric_eigen of
/// covariance.hpp, fixed size). This only adds variance (never claims more certainty than P), in
/// the direction that lost it, by about 1e-5 of the variances in float32 and 1e-14 in double
/// (where it does not trigger on a healthy P). An eigenvalue of C below -sqrt(eps) is not
/// round-off (a correlation above one): refused.
/// Returns false and leaves L unchanged for a negative or non-finite variance, such a P, or a
/// failed factorization.
template <class S, int N>
bool covariance_factor(const Mat<S, N, N>& P, Mat<S, N, N>& L) {
  const S eps = std::numeric_limits<S>::epsilon();
  const S kLow = S(16) * eps, kFloor = S(64) * eps;
  Vec<S, N> d;
  for (int i = 0; i < N; ++i) {
    if (!(P(i, i) >= S(0)) || !std::isfinite(P(i, i))) return false;
    d[i] = std::sqrt(P(i, i));
  }
  // C: unit diagonal; a component of zero variance keeps a unit row (its column of L is then
  // zero after the scaling by D).
  Mat<S, N, N> C = Mat<S, N, N>::Identity();
  for (int j = 0; j < N; ++j)
    for (int i = j + 1; i < N; ++i)
      if (d[i] > S(0) && d[j] > S(0)) C(i, j) = C(j, i) = (P(i, j) + P(j, i)) / (S(2) * d[i] * d[j]);
  if (!C.allFinite()) return false;
  if (!detail::has_cholesky<S, N>(Mat<S, N, N>(C - kLow * Mat<S, N, N>::Identity()))) {
    Vec<S, N> lam;
    Mat<S, N, N> V;
    detail::symmetric_eigen<S, N>(C, lam, &V);
    if (!lam.allFinite() || !V.allFinite() || !(lam.minCoeff() > -std::sqrt(eps))) return false;
    const Mat<S, N, N> VL = V * lam.cwiseMax(kFloor).asDiagonal();
    C = fixed_mul(VL, V.transpose());  // fixed_mul (types.hpp): no GEMM kernel, no malloc linked
    symmetrize(C);
  }
  Mat<S, N, N> Lc = Mat<S, N, N>::Zero();  // cholesky_small writes the lower triangle only
  Vec<S, N> inv_diag;
  if (!detail::cholesky_small<S, N>(C, Lc, inv_diag)) return false;
  const Mat<S, N, N> Ln = d.asDiagonal() * Lc;
  if (!Ln.allFinite()) return false;
  L = Ln;
  return true;
}

/// Sigma-point offsets: column 0 zero, column i = gamma L_i, column N+i = -gamma L_i (P = L L^T,
/// covariance_factor). Returns false (and leaves `offsets` unchanged) when P is not positive
/// definite up to round-off.
template <class S, int N>
bool sigma_offsets(const Mat<S, N, N>& P, S gamma, Mat<S, N, 2 * N + 1>& offsets) {
  Mat<S, N, N> L0;
  if (!covariance_factor<S, N>(P, L0)) return false;
  const Mat<S, N, N> L = gamma * L0;
  if (!L.allFinite()) return false;
  offsets.col(0).setZero();
  offsets.template middleCols<N>(1) = L;
  offsets.template rightCols<N>() = -L;
  return true;
}

/// Weighted mean of the columns of a deviation matrix (2N+1 columns).
template <class S, int N, int M>
Vec<S, M> sigma_mean(const Mat<S, M, 2 * N + 1>& Y, const UnscentedWeights<S, N>& w) {
  Vec<S, M> m = w.wm0 * Y.col(0);
  for (int i = 1; i < 2 * N + 1; ++i) m += w.wi * Y.col(i);
  return m;
}

/// Weighted covariance sum_i Wc_i d_i d_i^T of the deviation columns d_i (already centred).
template <class S, int N, int M>
Mat<S, M, M> sigma_covariance(const Mat<S, M, 2 * N + 1>& D, const UnscentedWeights<S, N>& w) {
  Mat<S, M, M> P = w.wc0 * D.col(0) * D.col(0).transpose();
  // sum_{i>=1} wi d_i d_i^T = wi * D_r D_r^T with D_r the remaining 2N columns.
  // fixed_mul (types.hpp): no GEMM kernel, so no malloc linked into a bare-metal image.
  P += w.wi * fixed_mul(D.template rightCols<2 * N>(), D.template rightCols<2 * N>().transpose());
  return P;
}

}  // namespace quatnav
