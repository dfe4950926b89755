// GpsInsFilter's covariance time update by blocks (detail::gpsins_Phi_blocks,
// detail::gpsins_propagate) against the dense products it replaces:
//   Phi = I + F dt + (F dt)^2 / 2,  Qd = (Phi Qc Phi^T + Qc) dt / 2,  P <- Phi P Phi^T + Qd,
// on random nominal states, specific forces, intervals, process noise and covariances, in double
// and float. The two differ only by the order of their sums: the bound is relative, per
// coefficient, to sqrt(P_ii P_jj) of the dense result (1e-12 in double, 1e-5 in float).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <quatnav/quatnav.hpp>

#include "random_matrix.hpp"

using namespace quatnav;

namespace {

template <class S> struct Draw {
  StrapdownState<S> nav;
  Vec3<S> f_b;
  S dt;
  GpsInsParams<S> p;
  Vec<S, 16> qc;
  Mat<S, 16, 16> P;
};

template <class S> Draw<S> draw(quatnav_test::Randn& rn, int k) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto u = [&] { return U(rn.g); };
  Draw<S> d;
  d.nav.lat = 1.3 * u();
  d.nav.lon = 3.0 * u();
  d.nav.h = 500.0 + 400.0 * u();
  d.nav.v_n = Vec3<S>(S(40 * u()), S(40 * u()), S(5 * u()));
  d.nav.q_nb = quat::normalized(Quat<S>(S(u()), S(u()), S(u()), S(u())));
  d.f_b = Vec3<S>(S(3 * u()), S(3 * u()), S(-9.8 + 3 * u()));
  d.dt = S(0.0025 + 0.05 * (1 + u()));  // 2.5 ms to 102.5 ms
  d.p.earth_rotation = k % 3 != 0;
  d.p.acc_bias_tau = k % 2 ? S(0) : S(100 + 50 * u());  // random walk or Gauss-Markov
  d.p.gyro_bias_tau = k % 4 < 2 ? S(200 + 50 * u()) : S(0);
  d.qc = detail::gpsins_Qc_diag(d.p, S(1 + 4 * (1 + u())));
  // A covariance with the scales of a running filter (m, m/s, rad, m/s^2, rad/s, m) and random
  // correlations: D (A A^T + I) D.
  Vec<double, 16> sig;
  sig << 3, 3, 5, 0.3, 0.3, 0.2, 0.01, 0.01, 0.05, 0.02, 0.02, 0.02, 1e-3, 1e-3, 1e-3, 2;
  for (int i = 0; i < 16; ++i) sig[i] *= std::exp(u());
  const Mat<double, 16, 16> C = rn.spd<Mat<double, 16, 16>>(1.0);
  d.P = (sig.asDiagonal() * C * sig.asDiagonal()).template cast<S>();
  symmetrize(d.P);
  return d;
}

template <class S> Mat<S, 16, 16> dense_Phi(const Draw<S>& d) {
  const Mat<S, 16, 16> Fdt = detail::gpsins_F<S>(d.nav, d.f_b, d.p) * d.dt;
  return Mat<S, 16, 16>::Identity() + Fdt + S(0.5) * (Fdt * Fdt);
}

template <class S> Mat<S, 16, 16> dense_update(const Draw<S>& d) {
  const Mat<S, 16, 16> Phi = dense_Phi(d);
  Mat<S, 16, 16> Qd = S(0.5) * d.dt * (Phi * d.qc.asDiagonal() * Phi.transpose());
  Qd.diagonal() += S(0.5) * d.dt * d.qc;
  Mat<S, 16, 16> P = Phi * d.P * Phi.transpose() + Qd;
  symmetrize(P);
  return P;
}

/// max_ij |A_ij - B_ij| / sqrt(B_ii B_jj)
template <class S> double max_rel(const Mat<S, 16, 16>& A, const Mat<S, 16, 16>& B) {
  double e = 0;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      e = std::max(e, std::abs(double(A(i, j)) - double(B(i, j))) / std::sqrt(double(B(i, i)) * double(B(j, j))));
  return e;
}

template <class S> void check_blockwise(double tol) {
  quatnav_test::Randn rn(20261202);
  double worst = 0, worst_phi = 0;
  for (int k = 0; k < 200; ++k) {
    const Draw<S> d = draw<S>(rn, k);
    const Mat<S, 16, 16> Phi_dense = dense_Phi(d);
    const detail::GpsInsPhi<S> blocks = detail::gpsins_Phi_blocks<S>(d.nav, d.f_b, d.dt, d.p);
    const Mat<S, 16, 16> Phi = blocks.dense();
    // The blocks that GpsInsPhi leaves out are exactly zero in the dense product.
    for (int i = 0; i < 16; ++i) {
      for (int j = 0; j < 16; ++j) {
        if (Phi(i, j) == S(0) && i != j) {
          ASSERT_EQ(Phi_dense(i, j), S(0)) << "k " << k << " (" << i << ", " << j << ")";
        }
      }
    }
    worst_phi = std::max(worst_phi, double((Phi - Phi_dense).cwiseAbs().maxCoeff()));
    ASSERT_EQ(detail::gpsins_Phi<S>(d.nav, d.f_b, d.dt, d.p), Phi);
    Mat<S, 16, 16> P = detail::gpsins_propagate<S>(blocks, d.P, d.qc, d.dt);
    symmetrize(P);
    ASSERT_TRUE(P.allFinite());
    const double e = max_rel<S>(P, dense_update(d));
    worst = std::max(worst, e);
    EXPECT_LE(e, tol) << "k " << k;
  }
  EXPECT_LE(worst_phi, tol);
  std::printf("%s: largest difference, P relative %.3g, Phi %.3g\n", sizeof(S) == 4 ? "float" : "double", worst,
              worst_phi);
}

TEST(GpsInsPropagate, BlockwiseEqualsDenseDouble) { check_blockwise<double>(1e-12); }
TEST(GpsInsPropagate, BlockwiseEqualsDenseFloat) { check_blockwise<float>(1e-5); }

// The filter's time update is the block-wise one: its covariance after predict() is the dense
// update from the state before (the filter symmetrizes; cov_floor is off by default).
template <class S> void check_filter(double tol) {
  quatnav_test::Randn rn(7);
  for (int k = 0; k < 20; ++k) {
    Draw<S> d = draw<S>(rn, k);
    GpsInsFilter<S> f(d.p);
    const Vec3<S> ba(S(0.01), S(-0.02), S(0.03)), bg(S(1e-3), S(2e-3), S(-1e-3));
    ASSERT_EQ(f.reset(d.nav.q_nb, d.nav.v_n, d.nav.lat, d.nav.lon, d.nav.h, ba, bg, d.P), Status::Ok);
    const Vec3<S> w(S(0.1), S(-0.2), S(0.3));
    const Vec3<S> f_m = d.f_b + ba;  // the filter subtracts its bias estimate
    const StrapdownState<S> nav = f.state().nav;
    const Mat<S, 16, 16> P0 = f.covariance();
    ASSERT_EQ(f.predict(w, f_m, d.dt), Status::Ok);
    Draw<S> ref = d;
    ref.nav = nav;
    ref.f_b = f_m - ba;
    ref.P = P0;
    ref.qc = detail::gpsins_Qc_diag(d.p, f.q_scale());
    EXPECT_LE(max_rel<S>(f.covariance(), dense_update(ref)), tol) << "k " << k;
  }
}

TEST(GpsInsPropagate, FilterTimeUpdateDouble) { check_filter<double>(1e-12); }
TEST(GpsInsPropagate, FilterTimeUpdateFloat) { check_filter<float>(1e-5); }

}  // namespace
