// The shared Kalman correction: against the textbook formulas, gating, failure leaves P alone.
#include <gtest/gtest.h>

#include <cstring>
#include <Eigen/LU>
#include <quatnav/core/kalman.hpp>
#include <random>

#include "random_matrix.hpp"

using namespace quatnav;
using quatnav_test::Randn;

// One correction against the textbook formulas K = P H^T S^-1, P+ = P - K S K^T, NIS y^T S^-1 y,
// with a dense random H (for N = 13 every product goes through fixed_mul; the reference uses
// operator*, Eigen's GEMM). Errors relative to the largest coefficient of P.
template <int N, int M> void check_textbook(unsigned seed, const Vec<double, M>& r, const Vec<double, M>& y,
                                            double tol) {
  Randn rnd(seed);
  const Mat<double, N, N> P0 = rnd.spd<Mat<double, N, N>>(1.0);
  const Mat<double, M, N> H = rnd.matrix<Mat<double, M, N>>();
  const Mat<double, M, M> R = r.asDiagonal();
  Mat<double, N, N> P = P0;
  Vec<double, N> dx;
  UpdateResult<double, M> res;
  ASSERT_EQ((kalman_correct<double, N, M>(P, H, R, y, dx, res)), Status::Ok);
  const Mat<double, M, M> S = H * P0 * H.transpose() + R;
  const Mat<double, N, M> K = P0 * H.transpose() * S.inverse();
  const double scale = P0.cwiseAbs().maxCoeff();
  EXPECT_LT((dx - K * y).norm(), tol * scale);
  EXPECT_LT((P - (P0 - K * S * K.transpose())).norm(), tol * scale);
  EXPECT_NEAR(res.nis, y.dot(S.inverse() * y), tol * (1 + res.nis));
  EXPECT_EQ(P, P.transpose());
}

TEST(Kalman, MatchesTextbookFormulas) {
  check_textbook<5, 2>(4, Vec2<double>(0.3, 0.5), Vec2<double>(0.7, -0.2), 1e-13);
  check_textbook<13, 3>(5, Vec3<double>(0.3, 0.5, 0.2), Vec3<double>(0.7, -0.2, 0.1), 1e-10);
}

TEST(Kalman, GateRejectsAndFailureLeavesCovarianceUntouched) {
  Mat<double, 3, 3> P = Mat<double, 3, 3>::Identity();
  Mat<double, 1, 3> H(1.0, 0.0, 0.0);
  Mat<double, 1, 1> R;
  R << 1.0;
  Vec<double, 1> y;
  y << 10.0;  // NIS = 100 / 2 = 50
  Vec<double, 3> dx = Vec<double, 3>::Constant(42.0);
  UpdateResult<double, 1> res;
  const Mat<double, 3, 3> P0 = P;
  EXPECT_EQ((kalman_correct<double, 3, 1>(P, H, R, y, dx, res, 9.0)), Status::Rejected);
  EXPECT_NEAR(res.nis, 50.0, 1e-12);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  EXPECT_EQ(dx[0], 42.0);
  R << -2.0;  // S = 1 - 2 < 0: not positive definite
  EXPECT_EQ((kalman_correct<double, 3, 1>(P, H, R, y, dx, res)), Status::SolveFailed);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  R << 1.0;
  y << std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ((kalman_correct<double, 3, 1>(P, H, R, y, dx, res)), Status::NumericalFailure);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
}

// fixed_mul (types.hpp) replaces operator* for the 12- to 15-state filters so that no GEMM
// kernel (and its malloc) is linked on bare metal: it must give operator*'s product.
template <class S, int R, int K, int C> void check_fixed_mul(std::mt19937& g, S tol) {
  std::normal_distribution<S> n;
  Mat<S, R, K> a;
  Mat<S, K, C> b;
  for (int i = 0; i < R * K; ++i) a.data()[i] = n(g);
  for (int i = 0; i < K * C; ++i) b.data()[i] = n(g);
  const Mat<S, R, C> ref = a * b;  // Eigen's own product (GEMM for these sizes)
  const Mat<S, R, C> got = fixed_mul(a, b);
  EXPECT_LE((got - ref).cwiseAbs().maxCoeff(), tol * (S(1) + ref.cwiseAbs().maxCoeff())) << R << "x" << K << "x" << C;
}

