// quatnav: strapdown inertial mechanization in the local NED frame.
//
// Twin of python/quatnav/strapdown.py (tested against it step by step in double to 1e-9).
//
// One step from t[k-1] to t[k] (dt = t[k] - t[k-1]). Inputs are the MEAN body rate omega_ib_b
// (rad/s) and specific force f_ib_b (m/s^2) over the interval, i.e. an IMU's increments divided
// by dt: dtheta = omega_ib_b dt, dv = f_ib_b dt. Two-sample corrections use the previous step's
// increments kept in the state (Savage, "Strapdown Analytics", 2000, ch. 7; Titterton & Weston,
// "Strapdown Inertial Navigation Technology", 2nd ed., 2004, ch. 11):
//   1. rotation vector with coning:   phi = dtheta + 1/12 dtheta_prev x dtheta
//   2. body velocity increment with rotation and sculling:
//        dv_rot = dv + 1/2 dtheta x dv + 1/6 dtheta x (dtheta x dv)
//                 + 1/12 (dtheta_prev x dv + dv_prev x dtheta)
//      (the two-sample terms are skipped on the first step)
//   3. velocity (paper 004 eq. 2) with the Earth terms at the interval midpoint, predicted by a
//      first pass with the values at t[k-1] (predictor-corrector):
//        zeta = (omega_ie_n + omega_en_n) dt           (rotation of NED over the step)
//        v_n += (I - 1/2 [zeta x]) C_nb dv_rot + (g_n - (2 omega_ie_n + omega_en_n) x v_mid) dt
//   4. position, trapezoidal in velocity with the radii at the midpoint:
//        lat += v_N dt / (R_M + h),  lon += v_E dt / ((R_N + h) cos lat),  h -= v_D dt
//   5. attitude: q_nb <- exp(-zeta) * q_nb * exp(phi), renormalized.
// With earth_rotation = false, omega_ie_n = omega_en_n = 0 (flat non-rotating Earth; gravity is
// still normal gravity at the current latitude and height).
//
// The geodetic position is kept in double whatever Scalar is: a float latitude resolves only
// about 0.4 m, which would swallow the per-step displacement of a slow vehicle.
//
// A step with non-finite input or state, or dt <= 0, returns a status and leaves the state
// untouched; so does a step whose result would be non-finite. No heap, no exceptions.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "../core/earth.hpp"
#include "../core/fields.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

/// Strapdown options.
struct StrapdownParams {
  bool earth_rotation = true;  ///< include Earth rate, Coriolis and transport-rate terms
};

/// Navigation state of the strapdown mechanization (plain data: copy it out and back freely).
// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_STRAPDOWN_STATE(X)                                                                    \
  X(Quat<S>, q_nb, Quat<S>(S(1), S(0), S(0), S(0)), "1", "attitude q_nb [w, x, y, z], body to NED")     \
  X(Vec3<S>, v_n, Vec3<S>::Zero(), "m/s", "velocity with respect to the Earth, NED")                    \
  X(double, lat, 0.0, "rad", "geodetic latitude")                                                      \
  X(double, lon, 0.0, "rad", "longitude")                                                              \
  X(double, h, 0.0, "m", "height above the ellipsoid")                                                 \
  X(Vec3<S>, dtheta_prev, Vec3<S>::Zero(), "rad", "previous angle increment (coning term)")             \
  X(Vec3<S>, dv_prev, Vec3<S>::Zero(), "m/s", "previous velocity increment (sculling term)")             \
  X(bool, has_prev, false, "-", "whether dtheta_prev and dv_prev hold a step")

template <class S> struct StrapdownState {
  QUATNAV_FIELDS(StrapdownState, QUATNAV_STRAPDOWN_STATE)
};

namespace detail {

/// Blocks template deduction, so only the state decides Scalar (Zero() and literals then work).
template <class T> struct identity {
  using type = T;
};

/// The Earth terms (earth.hpp) evaluated in double at the double position, rounded to S.
template <class S> struct EarthTerms {
  S g;
  Vec3<S> w_ie;
  Vec3<S> w_en;
};

template <class S> EarthTerms<S> earth_terms(double lat, double h, const Vec3<S>& v, bool earth_rotation) {
  const earth::Terms<double> t = earth::terms<double>(lat, h, v.template cast<double>(), earth_rotation);
  return EarthTerms<S>{S(t.g), t.omega_ie_n.template cast<S>(), t.omega_en_n.template cast<S>()};
}

template <class S> bool all_finite(const StrapdownState<S>& s) {
  return s.q_nb.allFinite() && s.v_n.allFinite() && std::isfinite(s.lat) && std::isfinite(s.lon) &&
         std::isfinite(s.h) && s.dtheta_prev.allFinite() && s.dv_prev.allFinite();
}

}  // namespace detail

