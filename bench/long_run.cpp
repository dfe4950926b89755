// Long-run benchmark: N steps (default 10 million) of each filter in float32 and float64 on
// simulated data, checking after every step that the covariance is symmetric and positive
// definite and that the quaternion keeps unit norm, and reporting:
//   * max | |q| - 1 |,
//   * covariance health of the error state [dtheta, db]: exact asymmetry (max |P - P^T|),
//     steps where its Cholesky factor does not exist (not PD), smallest and largest
//     eigenvalue (eigenvalues every `eig_every` steps),
//   * attitude error against the truth: RMS and max over the second half, max in the last 10%,
//     and the mean attitude NEES (3 dof; 3 is consistent),
//   * statuses other than Ok, and the wall time per step.
// Build and run: bash bench/long_run.sh [steps]   (or see that script for the compiler line)
//
// Simulated data (100 Hz): a smooth attitude trajectory given by ZYX Euler angles
//   roll = 0.5 sin(0.31 t), pitch = 0.4 sin(0.23 t + 1), yaw = 1.5 sin(0.013 t) + 0.6 sin(0.11 t),
// the gyro = body rate at the middle of each step + constant bias + white noise, the
// accelerometer = C_bn [0, 0, -g] + white noise (no linear acceleration), the magnetometer =
// C_bn m_n + white noise, all generated in double. Pitch stays within +-0.4 rad, so the Euler
// filter never approaches its singularity.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include <quatnav/quatnav.hpp>

using namespace quatnav;

