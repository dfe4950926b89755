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
//
// Navigation filters (NavFilter13 with each time update, GpsInsFilter), same attitude trajectory,
// Earth rotation on: the vehicle drives a circle of radius 1000 m at 10 m/s (v_N = 10 cos(0.01 t),
// v_E = 10 sin(0.01 t)) with v_D = 0.5 sin(0.05 t), starting at lat 0.6 rad, h 100 m; the true
// position is integrated in double. The IMU (100 Hz) is the exact body rate and specific force at
// the middle of each step in the Earth model of earth.hpp,
//   omega_ib_b = omega_nb_b + C_bn (omega_ie_n + omega_en_n),
//   f_ib_b     = C_bn (v_dot + (2 omega_ie_n + omega_en_n) x v - g_n),
// plus constant biases and white noise. Aids: NavFilter13 a velocity + yaw measurement at 10 Hz
// and a GPS position (set_position, 2.5 m / 5 m noise) at 1 Hz; GpsInsFilter GPS position and
// velocity at 5 Hz, altimeter and compass at 10 Hz. Errors against the truth: attitude (rotation
// vector), velocity and position (NED metres); the covariance health is that of each filter's
// error-state covariance (NavFilter13: the 12x12 [dv, dtheta, db_a, db_g]; GpsInsFilter: its 15x15 P).
// Usage: long_run [steps] [filter] [float32|float64] [no-baro]; filter one of QuaternionEKFPaper, EulerEKF,
// NavFilter13-ekf, NavFilter13-second_order, NavFilter13-ukf, GpsInsFilter (default: all);
// no-baro leaves out GpsInsFilter's altimeter updates (an experiment: its offset error enters R as
// white noise, see gps_ins.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include <quatnav/quatnav.hpp>

#include "../tests/cpp/nav_truth.hpp"

using namespace quatnav;
using quatnav_test::NavTruth;
using quatnav_test::Truth;

