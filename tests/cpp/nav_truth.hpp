// The simulated vehicle shared by the long runs (bench/long_run.cpp) and the navigation
// consistency test (test_nav13_consistency.cpp): a smooth attitude with body rates up to about
// 0.2 rad/s, a 1000 m circle at 10 m/s with a small vertical oscillation, and the exact IMU of the
// Earth model (earth.hpp) at the middle of each step.
#pragma once

#include <cmath>

#include <quatnav/core/earth.hpp>
#include <quatnav/core/quaternion.hpp>

namespace quatnav_test {

using quatnav::Quat;
using quatnav::Vec3;
namespace earth = quatnav::earth;
namespace quat = quatnav::quat;

/// Attitude truth: ZYX Euler angles [rad] as smooth functions of time.
struct Truth {
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

/// The true vehicle: Truth's attitude, a circle in velocity, the position integrated in double.
struct NavTruth {
  Truth att;
  double lat = 0.6, lon = 0.2, h = 100.0;
  Vec3<double> v(double t) const {
    return Vec3<double>(10.0 * std::cos(0.01 * t), 10.0 * std::sin(0.01 * t), 0.5 * std::sin(0.05 * t));
  }
  Vec3<double> v_dot(double t) const {
    return Vec3<double>(-0.1 * std::sin(0.01 * t), 0.1 * std::cos(0.01 * t), 0.025 * std::cos(0.05 * t));
  }
  /// The IMU over (t - dt, t] (noise-free, at the middle of the step) and the position advanced to t.
  void step(double t, double dt, Vec3<double>& w_ib_b, Vec3<double>& f_ib_b) {
    const double tm = t - 0.5 * dt;
    const Vec3<double> vm = v(tm);
    const Vec3<double> r0 = earth::geodetic_rates(lat, h, vm);
    const double lat_m = lat + 0.5 * dt * r0[0], h_m = h + 0.5 * dt * r0[2];
    const Quat<double> q = quat::from_euler(att.euler(tm));
    const Vec3<double> w_ie = earth::earth_rate_n(lat_m), w_en = earth::transport_rate_n(lat_m, h_m, vm);
    w_ib_b = att.body_rate(tm) + quat::rotate_inv(q, Vec3<double>(w_ie + w_en));
    f_ib_b = quat::rotate_inv(q, Vec3<double>(v_dot(tm) + (2.0 * w_ie + w_en).cross(vm) - earth::gravity_n(lat_m, h_m)));
    const Vec3<double> r = earth::geodetic_rates(lat_m, h_m, vm);
    lat += dt * r[0];
    lon += dt * r[1];
    h += dt * r[2];
  }
};

}  // namespace quatnav_test