TEST(Kalman, FixedMulIsTheProduct) {
  std::mt19937 g(11);
  check_fixed_mul<double, 13, 13, 13>(g, 1e-14);
  check_fixed_mul<double, 15, 15, 15>(g, 1e-14);
  check_fixed_mul<double, 12, 24, 12>(g, 1e-14);
  check_fixed_mul<double, 3, 13, 13>(g, 1e-14);
  check_fixed_mul<double, 13, 4, 13>(g, 1e-14);
  check_fixed_mul<float, 13, 13, 13>(g, 1e-5f);
  check_fixed_mul<float, 15, 15, 15>(g, 1e-5f);
  check_fixed_mul<float, 12, 24, 12>(g, 1e-5f);
  // Below Eigen's GEMM threshold operator* already evaluates coefficient by coefficient:
  // the same arithmetic, so the same bits (the small filters are unchanged).
  std::normal_distribution<double> n;
  Mat<double, 7, 7> a, b;
  for (int i = 0; i < 49; ++i) a.data()[i] = n(g), b.data()[i] = n(g);
  const Mat<double, 7, 7> ref = a * b, got = fixed_mul(a, b);
  EXPECT_EQ(std::memcmp(ref.data(), got.data(), sizeof ref), 0);
}

// A random correction for the diagonal-R forms: P0 (N x N, SPD), H nonzero in its NC columns from
// C0 on, R = diag(r), innovation y.
template <int N, int M, int C0, int NC> struct DiagonalProblem {
  explicit DiagonalProblem(unsigned seed) {
    Randn rnd(seed);
    P0 = rnd.spd<Mat<double, N, N>>(0.1);
    H.setZero();
    for (int i = 0; i < M; ++i)
      for (int j = C0; j < C0 + NC; ++j) H(i, j) = rnd();
    for (int i = 0; i < M; ++i) {
      r[i] = 0.05 + std::abs(rnd());
      y[i] = rnd();
    }
  }
  Mat<double, N, N> P0;
  Mat<double, M, N> H;
  Vec<double, M> r, y;
};

// Sequential scalar processing with a diagonal R gives the joint update (kalman_correct): the
// same dx, P, NIS and innovation covariance up to rounding, also when H is nonzero only in some
// columns (the C0/NC narrowing).
template <int N, int M, int C0, int NC> void check_diagonal_matches_joint(unsigned seed) {
  const DiagonalProblem<N, M, C0, NC> pb(seed);
  const Mat<double, N, N>& P0 = pb.P0;
  const Mat<double, M, N>& H = pb.H;
  const Vec<double, M>& r = pb.r;
  const Vec<double, M>& y = pb.y;
  const Mat<double, M, M> R = r.asDiagonal();
  Mat<double, N, N> Pj = P0, Ps = P0;
  Vec<double, N> dxj, dxs;
  UpdateResult<double, M> rj, rs;
  ASSERT_EQ((kalman_correct<double, N, M, C0, NC>(Pj, H, R, y, dxj, rj)), Status::Ok);
  ASSERT_EQ((kalman_correct_diagonal<double, N, M, C0, NC>(Ps, H, r, y, dxs, rs)), Status::Ok);
  const double scale = P0.cwiseAbs().maxCoeff();
  EXPECT_LT((dxs - dxj).norm(), 1e-12 * scale);
  EXPECT_LT((Ps - Pj).norm(), 1e-12 * scale);
  EXPECT_NEAR(rs.nis, rj.nis, 1e-12 * (1 + rj.nis));
  EXPECT_LT((rs.innovation_cov - rj.innovation_cov).norm(), 1e-12 * scale);
  EXPECT_EQ(rs.innovation, y);
  EXPECT_EQ(Ps, Ps.transpose());
  // The joint NIS from the textbook formula.
  const Mat<double, M, M> S = H * P0 * H.transpose() + R;
  EXPECT_NEAR(rs.nis, y.dot(S.inverse() * y), 1e-10 * (1 + rs.nis));
}