namespace {

bool g_no_baro = false;  ///< no altimeter updates for GpsInsFilter (argument "no-baro")

struct Stats {
  double max_norm_dev = 0, max_asym = 0, min_eig = 1e300, max_eig = 0;
  long not_pd = 0, not_ok = 0, nonfinite = 0;
  double sq_err = 0, max_err_half = 0, max_err_tail = 0, nees_sum = 0;
  long n_half = 0;
  double ns_per_step = 0;
};

template <class S> Mat<S, 6, 6> error_cov(const QuaternionEKFPaper<S>& f) {
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
  p.acc_sigma = S(0.03);
  p.mag_sigma = S(0.03);
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

// --- navigation filters ------------------------------------------------------------------------


/// Counts of statuses per operation kind (predict, then the aids).
struct StatusCounts {
  static constexpr int kKinds = 6, kStatuses = 16;
  long n[kKinds][kStatuses] = {};
  void add(int kind, Status s) { ++n[kind][int(s) % kStatuses]; }
  std::string str(const char* const* names) const {
    std::string o;
    for (int k = 0; k < kKinds; ++k) {
      if (!names[k]) continue;
      std::string part;
      for (int s = 0; s < kStatuses; ++s)
        if (n[k][s] > 0) part += (part.empty() ? "" : ",") + std::string(to_string(Status(s))) + "=" + std::to_string(n[k][s]);
      if (!part.empty()) o += std::string(o.empty() ? "" : " ") + names[k] + "{" + part + "}";
    }
    return o;
  }
};

struct NavStats {
  double max_norm_dev = 0, max_asym = 0, min_eig = 1e300, max_eig = 0;
  long not_pd = 0, nonfinite = 0;
  double sq_att = 0, sq_vel = 0, sq_pos = 0, max_att = 0, max_vel = 0, max_pos = 0;
  double fin_att = 0, fin_vel = 0, fin_pos = 0;
  double nees_att = 0, nees_vel = 0;
  long n_half = 0, n_nees = 0;
  StatusCounts counts;
  const char* names[StatusCounts::kKinds] = {};
  double ns_per_step = 0;
};

/// NED error (m) of an estimated position against the true one.
inline Vec3<double> ned_error(double lat, double lon, double h, const NavTruth& tr) {
  const earth::Radii<double> r = earth::radii(tr.lat);
  return Vec3<double>((lat - tr.lat) * (r.R_M + tr.h), (lon - tr.lon) * (r.R_N + tr.h) * std::cos(tr.lat),
                      -(h - tr.h));
}

/// What each navigation filter needs from the driver: construction, start, one step of
/// measurements, and its estimates in a common form.
template <class F> struct NavAdapter;

template <class S, TimeUpdate TU> struct NavAdapter<NavFilter13<S, TU>> {
  using F = NavFilter13<S, TU>;
  static constexpr int kErr = 12;
  static F make(double sg, double sa) {
    NavFilter13Params<S> p;
    p.acc_noise = S(sa);
    p.gyro_noise = S(sg);
    p.acc_bias_noise = S(1e-5);
    p.gyro_bias_noise = S(1e-6);
    p.gps_vel_sigma = S(0.03);
    p.yaw_sigma = S(0.035);
    p.cov_floor = sizeof(S) == 4 ? S(1e-9) : S(1e-12);
    return F(p);
  }
  static void names(const char** n) { n[0] = "predict"; n[1] = "vel+yaw"; n[2] = "set_position"; }
  static void start(F& f, const Quat<double>& q, const Vec3<double>& v, const NavTruth& tr) {
    Mat<S, 12, 12> Pe = Mat<S, 12, 12>::Zero();
    Pe.diagonal() << Vec3<S>::Constant(S(0.01)), Vec3<S>::Constant(S(9e-4)), Vec3<S>::Constant(S(2.5e-3)),
        Vec3<S>::Constant(S(1e-6));
    const Quat<S> qs = q.cast<S>();
    const Mat<S, 13, 12> Tb = detail::nav13_from_error(qs);
    const Mat<S, 13, 13> P = fixed_mul(fixed_mul(Tb, Pe), Tb.transpose());
    if (f.reset(v.cast<S>(), qs, Vec3<S>::Zero(), Vec3<S>::Zero(), Mat<S, 13, 13>((P + P.transpose()) * S(0.5)),
                S(tr.lat), S(tr.lon), S(tr.h)) != Status::Ok)
      std::abort();
  }
  static Status predict(F& f, const Vec3<double>& w, const Vec3<double>& a, double dt) {
    return f.predict(w.cast<S>(), a.cast<S>(), S(dt));
  }
  /// Aids at step k (100 Hz): velocity + yaw at 10 Hz, GPS position at 1 Hz.
  template <class Rng, class Dist>
  static void aid(F& f, long k, const NavTruth& tr, double t, StatusCounts& c, Rng& rng, Dist& N) {
    if (k % 10 == 0) {
      const Vec3<double> vm = tr.v(t) + 0.03 * Vec3<double>(N(rng), N(rng), N(rng));
      const double yaw = quat::wrap_pi(tr.att.euler(t)[2] + 0.035 * N(rng));
      c.add(1, f.update_velocity_yaw(vm.cast<S>(), S(yaw)).status);
    }
    if (k % 100 == 0) {
      const earth::Radii<double> r = earth::radii(tr.lat);
      c.add(2, f.set_position(S(tr.lat + 2.5 * N(rng) / (r.R_M + tr.h)),
                              S(tr.lon + 2.5 * N(rng) / ((r.R_N + tr.h) * std::cos(tr.lat))), S(tr.h + 5.0 * N(rng))));
    }
  }
  static Quat<double> q(const F& f) { return f.state().q_nb.template cast<double>(); }
  static Vec3<double> v(const F& f) { return f.state().v_n.template cast<double>(); }
  static Vec3<double> pos_err(const F& f, const NavTruth& tr) {
    return ned_error(double(f.state().lat), double(f.state().lon), double(f.state().h), tr);
  }
  static bool finite(const F& f) { return f.x().allFinite() && f.covariance().allFinite(); }
  static double asym(const F& f) { return double((f.covariance() - f.covariance().transpose()).cwiseAbs().maxCoeff()); }
  static Mat<S, 12, 12> err_cov(const F& f) { return f.error_covariance(); }
  /// Attitude error for NEES: body-frame rotation vector (q_true = q * exp(dtheta)), its covariance.
  static Vec3<double> att_err(const F& f, const Quat<double>& qt) { return quat::to_rotvec(quat::mul(quat::conj(q(f)), qt)); }
  static Mat3<double> att_cov(const F& f) { return f.error_covariance().template block<3, 3>(3, 3).template cast<double>(); }
  static Mat3<double> vel_cov(const F& f) { return f.covariance().template block<3, 3>(0, 0).template cast<double>(); }
};

template <class S> struct NavAdapter<GpsInsFilter<S>> {
  using F = GpsInsFilter<S>;
  static constexpr int kErr = F::kStates;
  static F make(double sg, double sa) {
    GpsInsParams<S> p;
    p.gyro_noise = S(sg);
    p.acc_noise = S(sa);
    p.gyro_bias_noise = S(1e-6);
    p.acc_bias_noise = S(1e-5);
    p.gps_pos_sigma_h = S(2.5);
    p.gps_pos_sigma_v = S(5.0);
    p.gps_vel_sigma = S(0.1);
    p.baro_sigma = S(0.5);
    p.compass_sigma = S(0.035);
    p.cov_floor = sizeof(S) == 4 ? S(1e-9) : S(1e-12);
    return F(p);
  }
  static void names(const char** n) {
    n[0] = "predict"; n[1] = "gps_pos"; n[2] = "gps_vel"; n[3] = "baro_h"; n[4] = "baro_vd"; n[5] = "compass";
  }
  static void start(F& f, const Quat<double>& q, const Vec3<double>& v, const NavTruth& tr) {
    if (f.reset(q.cast<S>(), v.cast<S>(), tr.lat, tr.lon, tr.h, Vec3<S>::Zero(), Vec3<S>::Zero(),
                     f.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5))) != Status::Ok)
      std::abort();
  }
  static Status predict(F& f, const Vec3<double>& w, const Vec3<double>& a, double dt) {
    return f.predict(w.cast<S>(), a.cast<S>(), S(dt));
  }
  /// Aids at step k (100 Hz): GPS position + velocity at 5 Hz, altimeter and compass at 10 Hz.
  template <class Rng, class Dist>
  static void aid(F& f, long k, const NavTruth& tr, double t, StatusCounts& c, Rng& rng, Dist& N) {
    const S nan = std::numeric_limits<S>::quiet_NaN();
    if (k % 10 == 0) {
      c.add(5, f.update_compass(S(quat::wrap_pi(tr.att.euler(t)[2] + 0.035 * N(rng)))).status);
      if (!g_no_baro) {
        const BaroResult<S> b = f.update_baro(tr.h + 0.5 * N(rng));
        c.add(3, b.height.status);
        if (b.vd.status != Status::NotInitialized) c.add(4, b.vd.status);
      }
    }
    if (k % 20 == 0) {
      const earth::Radii<double> r = earth::radii(tr.lat);
      const Vec3<double> vm = tr.v(t) + 0.1 * Vec3<double>(N(rng), N(rng), N(rng));
      const GpsResult<S> g = f.update_gps(tr.lat + 2.5 * N(rng) / (r.R_M + tr.h),
                                          tr.lon + 2.5 * N(rng) / ((r.R_N + tr.h) * std::cos(tr.lat)),
                                          tr.h + 5.0 * N(rng), vm.cast<S>(), Vec3<S>::Constant(nan), Vec3<S>::Constant(nan));
      c.add(1, g.pos.status);
      c.add(2, g.vel.status);
    }
  }
  static Quat<double> q(const F& f) { return f.q_nb().template cast<double>(); }
  static Vec3<double> v(const F& f) { return f.v_n().template cast<double>(); }
  static Vec3<double> pos_err(const F& f, const NavTruth& tr) {
    const Vec3<double> l = f.llh();
    return ned_error(l[0], l[1], l[2], tr);
  }
  static bool finite(const F& f) {
    return f.q_nb().allFinite() && f.v_n().allFinite() && f.llh().allFinite() && f.covariance().allFinite();
  }
  static double asym(const F& f) { return double((f.covariance() - f.covariance().transpose()).cwiseAbs().maxCoeff()); }
  static Mat<S, kErr, kErr> err_cov(const F& f) { return f.covariance(); }
  /// Attitude error psi (nav frame: C_est = (I + [psi x]) C_true), estimate minus truth.
  static Vec3<double> att_err(const F& f, const Quat<double>& qt) { return quat::to_rotvec(quat::mul(q(f), quat::conj(qt))); }
  static Mat3<double> att_cov(const F& f) { return f.covariance().template block<3, 3>(6, 6).template cast<double>(); }
  static Mat3<double> vel_cov(const F& f) { return f.covariance().template block<3, 3>(3, 3).template cast<double>(); }
};

