// test_robustness: the covariance floor and the fixed-size eigen-decomposition (robustness.hpp).
#include "robustness.hpp"

// --- covariance floor ------------------------------------------------------------------------
// The fixed-size Jacobi eigen-decomposition against Eigen's solver, on random symmetric matrices
// (including a repeated eigenvalue), in double and float.
template <class S, int N> void check_symmetric_eigen(std::mt19937& rng, S tol) {
  std::normal_distribution<double> nd;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix<double, N, N> B;
    for (int i = 0; i < N * N; ++i) B(i) = nd(rng);
    Eigen::Matrix<double, N, N> A = B + B.transpose();
    if (trial % 5 == 0) {  // repeated eigenvalue
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(A);
      Eigen::Matrix<double, N, 1> lam = es.eigenvalues();
      lam(1) = lam(0);
      A = es.eigenvectors() * lam.asDiagonal() * es.eigenvectors().transpose();
      A = (A + A.transpose()).eval() * 0.5;
    }
    const Mat<S, N, N> As = A.template cast<S>();
    Vec<S, N> lam;
    Mat<S, N, N> V;
    ASSERT_TRUE((detail::symmetric_eigen<S, N>(As, lam, &V)));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> ref(As.template cast<double>());
    Eigen::Matrix<double, N, 1> sorted = lam.template cast<double>();
    std::sort(sorted.data(), sorted.data() + N);
    const double scale = A.cwiseAbs().maxCoeff();
    EXPECT_LT((sorted - ref.eigenvalues()).cwiseAbs().maxCoeff(), tol * scale);
    EXPECT_LT((V.transpose() * V - Mat<S, N, N>::Identity()).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT((V * lam.asDiagonal() * V.transpose() - As).cwiseAbs().maxCoeff(), tol * scale);
  }
}

TEST(CovarianceFloor, JacobiEigenMatchesEigenSolver) {
  std::mt19937 rng(7);
  check_symmetric_eigen<double, 6>(rng, 1e-12);
  check_symmetric_eigen<double, 15>(rng, 1e-11);
  check_symmetric_eigen<float, 6>(rng, 2e-5f);
  check_symmetric_eigen<float, 15>(rng, 5e-5f);
}

TEST(CovarianceFloor, RepairsIndefiniteAndLeavesHealthyBitForBit) {
  Mat<double, 4, 4> A;
  A << 4, 1, 0.5, 0, 1, 3, 0.2, 0.1, 0.5, 0.2, 2, 0.3, 0, 0.1, 0.3, 1;
  Mat<double, 4, 4> P = A * A.transpose();
  const Mat<double, 4, 4> P0 = P;
  EXPECT_FALSE((floor_covariance<double, 4>(P, 1e-9)));
  EXPECT_TRUE(quatnav_fuzz::bits_equal(P, P0));
  // Rank-deficient and indefinite: eigenvalues {2, 1, 0, -1e-6}.
  Eigen::Matrix4d V = Eigen::Matrix4d::Identity();
  V.block<3, 3>(0, 0) = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized().toRotationMatrix();
  Mat<double, 4, 4> Q = V * Eigen::Vector4d(2, 1, 0, -1e-6).asDiagonal() * V.transpose();
  symmetrize(Q);
  const double floor = 1e-9;
  EXPECT_TRUE((floor_covariance<double, 4>(Q, floor)));
  const auto h = covariance_health<double, 4>(Q);
  EXPECT_TRUE(h.ok());
  EXPECT_GE(h.min_eig, floor * (1 - 1e-6));
  EXPECT_NEAR(h.max_eig, 2.0, 1e-12);
  EXPECT_EQ(h.asymmetry, 0.0);
  // floor <= 0 disables it.
  Mat<double, 4, 4> Qn = V * Eigen::Vector4d(2, 1, 0, -1e-6).asDiagonal() * V.transpose();
  const Mat<double, 4, 4> Qn0 = Qn;
  EXPECT_FALSE((floor_covariance<double, 4>(Qn, 0.0)));
  EXPECT_TRUE(quatnav_fuzz::bits_equal(Qn, Qn0));
}
