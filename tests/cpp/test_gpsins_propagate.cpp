// GpsInsFilter's covariance time update by blocks (detail::gpsins_Phi_blocks,
// detail::gpsins_propagate) against the dense products it replaces:
//   Phi = I + F dt + (F dt)^2 / 2,  Qd = (Phi Qc Phi^T + Qc) dt / 2,  P <- Phi P Phi^T + Qd,
// on random nominal states, specific forces, intervals, process noise (with or without the
// attitude's rate-proportional block, detail::gpsins_Qc_rate) and covariances, in double
// and float, with 16 error states and with the 22 of the scale-factor states (random scale
// factors and rates). The two differ only by the order of their sums: the bound is relative, per
// coefficient, to sqrt(P_ii P_jj) of the dense result (1e-12 in double, 1e-5 in float).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <quatnav/quatnav.hpp>

#include "random_matrix.hpp"

using namespace quatnav;

namespace {

template <class S, bool SF> struct Draw {
  static constexpr int N = gpsins::kStates<SF>;
  GpsInsState<S, SF> st;
  StrapdownState<S>& nav = st.nav;
  Vec3<S> f_b, w_b;
  S dt;
  GpsInsParams<S> p;
  Vec<S, N> qc;
  Mat3<S> qa;  // the full 3 x 3 attitude block added to Qc
  Mat<S, N, N> P;
  Draw() = default;
  Draw(const Draw& o) : st(o.st), f_b(o.f_b), w_b(o.w_b), dt(o.dt), p(o.p), qc(o.qc), qa(o.qa), P(o.P) {}
  Draw& operator=(const Draw& o) {
    st = o.st;
    f_b = o.f_b;
    w_b = o.w_b;
    dt = o.dt;
    p = o.p;
    qc = o.qc;
    qa = o.qa;
    P = o.P;
    return *this;
  }
};

template <class S, bool SF> Draw<S, SF> draw(quatnav_test::Randn& rn, int k) {
  constexpr int N = gpsins::kStates<SF>;
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto u = [&] { return U(rn.g); };
  Draw<S, SF> d;
  d.nav.lat = 1.3 * u();
  d.nav.lon = 3.0 * u();
  d.nav.h = 500.0 + 400.0 * u();
  d.nav.v_n = Vec3<S>(S(40 * u()), S(40 * u()), S(5 * u()));
  d.nav.q_nb = quat::normalized(Quat<S>(S(u()), S(u()), S(u()), S(u())));
  d.f_b = Vec3<S>(S(3 * u()), S(3 * u()), S(-9.8 + 3 * u()));
  d.w_b = Vec3<S>(S(u()), S(u()), S(u()));
  if constexpr (SF) {
    d.st.acc_scale = Vec3<S>(S(0.02 * u()), S(0.02 * u()), S(0.02 * u()));
    d.st.gyro_scale = Vec3<S>(S(0.02 * u()), S(0.02 * u()), S(0.02 * u()));
  }
  d.dt = S(0.0025 + 0.05 * (1 + u()));  // 2.5 ms to 102.5 ms
  d.p.earth_rotation = k % 3 != 0;
  d.p.acc_bias_tau = k % 2 ? S(0) : S(100 + 50 * u());  // random walk or Gauss-Markov
  d.p.gyro_bias_tau = k % 4 < 2 ? S(200 + 50 * u()) : S(0);
  d.p.acc_scale_noise = S(1e-4 * (1 + u()));
  d.p.gyro_scale_noise = S(1e-4 * (1 + u()));
  d.p.gyro_rate_noise = k % 2 ? S(0) : S(5e-3 * (1 + u()));  // off, or on
  const S q_scale = S(1 + 4 * (1 + u()));
  d.qc = detail::gpsins_Qc_diag<S, SF>(d.p, q_scale);
  d.qa = detail::gpsins_Qc_rate<S, SF>(d.p, q_scale, d.nav.q_nb, d.w_b);
  // A covariance with the scales of a running filter (m, m/s, rad, m/s^2, rad/s, m; scale factors
  // 1) and random correlations: D (A A^T + I) D.
  Vec<double, N> sig;
  sig.template head<16>() << 3, 3, 5, 0.3, 0.3, 0.2, 0.01, 0.01, 0.05, 0.02, 0.02, 0.02, 1e-3, 1e-3, 1e-3, 2;
  if constexpr (SF) sig.template tail<6>().setConstant(3e-3);
  for (int i = 0; i < N; ++i) sig[i] *= std::exp(u());
  const Mat<double, N, N> C = rn.spd<Mat<double, N, N>>(1.0);
  d.P = (sig.asDiagonal() * C * sig.asDiagonal()).template cast<S>();
  symmetrize(d.P);
  return d;
}

template <class S, bool SF> using MatN = Mat<S, gpsins::kStates<SF>, gpsins::kStates<SF>>;

template <class S, bool SF> MatN<S, SF> dense_Phi(const Draw<S, SF>& d) {
  MatN<S, SF> Fdt;
  if constexpr (SF)
    Fdt = detail::gpsins_F_scaled<S>(d.nav, d.f_b, d.w_b, d.st.acc_scale, d.st.gyro_scale, d.p) * d.dt;
  else
    Fdt = detail::gpsins_F<S>(d.nav, d.f_b, d.p) * d.dt;
  return MatN<S, SF>::Identity() + Fdt + S(0.5) * (Fdt * Fdt);
}

template <class S, bool SF> MatN<S, SF> dense_update(const Draw<S, SF>& d) {
  const MatN<S, SF> Phi = dense_Phi(d);
  MatN<S, SF> Qc = d.qc.asDiagonal();
  Qc.template block<3, 3>(6, 6) += d.qa;
  const MatN<S, SF> Qd = S(0.5) * d.dt * (Phi * Qc * Phi.transpose() + Qc);
  MatN<S, SF> P = Phi * d.P * Phi.transpose() + Qd;
  symmetrize(P);
  return P;
}

/// max_ij |A_ij - B_ij| / sqrt(B_ii B_jj)
template <class S, int N> double max_rel(const Mat<S, N, N>& A, const Mat<S, N, N>& B) {
  double e = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      e = std::max(e, std::abs(double(A(i, j)) - double(B(i, j))) / std::sqrt(double(B(i, i)) * double(B(j, j))));
  return e;
}

template <class S, bool SF> void check_blockwise(double tol) {
  constexpr int N = gpsins::kStates<SF>;
  quatnav_test::Randn rn(20261202);
  double worst = 0, worst_phi = 0;
  for (int k = 0; k < 200; ++k) {
    const Draw<S, SF> d = draw<S, SF>(rn, k);
    const MatN<S, SF> Phi_dense = dense_Phi(d);
    const detail::GpsInsPhi<S, SF> blocks = detail::gpsins_Phi_state<S, SF>(d.st, d.f_b, d.w_b, d.dt, d.p);
    const MatN<S, SF> Phi = blocks.dense();
    // The blocks that GpsInsPhi leaves out are exactly zero in the dense product.
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        if (Phi(i, j) == S(0) && i != j) {
          ASSERT_EQ(Phi_dense(i, j), S(0)) << "k " << k << " (" << i << ", " << j << ")";
        }
      }
    }
    worst_phi = std::max(worst_phi, double((Phi - Phi_dense).cwiseAbs().maxCoeff()));
    if constexpr (!SF) {
      ASSERT_EQ(detail::gpsins_Phi<S>(d.nav, d.f_b, d.dt, d.p), Phi);
    }
    MatN<S, SF> P = detail::gpsins_propagate<S, SF>(blocks, d.P, d.qc, d.dt, &d.qa);
    symmetrize(P);
    ASSERT_TRUE(P.allFinite());
    const double e = max_rel<S, N>(P, dense_update(d));
    worst = std::max(worst, e);
    EXPECT_LE(e, tol) << "k " << k;
  }
  EXPECT_LE(worst_phi, tol);
  std::printf("%s, %d states: largest difference, P relative %.3g, Phi %.3g\n", sizeof(S) == 4 ? "float" : "double",
              N, worst, worst_phi);
}

