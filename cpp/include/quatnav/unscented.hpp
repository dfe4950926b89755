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

#include <Eigen/Cholesky>
#include <cmath>

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

/// Sigma-point offsets: column 0 zero, column i = gamma L_i, column N+i = -gamma L_i (P = L L^T).
/// Returns false (and leaves `offsets` unchanged) when P is not positive definite.
template <class S, int N>
bool sigma_offsets(const Mat<S, N, N>& P, S gamma, Mat<S, N, 2 * N + 1>& offsets) {
  const Eigen::LLT<Mat<S, N, N>> llt(P);
  if (llt.info() != Eigen::Success) return false;
  const Mat<S, N, N> L = gamma * Mat<S, N, N>(llt.matrixL());
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