// The in-place form on a scratch copy gives the same bits as kalman_correct_diagonal.
template <int N, int M, int C0, int NC> void check_diagonal_in_place(unsigned seed) {
  const DiagonalProblem<N, M, C0, NC> pb(seed);
  const Mat<double, N, N>& P0 = pb.P0;
  const Mat<double, M, N>& H = pb.H;
  const Vec<double, M>& r = pb.r;
  const Vec<double, M>& y = pb.y;
  Mat<double, N, N> Pa = P0, Pb = P0;
  Vec<double, N> dxa, dxb;
  UpdateResult<double, M> ra, rb;
  ASSERT_EQ((kalman_correct_diagonal<double, N, M, C0, NC>(Pa, H, r, y, dxa, ra)), Status::Ok);
  const Mat<double, M, NC> Hc = H.template middleCols<NC>(C0);
  ASSERT_EQ((kalman_correct_diagonal_in_place<double, N, M, C0, NC>(Pb, Hc, r, y, dxb, rb)), Status::Ok);
  EXPECT_EQ(std::memcmp(Pa.data(), Pb.data(), sizeof Pa), 0);
  EXPECT_EQ(std::memcmp(dxa.data(), dxb.data(), sizeof dxa), 0);
  EXPECT_EQ(ra.nis, rb.nis);
  EXPECT_EQ(ra.innovation_cov, rb.innovation_cov);
}

// The row shapes skip only terms that are exactly zero: rows of a cross-product matrix [h x]
// (RowShape::Cross, also two of them stacked, as the joint accelerometer + magnetometer update)
// and unit rows (RowShape::Unit) give the bits of the dense products.
template <int M, int C0, RowShape Shape> void check_row_shape(unsigned seed, const Mat<double, M, 3>& Hc) {
  Randn rnd(seed);
  const Mat<double, 6, 6> P0 = rnd.spd<Mat<double, 6, 6>>(0.1);
  Vec<double, M> r, y;
  for (int i = 0; i < M; ++i) {
    r[i] = 0.05 + std::abs(rnd());
    y[i] = rnd();
  }
  Mat<double, 6, 6> Pd = P0, Ps = P0;
  Vec<double, 6> dxd, dxs;
  UpdateResult<double, M> rd, rs;
  ASSERT_EQ((kalman_correct_diagonal_in_place<double, 6, M, C0, 3>(Pd, Hc, r, y, dxd, rd)), Status::Ok);
  ASSERT_EQ((kalman_correct_diagonal_in_place<double, 6, M, C0, 3, Shape>(Ps, Hc, r, y, dxs, rs)), Status::Ok);
  EXPECT_EQ(std::memcmp(Pd.data(), Ps.data(), sizeof Pd), 0);
  EXPECT_EQ(std::memcmp(dxd.data(), dxs.data(), sizeof dxd), 0);
  EXPECT_EQ(rd.nis, rs.nis);
  EXPECT_EQ(rd.innovation_cov, rs.innovation_cov);
}

Mat<double, 3, 3> cross_matrix(const Vec<double, 3>& h) {
  Mat<double, 3, 3> m;
  m << 0.0, -h[2], h[1], h[2], 0.0, -h[0], -h[1], h[0], 0.0;
  return m;
}

TEST(Kalman, RowShapesGiveTheDenseBits) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    Randn rnd(seed + 100);
    const Vec<double, 3> h(rnd(), rnd(), rnd()), g(rnd(), rnd(), rnd());
    check_row_shape<3, 0, RowShape::Cross>(seed, cross_matrix(h));
    Mat<double, 6, 3> H2;
    H2 << cross_matrix(h), cross_matrix(g);
    check_row_shape<6, 0, RowShape::Cross>(seed, H2);
    check_row_shape<3, 3, RowShape::Unit>(seed, Mat<double, 3, 3>::Identity());
  }
}

/// A gain map that projects the gain of the rows before `rows` off the first state (a Schmidt
/// update), as QuaternionEKF's accelerometer rows do.
struct ProjectFirstState {
  int rows;
  bool optimal(int row) const { return row >= rows; }
  template <class K> void operator()(int row, K& k) const {
    if (row < rows) k[0] = 0.0;
  }
};