TEST(GpsInsPropagate, BlockwiseEqualsDenseDouble) { check_blockwise<double, false>(1e-12); }
TEST(GpsInsPropagate, BlockwiseEqualsDenseFloat) { check_blockwise<float, false>(1e-5); }
TEST(GpsInsPropagate, ScaleFactorsBlockwiseEqualsDenseDouble) { check_blockwise<double, true>(1e-12); }
TEST(GpsInsPropagate, ScaleFactorsBlockwiseEqualsDenseFloat) { check_blockwise<float, true>(1e-5); }

// The filter's time update is the block-wise one: its covariance after predict() is the dense
// update from the state before (the filter symmetrizes; cov_floor is off by default). In every
// other draw with the rate-proportional attitude noise, written out here from its derivation
// (detail::gpsins_Qc_rate) at the corrected rate w and the attitude after the step.
template <class S, bool SF> void check_filter(double tol) {
  constexpr int N = gpsins::kStates<SF>;
  quatnav_test::Randn rn(7);
  for (int k = 0; k < 20; ++k) {
    Draw<S, SF> d = draw<S, SF>(rn, k);
    GpsInsFilter<S, SF> f(d.p);
    const Vec3<S> ba(S(0.01), S(-0.02), S(0.03)), bg(S(1e-3), S(2e-3), S(-1e-3));
    ASSERT_EQ(f.reset(d.nav.q_nb, d.nav.v_n, d.nav.lat, d.nav.lon, d.nav.h, ba, bg, d.P), Status::Ok);
    GpsInsState<S, SF> st = f.state();
    st.acc_scale = d.st.acc_scale;
    st.gyro_scale = d.st.gyro_scale;
    ASSERT_EQ(f.set_state(st), Status::Ok);
    const Vec3<S> w(S(0.1), S(-0.2), S(0.3));
    // The sensor reads (1 + s) x + b; the filter undoes both with its estimates.
    const Vec3<S> f_m = (Vec3<S>::Ones() + st.acc_scale).cwiseProduct(d.f_b) + ba;
    const StrapdownState<S> nav = f.state().nav;
    const MatN<S, SF> P0 = f.covariance();
    ASSERT_EQ(f.predict(w, f_m, d.dt), Status::Ok);
    Draw<S, SF> ref = d;
    ref.nav = nav;
    ref.f_b = detail::gpsins_correct<S, SF>(f_m, ba, st.acc_scale);
    ref.w_b = detail::gpsins_correct<S, SF>(w, bg, st.gyro_scale);
    ref.P = P0;
    ref.qc = detail::gpsins_Qc_diag<S, SF>(d.p, f.q_scale());
    // Without the scale-factor states k^2 |w|^2 I; with them k^2 C_nb diag(|w|^2 - w_i^2) C_nb^T.
    const S k2 = f.q_scale() * d.p.gyro_rate_noise * d.p.gyro_rate_noise, w2 = ref.w_b.squaredNorm();
    const Mat3<S> C = quat::to_rotmat(f.state().nav.q_nb);
    const Vec3<S> body = SF ? Vec3<S>(Vec3<S>::Constant(w2) - ref.w_b.cwiseAbs2()) : Vec3<S>::Constant(w2);
    ref.qa = C * (k2 * body).asDiagonal() * C.transpose();
    if (k % 2 == 0) {
      EXPECT_GT(ref.qa.norm(), S(0)) << "k " << k;
    }
    EXPECT_LE((max_rel<S, N>(f.covariance(), dense_update(ref))), tol) << "k " << k;
  }
}

TEST(GpsInsPropagate, FilterTimeUpdateDouble) { check_filter<double, false>(1e-12); }
TEST(GpsInsPropagate, FilterTimeUpdateFloat) { check_filter<float, false>(1e-5); }
TEST(GpsInsPropagate, ScaleFactorsFilterTimeUpdateDouble) { check_filter<double, true>(1e-12); }
TEST(GpsInsPropagate, ScaleFactorsFilterTimeUpdateFloat) { check_filter<float, true>(1e-5); }

}  // namespace