namespace {

struct Truth {
  double t = 0;
  Vec3<double> euler(double tt) const {
    return Vec3<double>(0.5 * std::sin(0.31 * tt), 0.4 * std::sin(0.23 * tt + 1.0),
                        1.5 * std::sin(0.013 * tt) + 0.6 * std::sin(0.11 * tt));
  }
  Vec3<double> euler_rate(double tt) const {
    return Vec3<double>(0.5 * 0.31 * std::cos(0.31 * tt), 0.4 * 0.23 * std::cos(0.23 * tt + 1.0),
                        1.5 * 0.013 * std::cos(0.013 * tt) + 0.6 * 0.11 * std::cos(0.11 * tt));
  }
  /// Body rate omega_nb_b from ZYX Euler angles and their rates.
  Vec3<double> body_rate(double tt) const {
    const Vec3<double> e = euler(tt), d = euler_rate(tt);
    const double sr = std::sin(e[0]), cr = std::cos(e[0]), sp = std::sin(e[1]), cp = std::cos(e[1]);
    return Vec3<double>(d[0] - d[2] * sp, d[1] * cr + d[2] * sr * cp, -d[1] * sr + d[2] * cr * cp);
  }
};

struct Stats {
  double max_norm_dev = 0, max_asym = 0, min_eig = 1e300, max_eig = 0;
  long not_pd = 0, not_ok = 0, nonfinite = 0;
  double sq_err = 0, max_err_half = 0, max_err_tail = 0, nees_sum = 0;
  long n_half = 0;
  double ns_per_step = 0;
};

template <class S> Mat<S, 6, 6> error_cov(const QuaternionEKF<S>& f) {
  Mat<S, 6, 7> T = Mat<S, 6, 7>::Zero();
  T.template topLeftCorner<3, 4>() = S(2) * quat::xi(f.quat()).transpose();
  T.template bottomRightCorner<3, 3>().setIdentity();
  return T * f.covariance() * T.transpose();
}
template <class S> Mat<S, 6, 6> error_cov(const EulerEKF<S>& f) { return f.covariance(); }

/// Attitude covariance as the error state's 3x3 block in the body rotation-vector sense.
template <class F> Mat3<double> att_cov(const F& f) { return f.attitude_covariance().template cast<double>(); }

template <class F> Stats run(long steps, long eig_every, unsigned seed) {
  using S = typename F::Scalar;
  const double dt = 0.01, g = 9.81;
  const double sg = 0.005, sa = 0.02, sm = 0.02;  // gyro density [rad/s/sqrt(Hz)]; acc, mag std [normalized]
  const Vec3<double> bias(0.01, -0.02, 0.005), m_n(0.5, 0.0, 0.866);
  typename F::Params p;
  p.gyro_noise = S(sg);
  p.acc_noise = S(0.03);
  p.mag_noise = S(0.03);
  F f(p);
  f.set_mag_dip(S(std::atan2(m_n[2], m_n[0])));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  Truth tr;
  auto meas = [&](double tt, Vec3<S>& acc, Vec3<S>& mag) {
    const Quat<double> q = quat::from_euler(tr.euler(tt));
    const Vec3<double> a = quat::rotate_inv(q, Vec3<double>(0, 0, -g)) + g * sa * Vec3<double>(N(rng), N(rng), N(rng));
    const Vec3<double> m = quat::rotate_inv(q, m_n) + sm * Vec3<double>(N(rng), N(rng), N(rng));
    acc = a.cast<S>();
    mag = m.cast<S>();
  };
  Vec3<S> acc, mag;
  meas(0.0, acc, mag);
  if (f.initialize(acc, mag) != Status::Ok) std::abort();
  Stats st;
  const double gn = sg / std::sqrt(dt);
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 1; k <= steps; ++k) {
    const double t = k * dt;
    const Vec3<double> w = tr.body_rate(t - 0.5 * dt) + bias + gn * Vec3<double>(N(rng), N(rng), N(rng));
    meas(t, acc, mag);
    if (f.predict(w.cast<S>(), S(dt)) != Status::Ok) ++st.not_ok;
    if (f.update_acc(acc).status != Status::Ok) ++st.not_ok;
    if (f.update_mag(mag).status != Status::Ok) ++st.not_ok;
    // Health after every step.
    const Quat<S> q = f.quat();
    if (!q.allFinite() || !f.covariance().allFinite()) {
      ++st.nonfinite;
      continue;
    }
    st.max_norm_dev = std::max(st.max_norm_dev, std::abs(double(q.norm()) - 1.0));
    const auto& P = f.covariance();
    st.max_asym = std::max(st.max_asym, double((P - P.transpose()).cwiseAbs().maxCoeff()));
    const Mat<S, 6, 6> Pe = error_cov(f);
    if (Eigen::LLT<Mat<S, 6, 6>>(Pe).info() != Eigen::Success) ++st.not_pd;
    if (k % eig_every == 0) {
      const auto h = covariance_health<S, 6>(Mat<S, 6, 6>((Pe + Pe.transpose()) * S(0.5)));
      st.min_eig = std::min(st.min_eig, double(h.min_eig));
      st.max_eig = std::max(st.max_eig, double(h.max_eig));
    }
    if (k > steps / 2) {
      const Quat<double> qt = quat::from_euler(tr.euler(t));
      const Quat<double> qe = q.template cast<double>();
      // Body-frame rotation vector of the error: q_true = q * exp(dtheta).
      const Vec3<double> dth = quat::to_rotvec(quat::mul(quat::conj(qe), qt));
      const double err = dth.norm();
      st.sq_err += err * err;
      st.max_err_half = std::max(st.max_err_half, err);
      if (k > steps - steps / 10) st.max_err_tail = std::max(st.max_err_tail, err);
      if (k % 10 == 0) {
        st.nees_sum += dth.dot(att_cov(f).ldlt().solve(dth));
        ++st.n_half;
      }
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  st.ns_per_step = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(steps);
  return st;
}

template <class F> void report(const char* name, long steps, long eig_every) {
  const Stats s = run<F>(steps, eig_every, 42);
  const long n2 = steps - steps / 2;
  std::printf("%-14s %-7s steps=%ld  max||q|-1|=%.2e  P: max asym=%.1e not-PD steps=%ld eig=[%.2e, %.2e]  "
              "att err (2nd half): rms=%.3f mrad max=%.3f mrad, last 10%% max=%.3f mrad  mean NEES=%.2f  "
              "not-ok=%ld non-finite=%ld  %.0f ns/step (incl. checks and simulation)\n",
              name, sizeof(typename F::Scalar) == 4 ? "float32" : "float64", steps, s.max_norm_dev, s.max_asym,
              s.not_pd, s.min_eig, s.max_eig, 1e3 * std::sqrt(s.sq_err / double(n2)), 1e3 * s.max_err_half,
              1e3 * s.max_err_tail, s.n_half ? s.nees_sum / double(s.n_half) : 0.0, s.not_ok, s.nonfinite,
              s.ns_per_step);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const long steps = argc > 1 ? std::atol(argv[1]) : 10000000L;
  const std::string only = argc > 2 ? argv[2] : "";
  const long eig_every = 100;
  std::printf("quatnav long run: %ld steps of 0.01 s per filter and precision; eigenvalues every %ld steps\n", steps,
              eig_every);
  if (only.empty() || only == "QuaternionEKF") {
    report<QuaternionEKF<double>>("QuaternionEKF", steps, eig_every);
    report<QuaternionEKF<float>>("QuaternionEKF", steps, eig_every);
  }
  if (only.empty() || only == "EulerEKF") {
    report<EulerEKF<double>>("EulerEKF", steps, eig_every);
    report<EulerEKF<float>>("EulerEKF", steps, eig_every);
  }
  return 0;
}
