// quatnav: the one Kalman correction every filter uses.
//
// S = H P H^T + R is factorized by Cholesky (LLT); the gain is K = P H^T S^-1 computed by a
// solve, never by an inverse; the covariance update is the Joseph form
//   P+ = (I - K H) P (I - K H)^T + K R K^T,
// symmetrized afterwards. The normalized innovation squared (NIS) y^T S^-1 y is returned so
// that callers can gate and tests can judge consistency. Fixed-size Eigen only: no heap.
#pragma once

#include <Eigen/Cholesky>
#include <limits>

#include "types.hpp"

namespace quatnav {

/// True when every coefficient is finite.
template <class Derived> bool all_finite(const Eigen::MatrixBase<Derived>& m) {
  return m.allFinite();
}

/// Make a square matrix exactly symmetric in place.
template <class Derived> void symmetrize(Eigen::MatrixBase<Derived>& P) {
  P = (P + P.transpose()).eval() * typename Derived::Scalar(0.5);
}

/// One Kalman correction with N states and M measurement rows.
///
/// Inputs: P (NxN), H (MxN), R (MxM), innovation y = z - h(x) (M). On success writes the state
/// correction dx = K y, replaces P by the Joseph-form update and fills `res` (innovation,
/// its covariance S, NIS). When `gate` is positive and NIS exceeds it, returns Rejected.
/// Any status other than Ok leaves P and dx unchanged.
template <class S, int N, int M>
Status kalman_correct(Mat<S, N, N>& P, const Mat<S, M, N>& H, const Mat<S, M, M>& R,
                      const Vec<S, M>& y, Vec<S, N>& dx, UpdateResult<S, M>& res,
                      S gate = S(0)) {
  res.innovation = y;
  const Mat<S, N, M> PHt = fixed_mul(P, H.transpose());
  Mat<S, M, M> Sm = fixed_mul(H, PHt) + R;
  symmetrize(Sm);
  res.innovation_cov = Sm;
  if (!all_finite(Sm) || !all_finite(y)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  const Eigen::LLT<Mat<S, M, M>> llt(Sm);
  if (llt.info() != Eigen::Success) {
    res.status = Status::SolveFailed;
    return res.status;
  }
  // NIS = |L^-1 y|^2.
  const Vec<S, M> w = llt.matrixL().solve(y);
  res.nis = w.squaredNorm();
  if (gate > S(0) && !(res.nis <= gate)) {
    res.status = Status::Rejected;
    return res.status;
  }
  // K^T = S^-1 H P  (S symmetric), K = P H^T S^-1, solved one row of K at a time: Eigen solves
  // a fixed-size vector right-hand side fully inline, whereas a matrix right-hand side goes
  // through its blocked solver, whose heap fallback (never taken for fixed sizes) would still
  // link malloc into a microcontroller image (see docs/PORTING.md).
  Mat<S, N, M> K;
  for (int j = 0; j < N; ++j) K.row(j) = llt.solve(Vec<S, M>(PHt.row(j).transpose())).transpose();
  const Vec<S, N> dx_new = K * y;
  // Products through fixed_mul (types.hpp): no GEMM kernel, so no malloc linked, for N >= 8.
  Mat<S, N, N> IKH = Mat<S, N, N>::Identity() - fixed_mul(K, H);
  Mat<S, N, N> P_new = fixed_mul(fixed_mul(IKH, P), IKH.transpose()) + fixed_mul(Mat<S, N, M>(K * R), K.transpose());
  symmetrize(P_new);
  if (!all_finite(P_new) || !all_finite(dx_new)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  P = P_new;
  dx = dx_new;
  res.status = Status::Ok;
  return res.status;
}

/// Chi-square quantiles used as default gates (probability 0.9999) for 1..6 degrees of freedom.
template <class S> S chi2_gate_9999(int dof) {
  static constexpr double q[] = {0.0, 15.137, 18.421, 21.108, 23.513, 25.745, 27.856};
  return S(dof >= 1 && dof <= 6 ? q[dof] : 27.856 + 2.0 * (dof - 6));
}

}  // namespace quatnav