// RowForm::SymmetricWhereOptimal: the symmetric form P - k a^T for an optimal-gain row that is
// not too strong (detail::weak_row), the Joseph form's bits for a projected gain and for a strong
// row; exactly symmetric either way.
TEST(Kalman, SymmetricFormWhereTheGainIsOptimalAndTheRowWeak) {
  EXPECT_TRUE(detail::weak_row<float>(2000.0f, 1.0f));
  EXPECT_FALSE(detail::weak_row<float>(2100.0f, 1.0f));
  EXPECT_TRUE(detail::weak_row<double>(9e5, 1.0));
  EXPECT_FALSE(detail::weak_row<double>(1.1e6, 1.0));
  int differs = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const DiagonalProblem<6, 3, 0, 3> pb(seed);
    const Mat<double, 3, 3> Hc = pb.H.middleCols<3>(0);
    for (const double r_scale : {1.0, 1e-9}) {  // weak rows; rows 1e9 times stronger
      const Vec<double, 3> r = pb.r * r_scale;
      for (const int projected : {0, 3}) {
        const ProjectFirstState gain{projected};
        Mat<double, 6, 6> Pj = pb.P0, Ps = pb.P0;
        Vec<double, 6> dxj, dxs;
        UpdateResult<double, 3> rj, rs;
        ASSERT_EQ((kalman_correct_diagonal_in_place<double, 6, 3, 0, 3, RowShape::Dense, RowForm::Joseph>(
                      Pj, Hc, r, pb.y, dxj, rj, 0.0, gain)),
                  Status::Ok);
        ASSERT_EQ((kalman_correct_diagonal_in_place<double, 6, 3, 0, 3, RowShape::Dense, RowForm::SymmetricWhereOptimal>(
                      Ps, Hc, r, pb.y, dxs, rs, 0.0, gain)),
                  Status::Ok);
        EXPECT_EQ(Ps, Ps.transpose());
        if (projected || r_scale < 1.0) {  // the Joseph form: the same bits
          EXPECT_EQ(std::memcmp(Pj.data(), Ps.data(), sizeof Pj), 0) << seed << " " << r_scale << " " << projected;
          EXPECT_EQ(std::memcmp(dxj.data(), dxs.data(), sizeof dxj), 0);
        } else {  // the symmetric form: the same matrix up to rounding
          const double scale = pb.P0.cwiseAbs().maxCoeff();
          EXPECT_LT((Ps - Pj).norm(), 1e-13 * scale);
          EXPECT_LT((dxs - dxj).norm(), 1e-13 * scale);
          EXPECT_NEAR(rs.nis, rj.nis, 1e-12 * (1 + rj.nis));
          differs += std::memcmp(Pj.data(), Ps.data(), sizeof Pj) != 0;
        }
      }
    }
  }
  EXPECT_GT(differs, 0) << "the symmetric form was never taken";
}

TEST(Kalman, DiagonalInPlaceMatchesCopying) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    check_diagonal_in_place<7, 3, 0, 4>(seed);
    check_diagonal_in_place<6, 3, 0, 3>(seed + 30);
    check_diagonal_in_place<6, 3, 3, 3>(seed + 50);
  }
  // The one test it leaves to the caller: a covariance with a non-finite element outside the
  // measured columns. In place the status is Ok (the caller tests Pw); kalman_correct_diagonal
  // reports NumericalFailure and keeps P and dx.
  Mat<double, 2, 2> P = Mat<double, 2, 2>::Identity();
  P(0, 0) = std::numeric_limits<double>::infinity();
  const Mat<double, 2, 2> P0 = P;
  const Mat<double, 1, 2> H(0.0, 1.0);
  const Mat<double, 1, 1> Hc(1.0);
  const Vec<double, 1> r(1.0), y(0.5);
  Vec<double, 2> dx = Vec<double, 2>::Constant(42.0);
  UpdateResult<double, 1> res;
  Mat<double, 2, 2> Pw = P;
  EXPECT_EQ((kalman_correct_diagonal_in_place<double, 2, 1, 1, 1>(Pw, Hc, r, y, dx, res)), Status::Ok);
  EXPECT_FALSE(all_finite(Pw));
  dx.setConstant(42.0);
  EXPECT_EQ((kalman_correct_diagonal<double, 2, 1>(P, H, r, y, dx, res)), Status::NumericalFailure);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof P), 0);
  EXPECT_EQ(dx[0], 42.0);
}

