// GpsInsFilter's smoother (nav/gps_ins/smoother.hpp, core/smoother.hpp) on a simulated run (the
// circle of nav_truth.hpp, noisy IMU with biases, 1 Hz GNSS with a 30 s outage): the smoothed
// position error inside the outage below the forward one, smoothed sigmas never above the
// forward ones, the last sample equal to the forward one, the forward decisions unchanged, the same
// bits whatever the checkpoint interval, no heap in the forward loop or the backward pass; the
// transition against finite differences of the time update; the batch loop against the step loop
// written out, with compass and altimeter samples between IMU samples. float and double.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/nav/gps_ins/smoother.hpp>
#include <random>
#include <vector>

#include "nav_truth.hpp"

using namespace quatnav;

namespace {

template <class S> struct GpsInsCase {
  static constexpr double kDt = 0.01;
  static constexpr double kOut0 = 100.0, kOut1 = 130.0;  // the GNSS outage (s)
  int n = 20001;                                         // 200 s at 100 Hz
  std::vector<double> t, truth_llh, gps_t, gps_llh;
  std::vector<S> gyro, accel, gps_vel, gps_ps, gps_vs;
  GpsInsFilter<S> filter;

  GpsInsCase() {
    std::mt19937 g(7);
    std::normal_distribution<double> nd;
    quatnav_test::NavTruth tr;
    const Vec3<double> ba(0.03, -0.02, 0.04), bg(3e-4, -2e-4, 2.5e-4);
    GpsInsParams<S> p;
    const double sw = double(p.gyro_noise) / std::sqrt(kDt), sa = double(p.acc_noise) / std::sqrt(kDt);
    filter = GpsInsFilter<S>(p);
    for (int k = 0; k < n; ++k) {
      const double tk = k * kDt;
      Vec3<double> w(0, 0, 0), f(0, 0, 0);
      if (k > 0) tr.step(tk, kDt, w, f);
      t.push_back(tk);
      for (int i = 0; i < 3; ++i) {
        gyro.push_back(S(w[i] + bg[i] + sw * nd(g)));
        accel.push_back(S(f[i] + ba[i] + sa * nd(g)));
      }
      truth_llh.insert(truth_llh.end(), {tr.lat, tr.lon, tr.h});
      if (k > 0 && k % 100 == 0 && !(tk > kOut0 && tk < kOut1)) {
        const earth::Radii<double> r = earth::radii<double>(tr.lat);
        const Vec3<double> v = tr.v(tk);
        gps_t.push_back(tk);
        gps_llh.insert(gps_llh.end(), {tr.lat + 1.0 * nd(g) / (r.R_M + tr.h),
                                       tr.lon + 1.0 * nd(g) / ((r.R_N + tr.h) * std::cos(tr.lat)), tr.h + 2.0 * nd(g)});
        for (int i = 0; i < 3; ++i) {
          gps_vel.push_back(S(v[i] + 0.05 * nd(g)));
          gps_ps.push_back(S(i < 2 ? 1.0 : 2.0));
          gps_vs.push_back(S(0.05));
        }
      }
    }
    // Start from a slightly wrong state at the true position.
    const Vec3<double> e0 = tr.att.euler(0.0);
    const Quat<S> q0 = quat::from_euler<S>(S(e0[0] + 0.01), S(e0[1] - 0.01), S(e0[2] + 0.05));
    const Vec3<double> v0 = tr.v(0.0);
    typename GpsInsFilter<S>::Mat16 P0 = filter.initial_covariance(Vec3<S>(2, 2, 3), S(0.5));
    P0(gpsins::kBo, gpsins::kBo) = S(1);
    EXPECT_EQ(filter.reset(q0, Vec3<S>(v0.template cast<S>()), truth_llh[0], truth_llh[1], truth_llh[2],
                           Vec3<S>::Zero(), Vec3<S>::Zero(), P0),
              Status::Ok);
  }

  struct Out {
    std::vector<double> llh;
    std::vector<S> v, q, ba, bg, sigma;
    std::vector<double> bo;
    std::vector<std::uint32_t> flags;
    std::vector<std::uint8_t> gps_status;
    explicit Out(int n, std::size_t ng)
        : llh(3 * n), v(3 * n), q(4 * n), ba(3 * n), bg(3 * n), sigma(16 * n), bo(n), flags(n), gps_status(2 * ng) {}
  };

  GpsInsBatchIo<S> io(Out& o) const {
    GpsInsBatchIo<S> b;
    b.t = t.data();
    b.gyro = gyro.data();
    b.accel = accel.data();
    b.n = std::size_t(n);
    b.gps_t = gps_t.data();
    b.gps_llh = gps_llh.data();
    b.gps_vel = gps_vel.data();
    b.gps_pos_sigma = gps_ps.data();
    b.gps_vel_sigma = gps_vs.data();
    b.ng = gps_t.size();
    b.llh = o.llh.data();
    b.v_n = o.v.data();
    b.q_nb = o.q.data();
    b.acc_bias = o.ba.data();
    b.gyro_bias = o.bg.data();
    b.sigma = o.sigma.data();
    b.baro_offset = o.bo.data();
    b.flags = o.flags.data();
    b.report.gps.status = o.gps_status.data();
    return b;
  }

  double pos_err(const Out& o, int k) const {
    const Vec3<double> d = earth::geodetic_diff<double>(o.llh[3 * k], o.llh[3 * k + 1], o.llh[3 * k + 2],
                                                        truth_llh[3 * k], truth_llh[3 * k + 1], truth_llh[3 * k + 2]);
    return std::sqrt(d[0] * d[0] + d[1] * d[1]);
  }
};

template <class S> class GpsInsSmootherTest : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(GpsInsSmootherTest, Scalars);

TYPED_TEST(GpsInsSmootherTest, SmoothedRunBeatsForwardInsideAnOutage) {
  using S = TypeParam;
  GpsInsCase<S> c;
  const std::size_t ng = c.gps_t.size();
  typename GpsInsCase<S>::Out fw(c.n, ng), sm(c.n, ng);

  GpsInsFilter<S> f0 = c.filter;
  gpsins_batch(f0, c.io(fw));  // forward alone

  GpsInsFilter<S> f1 = c.filter;
  GpsInsRtsModel<S> model(f1, c.t.data(), c.gyro.data(), c.accel.data(), false);
  RtsSmoother<GpsInsRtsModel<S>> rts(model);
  const GpsInsBatchIo<S> io = c.io(sm);
  ASSERT_TRUE(rts.reserve(std::size_t(c.n), gpsins_max_epochs(f1.params(), io), 256));
  Eigen::internal::set_is_malloc_allowed(false);
  gpsins_batch(f1, io, rts);  // forward, recorded: the same outputs
  EXPECT_EQ(sm.llh, fw.llh);
  EXPECT_EQ(sm.sigma, fw.sigma);
  EXPECT_EQ(sm.gps_status, fw.gps_status);  // the decisions of the forward pass
  const auto r = rts.smooth(GpsInsSmoothedOutput<S>{io});
  Eigen::internal::set_is_malloc_allowed(true);
  ASSERT_EQ(r, RtsSmoother<GpsInsRtsModel<S>>::Result::Ok);
  // Records: the GNSS epochs and the checkpoints, not every sample.
  EXPECT_LT(rts.records(), std::size_t(c.n) / 20);

  // The last sample: the forward estimate, bit for bit.
  const int L = c.n - 1;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(sm.llh[3 * L + i], fw.llh[3 * L + i]);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(sm.q[4 * L + i], fw.q[4 * L + i]);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(sm.sigma[16 * L + i], fw.sigma[16 * L + i]);

  // The pure-prediction stretches are recomputed bit for bit: a checkpoint at every sample (no
  // recomputation) gives the same smoothed run.
  {
    typename GpsInsCase<S>::Out s1(c.n, ng);
    GpsInsFilter<S> f2 = c.filter;
    GpsInsRtsModel<S> m2(f2, c.t.data(), c.gyro.data(), c.accel.data(), false);
    RtsSmoother<GpsInsRtsModel<S>> rts1(m2);
    const GpsInsBatchIo<S> io1 = c.io(s1);
    ASSERT_TRUE(rts1.reserve(std::size_t(c.n), gpsins_max_epochs(f2.params(), io1), 1));
    gpsins_batch(f2, io1, rts1);
    ASSERT_EQ(rts1.smooth(GpsInsSmoothedOutput<S>{io1}), RtsSmoother<GpsInsRtsModel<S>>::Result::Ok);
    EXPECT_GT(rts1.records(), std::size_t(c.n) - 2);
    EXPECT_EQ(s1.llh, sm.llh);
    EXPECT_EQ(s1.q, sm.q);
    EXPECT_EQ(s1.sigma, sm.sigma);
  }

  // Smoothed sigmas never above the forward ones (the recursion is in double; the float filter's
  // stored covariance rounds at 1e-7 of a variance).
  const double tol = std::is_same<S, float>::value ? 1e-4 : 1e-9;
  int above = 0;
  for (int k = 0; k < c.n; ++k)
    for (int i = 0; i < 16; ++i)
      if (double(sm.sigma[16 * k + i]) > double(fw.sigma[16 * k + i]) * (1.0 + tol) + 1e-12) ++above;
  EXPECT_EQ(above, 0);

  // Inside the outage: the worst smoothed horizontal error well below the forward drift.
  double worst_f = 0, worst_s = 0;
  for (int k = 0; k < c.n; ++k) {
    const double tk = c.t[k];
    if (tk > GpsInsCase<S>::kOut0 && tk < GpsInsCase<S>::kOut1) {
      worst_f = std::max(worst_f, c.pos_err(fw, k));
      worst_s = std::max(worst_s, c.pos_err(sm, k));
    }
  }
  std::printf("outage worst horizontal error: forward %.3f m, smoothed %.3f m\n", worst_f, worst_s);
  EXPECT_GT(worst_f, 2.0);  // the outage makes the forward filter drift
  EXPECT_LT(worst_s, 0.5 * worst_f);
}

TYPED_TEST(GpsInsSmootherTest, BatchIsTheStepLoop) {
  // gpsins_batch against the documented step loop written out (batch.hpp: per sample k >= 1 the
  // time update, the constraints, then the aids with times in (t[k-1], t[k]]: compass, altimeter,
  // GNSS), bit for bit at every sample. The compass and altimeter times fall between IMU samples,
  // so an aid applied one sample early or late changes the state from that sample on: a slip in
  // the batch loop's aid times fails here without the Python tests.
  using S = TypeParam;
  GpsInsCase<S> c;
  c.n = 6001;  // the first 60 s, with the filter's ZUPT, NHC, compass and altimeter all in play
  std::vector<double> gps_t;
  for (double tg : c.gps_t)
    if (tg <= c.t[c.n - 1]) gps_t.push_back(tg);
  std::vector<double> comp_t, baro_t, baro_h;
  std::vector<S> comp_yaw;
  std::mt19937 g(3);
  std::normal_distribution<double> nd;
  quatnav_test::NavTruth tr;
  for (double tc = 0.504; tc < c.t[c.n - 1]; tc += 1.0) {  // 4 ms after a sample
    comp_t.push_back(tc);
    comp_yaw.push_back(S(tr.att.euler(tc)[2] + 0.01 * nd(g)));
  }
  for (double tb = 0.253; tb < c.t[c.n - 1]; tb += 0.5) {
    const std::size_t k = std::size_t(std::lround(tb / GpsInsCase<S>::kDt));
    baro_t.push_back(tb);
    baro_h.push_back(c.truth_llh[3 * k + 2] + 0.3 * nd(g));
  }
  typename GpsInsCase<S>::Out o(c.n, gps_t.size());
  GpsInsBatchIo<S> io = c.io(o);
  io.n = std::size_t(c.n);
  io.ng = gps_t.size();
  io.compass_t = comp_t.data();
  io.compass_yaw = comp_yaw.data();
  io.nc = comp_t.size();
  io.baro_t = baro_t.data();
  io.baro_h = baro_h.data();
  io.nb = baro_t.size();
  std::vector<std::uint8_t> comp_status(comp_t.size());
  io.report.compass.status = comp_status.data();
  GpsInsFilter<S> fb = c.filter;
  gpsins_batch(fb, io);

  GpsInsFilter<S> f = c.filter;
  std::size_t ic = 0, ib = 0, ig = 0, comp_used = 0, baro_used = 0, gps_used = 0;
  for (int k = 0; k < c.n; ++k) {
    if (k > 0) {
      const S dt = S(c.t[k] - c.t[k - 1]);
      ASSERT_EQ(f.predict(Vec3<S>(Eigen::Map<const Vec3<S>>(&c.gyro[3 * k])),
                          Vec3<S>(Eigen::Map<const Vec3<S>>(&c.accel[3 * k])), dt),
                Status::Ok);
      f.update_constraints();
      const double tk = c.t[k];
      for (; ic < comp_t.size() && comp_t[ic] <= tk; ++ic) {
        const auto r = f.update_compass(comp_yaw[ic]);
        comp_used += r.status == Status::Ok;
        ASSERT_EQ(comp_status[ic], std::uint8_t(r.status)) << "compass " << ic;
      }
      for (; ib < baro_t.size() && baro_t[ib] <= tk; ++ib) baro_used += f.update_baro(baro_h[ib]).height.status == Status::Ok;
      for (; ig < gps_t.size() && gps_t[ig] <= tk; ++ig) {
        const double* llh = &c.gps_llh[3 * ig];
        const auto r = f.update_gps(llh[0], llh[1], llh[2], Vec3<S>(Eigen::Map<const Vec3<S>>(&c.gps_vel[3 * ig])),
                                    Vec3<S>(Eigen::Map<const Vec3<S>>(&c.gps_ps[3 * ig])),
                                    Vec3<S>(Eigen::Map<const Vec3<S>>(&c.gps_vs[3 * ig])), S(tk - gps_t[ig]),
                                    GnssSolution::Unknown);
        gps_used += r.pos.status == Status::Ok;
      }
    }
    ASSERT_TRUE(f.navigating());
    const Vec3<double> l = f.llh();
    for (int i = 0; i < 3; ++i) ASSERT_EQ(o.llh[3 * k + i], l[i]) << "sample " << k;
    ASSERT_EQ(Vec4<S>(Eigen::Map<const Vec4<S>>(&o.q[4 * k])), Vec4<S>(f.q_nb())) << "sample " << k;
  }
  // Every aid took part (a loop that skipped one would pass the comparison above trivially).
  EXPECT_GT(comp_used, comp_t.size() / 2);
  EXPECT_GT(baro_used, baro_t.size() / 2);
  EXPECT_GT(gps_used, gps_t.size() / 2);
}

TYPED_TEST(GpsInsSmootherTest, TransitionIsTheTimeUpdates) {
  // The smoother's Phi against central finite differences of the filter's own time update in its
  // error chart: a sample of one step (its Phi taken at the posterior alone) and a coasted sample
  // of two steps (the product of the steps' Phi).
  using S = TypeParam;
  if (!std::is_same<S, double>::value) GTEST_SKIP() << "finite differences in double";
  for (const double step : {0.005, 0.02}) {  // max_dt 0.01: one step, then coasted in two
    SCOPED_TRACE(step);
    GpsInsCase<double> c;
    GpsInsFilter<double> f = c.filter;
    GpsInsParams<double> p = f.params();
    p.max_dt = 0.01;
    f.set_params(p);
    std::vector<double> t = {0.0, step};
    const std::vector<double> gyro = {0, 0, 0, 0.01, -0.02, 0.03}, accel = {0, 0, 0, 0.3, -0.2, -9.7};
    GpsInsRtsModel<double> m(f, t.data(), gyro.data(), accel.data(), false);
    typename GpsInsRtsModel<double>::Record x0{}, x1{}, xp{}, xm{};
    ASSERT_TRUE(m.capture(f, x0));
    ASSERT_EQ(m.predict(1, x0, x1), RtsLink::Predict);
    Mat<double, 16, 16> Phi;
    ASSERT_EQ(m.transition(1, x0, x1, Phi), RtsLink::Predict);
    EXPECT_GT((Phi - Mat<double, 16, 16>::Identity()).cwiseAbs().maxCoeff(), 1e-3);  // the step moved it
    const Mat<double, 16, 16> P0 = m.error_covariance(x0);
    for (int j = 0; j < 16; ++j) {
      const double h = 1e-3;  // the position is kept in radians: smaller steps drown in its rounding
      Vec<double, 16> e = Vec<double, 16>::Zero();
      e[j] = h;
      typename GpsInsRtsModel<double>::Record a{}, b{};
      m.retract(x0, e, P0, a);
      m.retract(x0, Vec<double, 16>(-e), P0, b);
      ASSERT_EQ(m.predict(1, a, xp), RtsLink::Predict);
      ASSERT_EQ(m.predict(1, b, xm), RtsLink::Predict);
      const Vec<double, 16> col = (m.local(xm, x1) - m.local(xp, x1)) / (2 * h);
      // retract(x0, e) has the error -e against x0; local(x, x1) is the error of x against x1.
      for (int i = 0; i < 16; ++i)
        EXPECT_NEAR(col[i], Phi(i, j), 1e-4 * (1.0 + std::abs(Phi(i, j)))) << i << "," << j;
    }
  }
}

}  // namespace