/// Advance `st` by one IMU interval. Returns Status::Ok, InvalidDt, NonFinite or
/// NumericalFailure; on anything but Ok the state is untouched.
template <class S>
Status strapdown_step(StrapdownState<S>& st, const typename detail::identity<Vec3<S>>::type& omega_ib_b,
                      const typename detail::identity<Vec3<S>>::type& f_ib_b,
                      typename detail::identity<S>::type dt, const StrapdownParams& params = StrapdownParams()) {
  using std::cos;
  if (!(std::isfinite(dt) && dt > S(0))) return Status::InvalidDt;
  if (!omega_ib_b.allFinite() || !f_ib_b.allFinite() || !detail::all_finite(st)) return Status::NonFinite;

  const Vec3<S> dth = omega_ib_b * dt;
  const Vec3<S> dvb = f_ib_b * dt;
  const Vec3<S> c = dth.cross(dvb);
  Vec3<S> phi = dth;
  Vec3<S> dv_rot = dvb + S(0.5) * c + dth.cross(c) / S(6);
  if (st.has_prev) {
    phi += st.dtheta_prev.cross(dth) / S(12);
    dv_rot += (st.dtheta_prev.cross(dvb) + st.dv_prev.cross(dth)) / S(12);
  }
  const Vec3<S> dv_n = quat::rotate(st.q_nb, dv_rot);
  const Vec3<S> v = st.v_n;
  const double lat = st.lat, h = st.h;

  auto velocity = [&](double lat_m, double h_m, const Vec3<S>& v_m, Vec3<S>& zeta) {
    const detail::EarthTerms<S> e = detail::earth_terms<S>(lat_m, h_m, v_m, params.earth_rotation);
    zeta = (e.w_ie + e.w_en) * dt;
    const Vec3<S> g_n(S(0), S(0), e.g);
    return Vec3<S>(v + dv_n - S(0.5) * zeta.cross(dv_n) + (g_n - (S(2) * e.w_ie + e.w_en).cross(v_m)) * dt);
  };

  // predictor: Earth terms at t[k-1]
  Vec3<S> zeta;
  const Vec3<S> v_pred = velocity(lat, h, v, zeta);
  const double R_M = earth::radii<double>(lat).R_M;
  const double ddt = double(dt);
  Vec3<S> v_mid = S(0.5) * (v + v_pred);
  double h_mid = h - 0.5 * ddt * double(v_mid[2]);
  double lat_mid = lat + 0.5 * ddt * double(v_mid[0]) / (R_M + h);
  // corrector: Earth terms at the midpoint
  const Vec3<S> v_new = velocity(lat_mid, h_mid, v_mid, zeta);
  const Vec3<double> v_avg = (S(0.5) * (v + v_new)).template cast<double>();
  h_mid = h - 0.5 * ddt * v_avg[2];
  lat_mid = lat + 0.5 * ddt * v_avg[0] / (R_M + h);
  const earth::Radii<double> rm = earth::radii<double>(lat_mid);
  const double lat_new = lat + ddt * v_avg[0] / (rm.R_M + h_mid);
  const double lon_new = st.lon + ddt * v_avg[1] / ((rm.R_N + h_mid) * cos(lat_mid));
  const double h_new = h - ddt * v_avg[2];

  Quat<S> q_new = quat::mul(quat::from_rotvec(Vec3<S>(-zeta)), quat::mul(st.q_nb, quat::from_rotvec(phi)));
  q_new /= q_new.norm();
  if (!q_new.allFinite() || !v_new.allFinite() || !std::isfinite(lat_new) || !std::isfinite(lon_new) ||
      !std::isfinite(h_new))
    return Status::NumericalFailure;
  st.q_nb = q_new;
  st.v_n = v_new;
  st.lat = lat_new;
  st.lon = lon_new;
  st.h = h_new;
  st.dtheta_prev = dth;
  st.dv_prev = dvb;
  st.has_prev = true;
  return Status::Ok;
}

/// Run n steps. omega_ib_b, f_ib_b: n x 3 row-major (mean rate and specific force over each
/// interval); dt: n interval lengths (s). Outputs (any may be null): q_out n x 4, v_out n x 3,
/// llh_out n x 3 ([lat, lon, h], double), status_out n (quatnav::Status as uint8). A failed step
/// leaves the state as it was and the run continues with the next sample. Allocates nothing.
template <class S>
void strapdown_batch(StrapdownState<S>& st, const S* omega_ib_b, const S* f_ib_b, const S* dt, std::size_t n,
                     const StrapdownParams& params, S* q_out, S* v_out, double* llh_out,
                     std::uint8_t* status_out) {
  for (std::size_t k = 0; k < n; ++k) {
    const Status s = strapdown_step(st, Vec3<S>(Eigen::Map<const Vec3<S>>(omega_ib_b + 3 * k)),
                                    Vec3<S>(Eigen::Map<const Vec3<S>>(f_ib_b + 3 * k)), dt[k], params);
    if (q_out) Eigen::Map<Vec4<S>>(q_out + 4 * k) = st.q_nb;
    if (v_out) Eigen::Map<Vec3<S>>(v_out + 3 * k) = st.v_n;
    if (llh_out) {
      llh_out[3 * k] = st.lat;
      llh_out[3 * k + 1] = st.lon;
      llh_out[3 * k + 2] = st.h;
    }
    if (status_out) status_out[k] = static_cast<std::uint8_t>(s);
  }
}

}  // namespace quatnav