// symmetrize works over one triangle in place above 8 x 8 and as the expression up to it; either
// way it must give the bits of (P_ij + P_ji) / 2 taken coefficient by coefficient, in float and
// double, on a matrix and on a block of one (leaving the rest of the matrix alone), with
// non-finite coefficients carried as the expression carries them.
template <class S, int N> void check_symmetrize(unsigned seed) {
  Randn rnd(seed);
  Mat<S, N, N> P = rnd.matrix<Mat<double, N, N>>().template cast<S>();
  P(0, N - 1) = std::numeric_limits<S>::max();
  P(N - 1, 0) = std::numeric_limits<S>::max();
  P(1, 1) = std::numeric_limits<S>::max();
  P(2, 0) = std::numeric_limits<S>::quiet_NaN();
  Mat<S, N, N> expected;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) expected(i, j) = (P(i, j) + P(j, i)) * S(0.5);
  const Mat<S, N, N> expression = (P + P.transpose()) * S(0.5);
  EXPECT_EQ(std::memcmp(expression.data(), expected.data(), sizeof expected), 0);
  Mat<S, N, N> got = P;
  symmetrize(got);
  EXPECT_EQ(std::memcmp(got.data(), expected.data(), sizeof got), 0);
  Mat<S, N + 2, N + 2> big = Mat<S, N + 2, N + 2>::Constant(S(3));
  big.template block<N, N>(1, 1) = P;
  auto blk = big.template block<N, N>(1, 1);
  symmetrize(blk);
  const Mat<S, N, N> inner = big.template block<N, N>(1, 1);
  EXPECT_EQ(std::memcmp(inner.data(), expected.data(), sizeof inner), 0);
  big.template block<N, N>(1, 1).setConstant(S(3));
  EXPECT_TRUE((big.array() == S(3)).all());  // the border untouched
}

TEST(Kalman, SymmetrizeGivesTheBitsOfTheExpression) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    check_symmetrize<double, 16>(seed);
    check_symmetrize<float, 16>(seed + 10);
    check_symmetrize<double, 6>(seed + 20);
    check_symmetrize<float, 3>(seed + 30);
  }
}

TEST(Kalman, DiagonalSequentialMatchesJoint) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    check_diagonal_matches_joint<7, 3, 0, 4>(seed);
    check_diagonal_matches_joint<7, 6, 0, 4>(seed + 10);
    check_diagonal_matches_joint<7, 3, 4, 3>(seed + 20);
    check_diagonal_matches_joint<6, 3, 0, 3>(seed + 30);
    check_diagonal_matches_joint<13, 3, 0, 13>(seed + 40);
  }
}

