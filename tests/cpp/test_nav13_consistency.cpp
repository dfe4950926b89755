// NavFilter13 consistency while the body rotates: Monte Carlo NEES of attitude and velocity on a
// short run with a rotating attitude, within two-sided 99% chi-square bounds.
//
// The IMU is what a real one delivers: the mean body rate and specific force over each step (here
// the exact values at the middle of the step, in the Earth model of earth.hpp), plus constant
// biases and white noise of the densities the filter is told. Without the rotation correction of
// the velocity increment (nav_filter13.hpp, eq. 12) the Euler step applies that mean specific force
// with the attitude at the start of the step, an error of dt^2/2 C (w x a) per step that does not
// average out while the body rotates: the mean NEES was about 8 (attitude) and 6-7 (velocity) on
// the long run (bench/long_run.cpp) and above the upper bound here.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <quatnav/nav/nav_filter13.hpp>

#include "nav_truth.hpp"

using namespace quatnav;
using quatnav_test::NavTruth;

namespace {

constexpr int kRuns = 8;
constexpr double kDt = 0.01, kT = 150.0;
// Two-sided 99% bounds of the mean of kRuns NEES of 3 dof: chi2.ppf([0.005, 0.995], 3 * 8) / 8.
constexpr double kLo = 9.8862335 / kRuns, kHi = 45.5585119 / kRuns;

/// ANEES (mean over kRuns runs) of attitude and velocity at each whole second from 50 s to kT.
template <TimeUpdate TU> void anees(std::vector<double>& att, std::vector<double>& vel) {
  const double sg = 1e-4, sa = 1e-3;  // densities [rad/s/sqrt(Hz)], [m/s^2/sqrt(Hz)], as the filter is told
  const int steps = int(kT / kDt + 0.5), every = int(1.0 / kDt + 0.5), first = int(50.0 / kDt + 0.5);
  const int n_checks = (steps - first) / every + 1;
  att.assign(n_checks, 0.0);
  vel.assign(n_checks, 0.0);
  for (int run = 0; run < kRuns; ++run) {
    std::mt19937_64 rng(1000 + run);
    std::normal_distribution<double> N(0.0, 1.0);
    auto n3 = [&] { return Vec3<double>(N(rng), N(rng), N(rng)); };
    NavFilter13Params<double> p;
    p.acc_noise = sa;
    p.gyro_noise = sg;
    p.acc_bias_noise = 1e-5;
    p.gyro_bias_noise = 1e-6;
    p.gps_vel_sigma = 0.03;
    p.yaw_sigma = 0.035;
    NavFilter13<double, TU> f(p);
    // Initial errors drawn from the initial covariance (attitude 0.03 rad, velocity 0.1 m/s,
    // biases 0.05 m/s^2 and 1e-3 rad/s per axis); the true biases are constant.
    const Vec3<double> b_a = 0.05 * n3(), b_g = 1e-3 * n3();
    Mat<double, 12, 12> Pe = Mat<double, 12, 12>::Zero();
    Pe.diagonal() << Vec3<double>::Constant(0.01), Vec3<double>::Constant(9e-4), Vec3<double>::Constant(2.5e-3),
        Vec3<double>::Constant(1e-6);
    NavTruth tr;  // the vehicle of bench/long_run.cpp
    const Quat<double> q0 = quat::mul(quat::from_euler(tr.att.euler(0.0)), quat::from_rotvec(Vec3<double>(0.03 * n3())));
    const Mat<double, 13, 12> Tb = detail::nav13_from_error(q0);
    const Mat<double, 13, 13> P0 = Tb * Pe * Tb.transpose();
    ASSERT_EQ(f.reset(Vec3<double>(tr.v(0.0) + 0.1 * n3()), q0, Vec3<double>::Zero(), Vec3<double>::Zero(),
                      Mat<double, 13, 13>((P0 + P0.transpose()) * 0.5), tr.lat, tr.lon, tr.h),
              Status::Ok);
    for (int k = 1; k <= steps; ++k) {
      const double t = k * kDt;
      Vec3<double> w, a;
      tr.step(t, kDt, w, a);
      w += b_g + (sg / std::sqrt(kDt)) * n3();
      a += b_a + (sa / std::sqrt(kDt)) * n3();
      ASSERT_EQ(f.predict(w, a, kDt), Status::Ok);
      if (k % 10 == 0) {
        const double yaw = quat::wrap_pi(tr.att.euler(t)[2] + 0.035 * N(rng));
        ASSERT_EQ(f.update_velocity_yaw(Vec3<double>(tr.v(t) + 0.03 * n3()), yaw).status, Status::Ok);
      }
      if (k >= first && (k - first) % every == 5) {  // between the 10 Hz aids
        const int i = (k - first) / every;
        const Quat<double> qt = quat::from_euler(tr.att.euler(t));
        const Vec3<double> dth = quat::to_rotvec(quat::mul(quat::conj(f.state().q_nb), qt));
        const Vec3<double> dv = f.state().v_n - tr.v(t);
        const Mat<double, 12, 12> E = f.error_covariance();
        att[i] += dth.dot(E.block<3, 3>(3, 3).ldlt().solve(dth)) / kRuns;
        vel[i] += dv.dot(E.block<3, 3>(0, 0).ldlt().solve(dv)) / kRuns;
      }
    }
  }
}

template <TimeUpdate TU> void expect_consistent() {
  std::vector<double> att, vel;
  anees<TU>(att, vel);
  int att_in = 0, vel_in = 0;
  double att_mean = 0, vel_mean = 0;
  for (std::size_t i = 0; i < att.size(); ++i) {
    att_in += att[i] > kLo && att[i] < kHi;
    vel_in += vel[i] > kLo && vel[i] < kHi;
    att_mean += att[i] / double(att.size());
    vel_mean += vel[i] / double(att.size());
  }
  const double n = double(att.size());
  // 99% bounds at each checked time: nearly every time inside, and the time average near 3.
  EXPECT_GE(att_in / n, 0.9) << "attitude ANEES mean " << att_mean;
  EXPECT_GE(vel_in / n, 0.9) << "velocity ANEES mean " << vel_mean;
  EXPECT_GT(att_mean, 1.5);
  EXPECT_LT(att_mean, 4.5);
  EXPECT_GT(vel_mean, 1.5);
  EXPECT_LT(vel_mean, 4.5);
  std::printf("ANEES (3 dof, %d runs, 50-%.0f s): attitude mean %.2f (%.0f%% of times inside [%.2f, %.2f]), "
              "velocity mean %.2f (%.0f%%)\n",
              kRuns, kT, att_mean, 100 * att_in / n, kLo, kHi, vel_mean, 100 * vel_in / n);
}

}  // namespace

TEST(Nav13Consistency, EkfNeesWithinBoundsWhileRotating) { expect_consistent<TimeUpdate::Ekf>(); }
TEST(Nav13Consistency, UkfNeesWithinBoundsWhileRotating) { expect_consistent<TimeUpdate::Ukf>(); }