template <class F> NavStats nav_run(long steps, long eig_every, unsigned seed) {
  using A = NavAdapter<F>;
  using S = typename F::Scalar;
  constexpr int E = A::kErr;
  const double dt = 0.01;
  const double sg = 1e-4, sa = 1e-3;  // gyro [rad/s/sqrt(Hz)], accelerometer [m/s^2/sqrt(Hz)] densities
  const Vec3<double> b_g(1e-4, -2e-4, 5e-5), b_a(0.02, -0.01, 0.03);
  F f = A::make(sg, sa);
  NavStats st;
  A::names(st.names);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  NavTruth tr;
  const Quat<double> q0 = quat::mul(quat::from_euler(tr.att.euler(0.0)), quat::from_rotvec(Vec3<double>(0.01, -0.01, 0.02)));
  A::start(f, q0, tr.v(0.0) + Vec3<double>(0.1, -0.1, 0.05), tr);
  const double gn = sg / std::sqrt(dt), an = sa / std::sqrt(dt);
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 1; k <= steps; ++k) {
    const double t = k * dt;
    Vec3<double> w, a;
    tr.step(t, dt, w, a);
    w += b_g + gn * Vec3<double>(N(rng), N(rng), N(rng));
    a += b_a + an * Vec3<double>(N(rng), N(rng), N(rng));
    st.counts.add(0, A::predict(f, w, a, dt));
    A::aid(f, k, tr, t, st.counts, rng, N);
    if (!A::finite(f)) {
      ++st.nonfinite;
      continue;
    }
    st.max_norm_dev = std::max(st.max_norm_dev, std::abs(A::q(f).norm() - 1.0));
    st.max_asym = std::max(st.max_asym, A::asym(f));
    const Mat<S, E, E> Pe = A::err_cov(f);
    const Mat<S, E, E> Pes = (Pe + Pe.transpose()) * S(0.5);
    if (!detail::has_cholesky<S, E>(Pes)) ++st.not_pd;
    if (k % eig_every == 0) {
      const auto hh = covariance_health<double, E>(Mat<double, E, E>(Pes.template cast<double>()));
      st.min_eig = std::min(st.min_eig, hh.min_eig);
      st.max_eig = std::max(st.max_eig, hh.max_eig);
    }
    const Quat<double> qt = quat::from_euler(tr.att.euler(t));
    const Vec3<double> de = A::att_err(f, qt), dv = A::v(f) - tr.v(t), dp = A::pos_err(f, tr);
    if (k > steps / 2) {
      st.sq_att += de.squaredNorm();
      st.sq_vel += dv.squaredNorm();
      st.sq_pos += dp.squaredNorm();
      st.max_att = std::max(st.max_att, de.norm());
      st.max_vel = std::max(st.max_vel, dv.norm());
      st.max_pos = std::max(st.max_pos, dp.norm());
      ++st.n_half;
      if (k % 10 == 5) {  // between the 10 Hz aids
        st.nees_att += de.dot(A::att_cov(f).ldlt().solve(de));
        st.nees_vel += dv.dot(A::vel_cov(f).ldlt().solve(dv));
        ++st.n_nees;
      }
    }
    if (k == steps) {
      st.fin_att = de.norm();
      st.fin_vel = dv.norm();
      st.fin_pos = dp.norm();
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  st.ns_per_step = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(steps);
  return st;
}

template <class F> void nav_report(const char* name, long steps, long eig_every) {
  const NavStats s = nav_run<F>(steps, eig_every, 7);
  const double n = s.n_half ? double(s.n_half) : 1.0, m = s.n_nees ? double(s.n_nees) : 1.0;
  std::printf("%-24s %-7s steps=%ld  max||q|-1|=%.2e  P: max asym=%.1e not-PD steps=%ld eig=[%.2e, %.2e]  "
              "2nd half rms/max, final: att %.3f/%.3f, %.3f mrad; vel %.4f/%.4f, %.4f m/s; pos %.2f/%.2f, %.2f m  "
              "mean NEES att=%.2f vel=%.2f (3 dof)  non-finite=%ld  statuses: %s  %.0f ns/step (incl. checks and "
              "simulation)\n",
              name, sizeof(typename F::Scalar) == 4 ? "float32" : "float64", steps, s.max_norm_dev, s.max_asym, s.not_pd,
              s.min_eig, s.max_eig, 1e3 * std::sqrt(s.sq_att / n), 1e3 * s.max_att, 1e3 * s.fin_att,
              std::sqrt(s.sq_vel / n), s.max_vel, s.fin_vel, std::sqrt(s.sq_pos / n), s.max_pos, s.fin_pos,
              s.nees_att / m, s.nees_vel / m, s.nonfinite, s.counts.str(s.names).c_str(), s.ns_per_step);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const long steps = argc > 1 ? std::atol(argv[1]) : 10000000L;
  const std::string only = argc > 2 ? argv[2] : "";
  const std::string prec = argc > 3 ? argv[3] : "";
  const bool f64 = prec.empty() || prec == "float64", f32 = prec.empty() || prec == "float32";
  g_no_baro = argc > 4 && std::string(argv[4]) == "no-baro";
  const long eig_every = 100;
  std::printf("quatnav long run: %ld steps of 0.01 s per filter and precision; eigenvalues every %ld steps%s\n", steps,
              eig_every, g_no_baro ? "; GpsInsFilter without the altimeter" : "");
  if (only.empty() || only == "QuaternionEKFPaper") {
    if (f64) report<QuaternionEKFPaper<double>>("QuaternionEKFPaper", steps, eig_every);
    if (f32) report<QuaternionEKFPaper<float>>("QuaternionEKFPaper", steps, eig_every);
  }
  if (only.empty() || only == "EulerEKF") {
    if (f64) report<EulerEKF<double>>("EulerEKF", steps, eig_every);
    if (f32) report<EulerEKF<float>>("EulerEKF", steps, eig_every);
  }
  if (only.empty() || only == "NavFilter13-ekf") {
    if (f64) nav_report<NavFilter13<double, TimeUpdate::Ekf>>("NavFilter13-ekf", steps, eig_every);
    if (f32) nav_report<NavFilter13<float, TimeUpdate::Ekf>>("NavFilter13-ekf", steps, eig_every);
  }
  if (only.empty() || only == "NavFilter13-second_order") {
    if (f64) nav_report<NavFilter13<double, TimeUpdate::SecondOrder>>("NavFilter13-second_order", steps, eig_every);
    if (f32) nav_report<NavFilter13<float, TimeUpdate::SecondOrder>>("NavFilter13-second_order", steps, eig_every);
  }
  if (only.empty() || only == "NavFilter13-ukf") {
    if (f64) nav_report<NavFilter13<double, TimeUpdate::Ukf>>("NavFilter13-ukf", steps, eig_every);
    if (f32) nav_report<NavFilter13<float, TimeUpdate::Ukf>>("NavFilter13-ukf", steps, eig_every);
  }
  if (only.empty() || only == "GpsInsFilter") {
    if (f64) nav_report<GpsInsFilter<double>>("GpsInsFilter", steps, eig_every);
    if (f32) nav_report<GpsInsFilter<float>>("GpsInsFilter", steps, eig_every);
  }
  return 0;
}
