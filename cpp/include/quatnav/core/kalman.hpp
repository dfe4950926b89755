// quatnav: the one Kalman correction every filter uses.
//
// S = H P H^T + R is factorized by Cholesky (LLT); the gain is K = P H^T S^-1 computed by a
// solve, never by an inverse; the covariance update is the Joseph form
//   P+ = (I - K H) P (I - K H)^T + K R K^T,
// symmetrized afterwards (evaluated by blocks, exploiting the zero columns of H: see
// joseph_update). The normalized innovation squared (NIS) y^T S^-1 y is returned so that
// callers can gate and tests can judge consistency. Fixed-size Eigen only: no heap.
#pragma once

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "types.hpp"

namespace quatnav {

/// True when every coefficient is finite. x * 0 is (+-)0 for a finite x and NaN for an infinite
/// or NaN one, so the sum of those products is zero exactly when every coefficient is finite: a
/// branch-free reduction that vectorizes (DenseBase::allFinite() tests the coefficients one by
/// one).
template <class Derived> bool all_finite(const Eigen::MatrixBase<Derived>& m) {
  using S = typename Derived::Scalar;
  return (m.derived().array() * S(0)).sum() == S(0);
}

/// Make a square matrix exactly symmetric in place: P <- (P + P^T) / 2. Up to 8 x 8 as the
/// expression (vectorized, through a temporary); larger coefficient by coefficient over one
/// triangle, the same bits (a fifth of the expression's instructions for a 16 x 16 P).
template <class Derived> void symmetrize(Eigen::MatrixBase<Derived>& P) {
  using S = typename Derived::Scalar;
  constexpr int kRows = Derived::RowsAtCompileTime;
  if constexpr (kRows != Eigen::Dynamic && kRows <= 8) {
    P = (P + P.transpose()).eval() * S(0.5);
  } else {
    const Eigen::Index n = P.rows();
    for (Eigen::Index j = 0; j < n; ++j) {
      P(j, j) = (P(j, j) + P(j, j)) * S(0.5);
      for (Eigen::Index i = j + 1; i < n; ++i) {
        const S s = (P(i, j) + P(j, i)) * S(0.5);
        P(i, j) = s;
        P(j, i) = s;
      }
    }
  }
}

/// The Joseph-form covariance update P+ = (I - K H) P (I - K H)^T + K R K^T for a gain K (any
/// gain, not only the optimal one), where H is nonzero only in its NC columns from C0 on
/// (`Hc` holds those columns). Evaluated by blocks, without forming I - K H:
///   B  = (I - K H) P = P - K (H P)
///   P+ = B (I - K H)^T + K R K^T = B + (K R - B H^T) K^T,
/// which is the same expression re-associated (3 N^2 M + N M^2 multiply-adds instead of
/// 2 N^3 + ...). P_out is symmetrized; it may not alias P. Every product is coefficient-based
/// (lazyProduct, as fixed_mul in types.hpp): for N >= 8 Eigen's default product goes through its
/// GEMM kernel, whose heap fallback (never taken for fixed sizes) would still link malloc into a
/// microcontroller image (docs/PORTING.md).
template <class S, int N, int M, int C0, int NC>
void joseph_update(const Mat<S, N, N>& P, const Mat<S, N, M>& K, const Mat<S, M, NC>& Hc,
                   const Mat<S, M, M>& R, Mat<S, N, N>& P_out) {
  static_assert(C0 >= 0 && NC >= 1 && C0 + NC <= N, "H columns out of range");
  Mat<S, M, N> HP;
  HP.noalias() = Hc.lazyProduct(P.template middleRows<NC>(C0));
  P_out = P;
  P_out.noalias() -= K.lazyProduct(HP);  // B
  Mat<S, N, M> W;
  W.noalias() = K.lazyProduct(R);
  W.noalias() -= P_out.template middleCols<NC>(C0).lazyProduct(Hc.transpose());
  P_out.noalias() += W.lazyProduct(K.transpose());
  symmetrize(P_out);
}

namespace detail {

/// Cholesky factor A = L L^T of a small symmetric matrix (lower triangle read; the lower
/// triangle of L written, with the reciprocals of its diagonal in `inv_diag`). False at the
/// first pivot that is not positive: A is not positive definite. Plain loops on fixed sizes,
/// fully inline (no heap, nothing for a bare-metal image to link).
template <class S, int M> bool cholesky_small(const Mat<S, M, M>& A, Mat<S, M, M>& L, Vec<S, M>& inv_diag) {
  for (int j = 0; j < M; ++j) {
    S d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(d > S(0))) return false;
    const S ljj = std::sqrt(d);
    L(j, j) = ljj;
    inv_diag[j] = S(1) / ljj;
    for (int i = j + 1; i < M; ++i) {
      S v = A(i, j);
      for (int k = 0; k < j; ++k) v -= L(i, k) * L(j, k);
      L(i, j) = v * inv_diag[j];
    }
  }
  return true;
}

/// X = B L^-T for the factor of cholesky_small (forward substitution on the columns of X, each
/// an R-vector): X L^T = B.
template <class S, int M, int R>
void solve_right_lower_transposed(const Mat<S, M, M>& L, const Vec<S, M>& inv_diag, const Mat<S, R, M>& B,
                                  Mat<S, R, M>& X) {
  for (int i = 0; i < M; ++i) {
    Vec<S, R> c = B.col(i);
    for (int k = 0; k < i; ++k) c -= L(i, k) * X.col(k);
    X.col(i) = c * inv_diag[i];
  }
}

/// X = B L^-1 (backward substitution on the columns): X L = B.
template <class S, int M, int R>
void solve_right_lower(const Mat<S, M, M>& L, const Vec<S, M>& inv_diag, const Mat<S, R, M>& B, Mat<S, R, M>& X) {
  for (int i = M - 1; i >= 0; --i) {
    Vec<S, R> c = B.col(i);
    for (int k = i + 1; k < M; ++k) c -= L(k, i) * X.col(k);
    X.col(i) = c * inv_diag[i];
  }
}

/// The common end of kalman_correct and kalman_correct_diagonal: a result with any non-finite
/// part is NumericalFailure and leaves P and dx as they were; otherwise it is stored and Ok.
/// A finite innovation can still overflow y^T S^-1 y (a reading near the float maximum): an
/// infinite NIS is a failure too, never an Ok with a non-finite output.
template <class S, int N, int M>
Status commit_correction(Mat<S, N, N>& P, Vec<S, N>& dx, const Mat<S, N, N>& P_new, const Vec<S, N>& dx_new,
                         UpdateResult<S, M>& res) {
  if (!all_finite(P_new) || !all_finite(dx_new) || !std::isfinite(res.nis)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  P = P_new;
  dx = dx_new;
  res.status = Status::Ok;
  return res.status;
}

}  // namespace detail

/// The covariance time update P+ = Phi P Phi^T + Q for a transition Phi = [F B; 0 I] (a state
/// [a (NA), b (NB)] whose b part, biases, is constant over the step), by blocks: with
/// P = [A C; C^T D],
///   P+ = [F A F^T + F C B^T + B C^T F^T + B D B^T + Q_aa,  F C + B D;  (F C + B D)^T,  D + Q_bb],
/// Q_aa any expression of an NA x NA matrix (evaluated straight into the block: pass the
/// unevaluated product), Q_bb = q_bb I. The top-left block is symmetric only up to rounding
/// (the caller symmetrizes it); the others are exact mirrors. Writes P_new (not aliasing P).
template <class S, int NA, int NB, class QaaExpr>
void predict_covariance_fb(const Mat<S, NA + NB, NA + NB>& P, const Mat<S, NA, NA>& F, const Mat<S, NA, NB>& B,
                           const QaaExpr& Q_aa, S q_bb, Mat<S, NA + NB, NA + NB>& P_new) {
  const auto A = P.template topLeftCorner<NA, NA>();
  const auto C = P.template topRightCorner<NA, NB>();
  const auto D = P.template bottomRightCorner<NB, NB>();
  Mat<S, NA, NB> FC_BD;
  FC_BD.noalias() = F * C;
  FC_BD.noalias() += B * D;
  Mat<S, NA, NA> M;  // F A + B C^T  (the top rows of Phi P)
  M.noalias() = F * A;
  M.noalias() += B * C.transpose();
  P_new.template topLeftCorner<NA, NA>().noalias() = Q_aa;
  P_new.template topLeftCorner<NA, NA>().noalias() += M * F.transpose();
  P_new.template topLeftCorner<NA, NA>().noalias() += FC_BD * B.transpose();
  P_new.template topRightCorner<NA, NB>() = FC_BD;
  P_new.template bottomLeftCorner<NB, NA>() = FC_BD.transpose();
  P_new.template bottomRightCorner<NB, NB>() = D;
  P_new.template bottomRightCorner<NB, NB>().diagonal().array() += q_bb;
}

/// One Kalman correction with N states and M measurement rows.
///
/// Inputs: P (NxN), H (MxN), R (MxM), innovation y = z - h(x) (M). On success writes the state
/// correction dx = K y, replaces P by the Joseph-form update and fills `res` (innovation,
/// its covariance S, NIS). When `gate` is positive and NIS exceeds it, returns Rejected.
/// Any status other than Ok leaves P and dx unchanged; a non-finite result (P, dx or the NIS,
/// which a finite innovation near the float maximum can overflow) is NumericalFailure.
///
/// C0, NC: H is nonzero only in the NC columns starting at column C0 (a measurement of part of
/// the state, the usual case); the products then skip the zero columns. The default is a dense
/// H. Columns outside that range are ignored, so a caller must only narrow it when they are
/// zero.
template <class S, int N, int M, int C0 = 0, int NC = N>
Status kalman_correct(Mat<S, N, N>& P, const Mat<S, M, N>& H, const Mat<S, M, M>& R,
                      const Vec<S, M>& y, Vec<S, N>& dx, UpdateResult<S, M>& res,
                      S gate = S(0)) {
  res.innovation = y;
  const Mat<S, M, NC> Hc = H.template middleCols<NC>(C0);
  Mat<S, N, M> PHt;
  PHt.noalias() = P.template middleCols<NC>(C0).lazyProduct(Hc.transpose());
  Mat<S, M, M> Sm = R;
  Sm.noalias() += Hc.lazyProduct(PHt.template middleRows<NC>(C0));
  symmetrize(Sm);
  res.innovation_cov = Sm;
  if (!all_finite(Sm) || !all_finite(y)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  // S = L L^T (Cholesky).
  Mat<S, M, M> L;
  Vec<S, M> inv_diag;
  if (!detail::cholesky_small<S, M>(Sm, L, inv_diag)) {
    res.status = Status::SolveFailed;
    return res.status;
  }
  // NIS = |L^-1 y|^2.
  Mat<S, 1, M> w;
  detail::solve_right_lower_transposed<S, M, 1>(L, inv_diag, Mat<S, 1, M>(y.transpose()), w);
  res.nis = w.squaredNorm();
  if (gate > S(0) && !(res.nis <= gate)) {
    res.status = Status::Rejected;
    return res.status;
  }
  // K = P H^T S^-1 = (P H^T L^-T) L^-1 by two triangular solves, never an inverse. Plain
  // substitution loops: Eigen's triangular solve with a matrix right-hand side goes through its
  // blocked solver, whose heap fallback (never taken for fixed sizes) would still link malloc
  // into a microcontroller image (see docs/PORTING.md).
  Mat<S, N, M> Z, K;
  detail::solve_right_lower_transposed<S, M, N>(L, inv_diag, PHt, Z);
  detail::solve_right_lower<S, M, N>(L, inv_diag, Z, K);
  Vec<S, N> dx_new;
  dx_new.noalias() = K * y;
  Mat<S, N, N> P_new;
  joseph_update<S, N, M, C0, NC>(P, K, Hc, R, P_new);
  return detail::commit_correction(P, dx, P_new, dx_new, res);
}

namespace detail {

/// The columns J, J+1, ... of joseph_update_scalar's lower triangle, P(i, j) for i >= j, as
/// one vector expression per column. The column is started at the packet boundary below its
/// diagonal (J rounded down to a multiple of the SIMD width; J itself when nothing is
/// vectorized), so that it runs as whole packets: the few coefficients above the diagonal
/// that this computes too are overwritten by the mirror afterwards, and are never read before
/// (column J reads only its own coefficients).
template <class S, int N, int J>
void joseph_columns(Mat<S, N, N>& P, const Vec<S, N>& a, const Vec<S, N>& k, const Vec<S, N>& b) {
  if constexpr (J < N) {
    constexpr int kPacket = Eigen::internal::packet_traits<S>::Vectorizable ? Eigen::internal::packet_traits<S>::size : 1;
    constexpr int I0 = J - J % kPacket;
    constexpr int L = N - I0;
    auto col = P.col(J).template segment<L>(I0);
    col = col - a.template segment<L>(I0) * k[J] - k.template segment<L>(I0) * b[J];
    joseph_columns<S, N, J + 1>(P, a, k, b);
  }
}

/// P(j, i) = P(i, j) for i > j, column by column.
template <class S, int N, int J> void mirror_lower(Mat<S, N, N>& P) {
  if constexpr (J + 1 < N) {
    P.row(J).template segment<N - J - 1>(J + 1) = P.col(J).template segment<N - J - 1>(J + 1).transpose();
    mirror_lower<S, N, J + 1>(P);
  }
}

}  // namespace detail

/// The scalar Joseph update P+ = (I - k h^T) P (I - k h^T)^T + r k k^T for one measurement row
/// h and any gain k, given a = P h and s = h^T P h + r (so r = s - h^T a):
///   P+ = P - k a^T - a k^T + s k k^T = P - a k^T - k b^T,   b = a - s k,
/// (b is the gain's departure from the optimal a / s, times -s: rounding noise for the optimal
/// gain, which is why the Joseph form keeps a gain error out of P to first order), evaluated
/// once per pair (i >= j), P+(i, j) = P(i, j) - a_i k_j - k_i b_j in that order, and mirrored,
/// so P+ is exactly symmetric. O(N^2); in place.
///
/// The lower triangle is computed column by column as vector expressions on local copies of
/// a, k and b (detail::joseph_columns: whole SIMD packets, no aliasing between P and the
/// vectors), then mirrored once. The same operations in the same order per coefficient as a
/// scalar loop over the pairs, hence the same bits; in double with SSE2 (N = 6) 150 instead of
/// 210 instructions per call: that loop ran out of registers for the 3 N values it keeps.
///
/// Without SIMD (a Cortex-M4) the columns would only add the mirror's second pass: there the
/// pairs are computed in one loop that writes both halves (the same bits again).
template <class S, int N> void joseph_update_scalar(Mat<S, N, N>& P, const Vec<S, N>& k, const Vec<S, N>& a, S s) {
  if constexpr (Eigen::internal::packet_traits<S>::Vectorizable && Eigen::internal::packet_traits<S>::size > 1) {
    const Vec<S, N> av = a, kv = k;
    const Vec<S, N> bv = av - s * kv;
    detail::joseph_columns<S, N, 0>(P, av, kv, bv);
    detail::mirror_lower<S, N, 0>(P);
  } else {
    // Local arrays: written through P's reference, the loop would otherwise reload a, k and b
    // after every store (they could alias P).
    S av[N], kv[N], bv[N];
    for (int i = 0; i < N; ++i) {
      av[i] = a[i];
      kv[i] = k[i];
      bv[i] = a[i] - s * k[i];
    }
    S* p = P.data();  // column-major: P(i, j) = p[i + N j]
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 16
#endif
    for (int j = 0; j < N; ++j) {
      const S kj = kv[j], bj = bv[j];
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 16
#endif
      for (int i = j; i < N; ++i) {
        const S v = p[i + N * j] - av[i] * kj - kv[i] * bj;
        p[i + N * j] = v;
        p[j + N * i] = v;
      }
    }
  }
}

/// One Kalman correction with N states and M measurement rows whose noise is uncorrelated
/// (R = diag(r)): the rows are processed one after the other as scalar updates, each
/// linearized at the prior (H fixed), with the innovation of row i taken against the
/// correction accumulated so far, e_i = y_i - h_i^T dx. In exact arithmetic this is the joint
/// update of kalman_correct: the scalar variances s_i and the e_i are the pivots and the
/// forward substitution of the LDL^T factorization of S = H P H^T + R, so
///   NIS = y^T S^-1 y = sum_i e_i^2 / s_i,   S = L diag(s) L^T,  L_ji = h_j^T P_(i-1) h_i / s_i,
/// and the result's innovation, innovation_cov and nis are those of the joint update (up to
/// rounding). No M x M factorization, no N x M products: O(M N^2) multiply-adds.
///
/// Each scalar step uses the optimal gain k = a / s (a = P h) and the Joseph form
/// (joseph_update_scalar): its extra terms s k k^T - a k^T vanish in exact arithmetic, but they
/// keep a rounding error in k from entering P to first order, which the short form P - k a^T
/// does not (that matters in float32); evaluated once per pair and mirrored (exactly symmetric).
///
/// Statuses as kalman_correct: NumericalFailure for a non-finite H, r, y or result (the NIS
/// included), SolveFailed when a pivot s_i is not positive (S not positive definite), Rejected
/// when `gate` is positive and NIS exceeds it. Any status other than Ok leaves P and dx unchanged. C0, NC: H is nonzero
/// only in the NC columns from C0 on (see kalman_correct).
template <class S, int N, int M, int C0 = 0, int NC = N>
Status kalman_correct_diagonal(Mat<S, N, N>& P, const Mat<S, M, N>& H, const Vec<S, M>& r, const Vec<S, M>& y,
                               Vec<S, N>& dx, UpdateResult<S, M>& res, S gate = S(0));

/// The gain of kalman_correct_diagonal_in_place as computed: the optimal one. A gain map says
/// by optimal(row) whether it leaves row's gain optimal (RowForm::SymmetricWhereOptimal).
struct OptimalGain {
  template <class K> void operator()(int /*row*/, K& /*k*/) const {}
  static constexpr bool optimal(int /*row*/) { return true; }
};

/// The structure of the rows of H that kalman_correct_diagonal_in_place exploits (its products
/// skip what is known to be zero: the same sums of the same nonzero terms, so the same bits for
/// a finite covariance).
enum class RowShape {
  Dense,  ///< no known zeros
  Cross,  ///< row i of Hc is zero in column i % NC: the rows of a cross-product matrix [h x]
  Unit,   ///< row i of Hc is the unit row e_(i % NC): a direct measurement of the states
};

/// The covariance update of each scalar row in kalman_correct_diagonal_in_place.
enum class RowForm {
  Joseph,                 ///< the Joseph form for every row (joseph_update_scalar)
  SymmetricWhereOptimal,  ///< the symmetric form P - k a^T where the gain is optimal and the row weak
};

namespace detail {

/// h^T v over the NC columns of row `row` of Hc (shape as RowShape), v the matching NC values.
template <RowShape Shape, class S, int M, int NC, class V>
S row_dot(const Mat<S, M, NC>& Hc, int row, const V& v) {
  if constexpr (Shape == RowShape::Unit) {
    return v[row % NC];
  } else if constexpr (Shape == RowShape::Cross && NC == 3) {
    const int i = row % 3, c1 = i == 0 ? 1 : 0, c2 = i == 2 ? 1 : 2;  // the two other columns
    return Hc(row, c1) * v[c1] + Hc(row, c2) * v[c2];
  } else {
    return Hc.row(row).dot(v);
  }
}

/// row_dot for the row being processed, h = that row as a contiguous vector (a dense row's
/// products take h, as they always have: the same bits).
template <RowShape Shape, class S, int M, int NC, class V>
S row_dot(const Mat<S, M, NC>& Hc, const Eigen::Matrix<S, NC, 1>& h, int row, const V& v) {
  if constexpr (Shape == RowShape::Dense) {
    return h.dot(v);
  } else {
    return row_dot<Shape>(Hc, row, v);
  }
}

/// a = P h over the NC columns from C0 (shape as RowShape; h: row `row` of Hc, contiguous).
template <RowShape Shape, class S, int N, int M, int C0, int NC>
void row_product(const Mat<S, N, N>& P, const Mat<S, M, NC>& Hc, const Eigen::Matrix<S, NC, 1>& h, int row,
                 Vec<S, N>& a) {
  if constexpr (Shape == RowShape::Unit) {
    a = P.col(C0 + row % NC);
  } else if constexpr (Shape == RowShape::Cross && NC == 3) {
    const int i = row % 3, c1 = i == 0 ? 1 : 0, c2 = i == 2 ? 1 : 2;
    a.noalias() = P.col(C0 + c1) * Hc(row, c1) + P.col(C0 + c2) * Hc(row, c2);
  } else {
    a.noalias() = P.template middleCols<NC>(C0).lazyProduct(h);
  }
}

/// The columns J, J+1, ... of the symmetric form's lower triangle, P(i, j) - k_i a_j for i >= j,
/// as joseph_columns does the Joseph form's (whole SIMD packets from the packet boundary below
/// the diagonal; the few coefficients above it are overwritten by the mirror).
template <class S, int N, int J>
void symmetric_columns(Mat<S, N, N>& P, const Vec<S, N>& k, const Vec<S, N>& a) {
  if constexpr (J < N) {
    constexpr int kPacket = Eigen::internal::packet_traits<S>::Vectorizable ? Eigen::internal::packet_traits<S>::size : 1;
    constexpr int I0 = J - J % kPacket;
    constexpr int L = N - I0;
    auto col = P.col(J).template segment<L>(I0);
    col = col - k.template segment<L>(I0) * a[J];
    symmetric_columns<S, N, J + 1>(P, k, a);
  }
}

/// The symmetric form of a scalar update with the optimal gain k = a / s: P+ = P - k a^T,
/// evaluated once per pair (i >= j), P+(i, j) = P(i, j) - k_i a_j, and mirrored (exactly
/// symmetric). One multiply-add per coefficient against the Joseph form's two. As
/// joseph_update_scalar: columns as vector expressions where there is SIMD, one loop writing
/// both halves where there is none (the same bits).
template <class S, int N> void symmetric_update_scalar(Mat<S, N, N>& P, const Vec<S, N>& k, const Vec<S, N>& a) {
  if constexpr (Eigen::internal::packet_traits<S>::Vectorizable && Eigen::internal::packet_traits<S>::size > 1) {
    const Vec<S, N> av = a, kv = k;
    symmetric_columns<S, N, 0>(P, kv, av);
    mirror_lower<S, N, 0>(P);
  } else {
    S av[N], kv[N];
    for (int i = 0; i < N; ++i) {
      av[i] = a[i];
      kv[i] = k[i];
    }
    S* p = P.data();  // column-major: P(i, j) = p[i + N j]
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 16
#endif
    for (int j = 0; j < N; ++j) {
      const S aj = av[j];
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 16
#endif
      for (int i = j; i < N; ++i) {
        const S v = p[i + N * j] - kv[i] * aj;
        p[i + N * j] = v;
        p[j + N * i] = v;
      }
    }
  }
}

/// True when a row with innovation variance s and noise variance r is weak enough for the
/// symmetric form. The posterior variance along h is hPh r / s; the symmetric form computes it
/// as hPh - (hPh)^2 / s, a difference of terms of size hPh, so its rounding relative to the
/// result grows as eps s / r (and a rounding error of the gain enters P to first order). Below
/// s / r = min(1e6, 1 / (4096 eps)), i.e. 2,048 in float (a relative rounding of at most
/// 2.4e-4 of the posterior) and 1e6 in double (2.2e-10), the symmetric form is used; from there
/// on the Joseph form.
template <class S> bool weak_row(S s, S r) {
  // const, not constexpr: a scalar type without constexpr constructors (the benchmark's
  // counting scalar, bench/cpp/flop_counter.hpp) instantiates it too.
  const S kMaxRatio = std::min(S(1e6), S(1) / (S(4096) * std::numeric_limits<S>::epsilon()));
  return s < kMaxRatio * r;
}

}  // namespace detail

/// kalman_correct_diagonal on a scratch covariance, for a filter that already works on a copy
/// of its own (it saves two N x N copies and a finiteness test of P per correction).
/// Hc: the NC nonzero columns of H (from column C0 on). On Ok, Pw holds the corrected covariance
/// and dx the correction; on any other status Pw is partly updated and must be discarded. The
/// statuses are those of kalman_correct_diagonal but for one test left to the caller: a
/// non-finite Pw is not checked here (dx and the NIS are), so the caller must test Pw before
/// keeping it.
///
/// `gain(i, k)` may change the gain k (N) of row i before it is used: a Schmidt-Kalman
/// ("consider") update that must not correct some directions of the state projects them out.
/// The Joseph form keeps Pw the covariance of the error for any gain. When the directions taken
/// out of k lie in the null space of H (h_j^T k unchanged for every row j), the innovations
/// e_i, the pivots s_i, the NIS and the innovation covariance are those of the optimal update,
/// and the rows in turn give the same result as the projected joint gain.
///
/// Shape: the structure of Hc's rows (RowShape; the products skip the known zeros, same bits).
/// Form: RowForm::Joseph (the default) updates every row's covariance in the Joseph form;
/// RowForm::SymmetricWhereOptimal uses the symmetric form P - k a^T (one multiply-add per
/// coefficient instead of two) for a row whose gain is optimal (gain.optimal(row)) and that is
/// weak enough (detail::weak_row: s / r below about 1 / (4096 eps)) for its rounding not to
/// matter, the Joseph form otherwise.
template <class S, int N, int M, int C0, int NC, RowShape Shape = RowShape::Dense, RowForm Form = RowForm::Joseph,
          class Gain = OptimalGain>
Status kalman_correct_diagonal_in_place(Mat<S, N, N>& Pw, const Mat<S, M, NC>& Hc, const Vec<S, M>& r,
                                        const Vec<S, M>& y, Vec<S, N>& dx, UpdateResult<S, M>& res, S gate = S(0),
                                        const Gain& gain = Gain{}) {
  static_assert(C0 >= 0 && NC >= 1 && C0 + NC <= N, "H columns out of range");
  res.innovation = y;
  if (!all_finite(Hc) || !all_finite(r) || !all_finite(y)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  Vec<S, N> dxw = Vec<S, N>::Zero();
  Vec<S, M> s;
  Mat<S, M, M> L = Mat<S, M, M>::Identity();  // unit lower factor of S
  S nis = S(0);
  for (int i = 0; i < M; ++i) {
    const Eigen::Matrix<S, NC, 1> h = Hc.row(i).transpose();
    Vec<S, N> a;
    detail::row_product<Shape, S, N, M, C0, NC>(Pw, Hc, h, i, a);
    const S si = detail::row_dot<Shape>(Hc, h, i, a.template segment<NC>(C0)) + r[i];
    if (!std::isfinite(si)) {
      res.status = Status::NumericalFailure;
      return res.status;
    }
    if (!(si > S(0))) {
      res.status = Status::SolveFailed;
      return res.status;
    }
    s[i] = si;
    const S inv_s = S(1) / si;
    for (int j = i + 1; j < M; ++j) L(j, i) = detail::row_dot<Shape>(Hc, j, a.template segment<NC>(C0)) * inv_s;
    const S e = y[i] - detail::row_dot<Shape>(Hc, h, i, dxw.template segment<NC>(C0));
    nis += e * e * inv_s;
    Vec<S, N> k = a * inv_s;
    gain(i, k);
    dxw.noalias() += k * e;
    if constexpr (Form == RowForm::SymmetricWhereOptimal) {
      if (gain.optimal(i) && detail::weak_row(si, r[i])) {
        detail::symmetric_update_scalar<S, N>(Pw, k, a);
        continue;
      }
    }
    joseph_update_scalar<S, N>(Pw, k, a, si);
  }
  // S = L diag(s) L^T on the lower triangle, L unit lower: S(j, k) = sum_(i <= k) L(j, i) s_i L(k, i)
  // for j >= k, mirrored (exactly symmetric).
  for (int k = 0; k < M; ++k) {
    for (int j = k; j < M; ++j) {
      S v = s[k] * L(j, k);
      for (int i = 0; i < k; ++i) v += L(j, i) * s[i] * L(k, i);
      res.innovation_cov(j, k) = res.innovation_cov(k, j) = v;
    }
  }
  res.nis = nis;
  if (gate > S(0) && !(nis <= gate)) {
    res.status = Status::Rejected;
    return res.status;
  }
  if (!all_finite(dxw) || !std::isfinite(nis)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  dx = dxw;
  res.status = Status::Ok;
  return res.status;
}

template <class S, int N, int M, int C0, int NC>
Status kalman_correct_diagonal(Mat<S, N, N>& P, const Mat<S, M, N>& H, const Vec<S, M>& r, const Vec<S, M>& y,
                               Vec<S, N>& dx, UpdateResult<S, M>& res, S gate) {
  Mat<S, N, N> Pw = P;
  Vec<S, N> dxw;
  const Mat<S, M, NC> Hc = H.template middleCols<NC>(C0);
  if (kalman_correct_diagonal_in_place<S, N, M, C0, NC>(Pw, Hc, r, y, dxw, res, gate) != Status::Ok) return res.status;
  return detail::commit_correction(P, dx, Pw, dxw, res);
}

}  // namespace quatnav