TEST(Kalman, DiagonalGateAndFailuresLeaveCovarianceUntouched) {
  Mat<double, 3, 3> P = Mat<double, 3, 3>::Identity();
  const Mat<double, 3, 3> P0 = P;
  Mat<double, 2, 3> H;
  H << 1.0, 0.0, 0.0, 0.0, 1.0, 0.0;
  Vec2<double> r(1.0, 1.0), y(10.0, 0.0);  // NIS = 100 / 2 = 50
  Vec<double, 3> dx = Vec<double, 3>::Constant(42.0);
  UpdateResult<double, 2> res;
  EXPECT_EQ((kalman_correct_diagonal<double, 3, 2>(P, H, r, y, dx, res, 9.0)), Status::Rejected);
  EXPECT_NEAR(res.nis, 50.0, 1e-12);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  EXPECT_EQ(dx[0], 42.0);
  r << 1.0, -2.0;  // the second pivot 1 - 2 < 0: S not positive definite
  EXPECT_EQ((kalman_correct_diagonal<double, 3, 2>(P, H, r, y, dx, res)), Status::SolveFailed);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  r << 1.0, 1.0;
  y[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ((kalman_correct_diagonal<double, 3, 2>(P, H, r, y, dx, res)), Status::NumericalFailure);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  EXPECT_EQ(dx[0], 42.0);
}

// The scalar Joseph form equals (I - k h^T) P (I - k h^T)^T + r k k^T for any gain.
TEST(Kalman, ScalarJosephMatchesProductForm) {
  Randn rnd(9);
  const Mat<double, 7, 7> P0 = rnd.spd<Mat<double, 7, 7>>(1.0);
  Vec<double, 7> h, k;
  for (int i = 0; i < 7; ++i) {
    h[i] = rnd();
    k[i] = rnd();  // not the optimal gain
  }
  const double r = 0.7;
  const Vec<double, 7> a = P0 * h;
  Mat<double, 7, 7> P = P0;
  joseph_update_scalar<double, 7>(P, k, a, h.dot(a) + r);
  const Mat<double, 7, 7> IKH = Mat<double, 7, 7>::Identity() - k * h.transpose();
  const Mat<double, 7, 7> ref = IKH * P0 * IKH.transpose() + r * k * k.transpose();
  EXPECT_LT((P - ref).norm(), 1e-11 * ref.norm());
  EXPECT_EQ(P, P.transpose());
}

// Each coefficient of the scalar Joseph form is P(i, j) - a_i k_j - k_i b_j (b = a - s k), in
// that order, for i >= j, and its mirror: the vectorized columns give the bits of that scalar
// loop, in float and double, for even and odd sizes (where a column starts above its diagonal).
template <class S, int N> void expect_joseph_bits_of_scalar_loop(unsigned seed) {
  Randn rnd(seed);
  const Mat<S, N, N> P0 = rnd.spd<Mat<double, N, N>>(0.5).template cast<S>();
  Vec<S, N> k, a;
  for (int i = 0; i < N; ++i) {
    k[i] = S(rnd());
    a[i] = S(rnd());
  }
  const S s = S(1.3);
  Mat<S, N, N> ref = P0;
  for (int j = 0; j < N; ++j)
    for (int i = j; i < N; ++i) {
      const S b_j = a[j] - s * k[j];
      ref(i, j) = ref(j, i) = P0(i, j) - a[i] * k[j] - k[i] * b_j;
    }
  Mat<S, N, N> P = P0;
  joseph_update_scalar<S, N>(P, k, a, s);
  EXPECT_EQ(std::memcmp(P.data(), ref.data(), sizeof(P)), 0) << "N = " << N << ", " << sizeof(S) * 8 << " bit";
}

TEST(Kalman, ScalarJosephIsTheScalarLoopBitForBit) {
  expect_joseph_bits_of_scalar_loop<double, 6>(3);
  expect_joseph_bits_of_scalar_loop<double, 7>(4);
  expect_joseph_bits_of_scalar_loop<double, 15>(5);
  expect_joseph_bits_of_scalar_loop<float, 6>(6);
  expect_joseph_bits_of_scalar_loop<float, 7>(7);
  expect_joseph_bits_of_scalar_loop<float, 9>(8);
}

// A finite innovation whose y^T S^-1 y overflows (1e200 against S = 2: dx and P stay finite,
// the NIS is infinite) is a NumericalFailure in both corrections, with P and dx untouched; with
// a gate it stays a rejection (an infinite NIS exceeds any gate).
TEST(Kalman, OverflowingNisIsRefused) {
  Mat<double, 3, 3> P = Mat<double, 3, 3>::Identity();
  const Mat<double, 3, 3> P0 = P;
  Mat<double, 1, 3> H(1.0, 0.0, 0.0);
  Mat<double, 1, 1> R;
  R << 1.0;
  Vec<double, 1> y;
  y << 1e200;
  Vec<double, 3> dx = Vec<double, 3>::Constant(42.0);
  UpdateResult<double, 1> res;
  EXPECT_EQ((kalman_correct<double, 3, 1>(P, H, R, y, dx, res)), Status::NumericalFailure);
  EXPECT_TRUE(std::isinf(res.nis));
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  EXPECT_EQ(dx[0], 42.0);
  EXPECT_EQ((kalman_correct<double, 3, 1>(P, H, R, y, dx, res, 9.0)), Status::Rejected);
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);

  const Vec<double, 1> r(1.0);
  EXPECT_EQ((kalman_correct_diagonal<double, 3, 1>(P, H, r, y, dx, res)), Status::NumericalFailure);
  EXPECT_TRUE(std::isinf(res.nis));
  EXPECT_EQ(std::memcmp(P.data(), P0.data(), sizeof(P0)), 0);
  EXPECT_EQ(dx[0], 42.0);
  EXPECT_EQ((kalman_correct_diagonal<double, 3, 1>(P, H, r, y, dx, res, 9.0)), Status::Rejected);

  // The same update with a representable NIS is accepted.
  y << 1e100;
  EXPECT_EQ((kalman_correct<double, 3, 1>(P, H, R, y, dx, res)), Status::Ok);
  EXPECT_TRUE(std::isfinite(res.nis));
}
