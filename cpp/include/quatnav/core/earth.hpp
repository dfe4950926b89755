// quatnav: WGS-84 Earth model (twin of python/quatnav/earth.py; the two are tested together).
//
// Constants: NIMA TR8350.2, "Department of Defense World Geodetic System 1984", 3rd ed. (2000),
// tables 3.1-3.3. Normal gravity in the four-coefficient form of paper 004 eq. (2),
//     g(L, h) = g0 + g1 sin^2 L + g2 h + g3 h sin^2 L,
// with g0 = gamma_e, g1 = gamma_p - gamma_e (exact at the equator and the poles; within 6e-5 m/s^2
// of Somigliana's closed form, TR8350.2 eq. 4-1) and g2, g3 the linear free-air terms of
// TR8350.2 eq. 4-3, -2 gamma(L)/a (1 + f + m - 2 f sin^2 L) h, to first order in sin^2 L.
// Numerically g = 9.7803253 + 0.0518596 sin^2 L - 3.0877e-6 h + 4.19e-9 h sin^2 L; compare the
// normal-gravity formula quoted by Titterton & Weston (2004, ch. 3) and Savage (2000).
//
// NED navigation frame, SI units, radians. Header-only, fixed-size Eigen, no heap.
#pragma once

#include <cmath>

#include "quaternion.hpp"
#include "types.hpp"

namespace quatnav {
namespace earth {

inline constexpr double kA = 6378137.0;                       ///< semi-major axis (m)
inline constexpr double kF = 1.0 / 298.257223563;             ///< flattening
inline constexpr double kB = kA * (1.0 - kF);                 ///< semi-minor axis (m)
inline constexpr double kE2 = kF * (2.0 - kF);                ///< first eccentricity squared
inline constexpr double kOmegaIe = 7.292115e-5;               ///< Earth rotation rate (rad/s)
inline constexpr double kGM = 3.986004418e14;                 ///< gravitational constant (m^3/s^2)
inline constexpr double kGammaE = 9.7803253359;               ///< normal gravity, equator (m/s^2)
inline constexpr double kGammaP = 9.8321849378;               ///< normal gravity, poles (m/s^2)
inline constexpr double kM = kOmegaIe * kOmegaIe * kA * kA * kB / kGM;  ///< omega^2 a^2 b / GM
inline constexpr double kStandardGravity = 9.80665;           ///< conventional g (unit conversions only)
inline constexpr double kG0 = kGammaE;                        ///< m/s^2
inline constexpr double kG1 = kGammaP - kGammaE;              ///< m/s^2
inline constexpr double kG2 = -2.0 * kGammaE * (1.0 + kF + kM) / kA;  ///< 1/s^2
inline constexpr double kG3 = -2.0 * ((kGammaP - kGammaE) * (1.0 + kF + kM) - 2.0 * kF * kGammaE) / kA;  ///< 1/s^2

/// Meridian (R_M) and transverse (R_N) radii of curvature (m).
template <class S> struct Radii {
  S R_M;
  S R_N;
};

/// Radii of curvature at geodetic latitude `lat` (rad).
template <class S> Radii<S> radii(S lat) {
  using std::sin;
  using std::sqrt;
  const S s = sin(lat);
  const S w = S(1) - S(kE2) * s * s;
  const S sw = sqrt(w);
  return {S(kA) * (S(1) - S(kE2)) / (w * sw), S(kA) / sw};
}

/// Normal gravity magnitude (m/s^2) at latitude `lat` (rad) and height `h` (m), paper 004 eq. (2).
template <class S> S gravity(S lat, S h) {
  using std::sin;
  const S s = sin(lat);
  const S s2 = s * s;
  return S(kG0) + S(kG1) * s2 + (S(kG2) + S(kG3) * s2) * h;
}

/// Normal gravity vector in NED, [0, 0, g] (m/s^2).
template <class S> Vec3<S> gravity_n(S lat, S h) { return Vec3<S>(S(0), S(0), gravity(lat, h)); }

/// Earth rotation rate in NED, Omega [cos L, 0, -sin L] (rad/s).
template <class S> Vec3<S> earth_rate_n(S lat) {
  using std::cos;
  using std::sin;
  return Vec3<S>(S(kOmegaIe) * cos(lat), S(0), -S(kOmegaIe) * sin(lat));
}

/// Transport rate omega_en_n = [v_E/(R_N+h), -v_N/(R_M+h), -v_E tan L/(R_N+h)] (rad/s).
template <class S> Vec3<S> transport_rate_n(S lat, S h, const Vec3<S>& v_n) {
  using std::tan;
  const Radii<S> r = radii(lat);
  return Vec3<S>(v_n[1] / (r.R_N + h), -v_n[0] / (r.R_M + h), -v_n[1] * tan(lat) / (r.R_N + h));
}

/// [lat_dot (rad/s), lon_dot (rad/s), h_dot (m/s)] for a NED velocity.
template <class S> Vec3<S> geodetic_rates(S lat, S h, const Vec3<S>& v_n) {
  using std::cos;
  const Radii<S> r = radii(lat);
  return Vec3<S>(v_n[0] / (r.R_M + h), v_n[1] / ((r.R_N + h) * cos(lat)), -v_n[2]);
}

/// The Earth terms of a NED mechanization at (lat, h) for the velocity v_n (m/s), in the
/// arithmetic of T: normal gravity g (m/s^2, down), the Earth rate omega_ie_n and the transport
/// rate omega_en_n (rad/s; both zero when earth_rotation is false). The strapdown evaluates them
/// in double (its position is double), NavFilter13 in its Scalar.
template <class T> struct Terms {
  T g;
  Vec3<T> omega_ie_n;
  Vec3<T> omega_en_n;
  Vec3<T> g_n() const { return Vec3<T>(T(0), T(0), g); }
};

template <class T> Terms<T> terms(T lat, T h, const Vec3<T>& v_n, bool earth_rotation) {
  Terms<T> e;
  e.g = gravity(lat, h);
  if (earth_rotation) {
    e.omega_ie_n = earth_rate_n(lat);
    e.omega_en_n = transport_rate_n(lat, h, v_n);
  } else {
    e.omega_ie_n.setZero();
    e.omega_en_n.setZero();
  }
  return e;
}

/// Small-displacement NED (m, about a reference point) -> [lat, lon, h] (rad, rad, m).
template <class S> Vec3<S> ned_to_geodetic(const Vec3<S>& p_n, S lat0, S lon0, S h0) {
  using std::cos;
  const Radii<S> r = radii(lat0);
  return Vec3<S>(lat0 + p_n[0] / (r.R_M + h0), lon0 + p_n[1] / ((r.R_N + h0) * cos(lat0)), h0 - p_n[2]);
}

/// Inverse of ned_to_geodetic: local NED position (m) of [lat, lon, h] about a reference point.
template <class S> Vec3<S> geodetic_to_ned(S lat, S lon, S h, S lat0, S lon0, S h0) {
  using std::cos;
  const Radii<S> r = radii(lat0);
  return Vec3<S>((lat - lat0) * (r.R_M + h0), (lon - lon0) * (r.R_N + h0) * cos(lat0), h0 - h);
}

/// Geodetic point (lat, lon, h) moved in place by the NED displacement d (m), about the point
/// (ned_to_geodetic in double).
inline void geodetic_add(double& lat, double& lon, double& h, const Vec3<double>& d) {
  const Vec3<double> g = ned_to_geodetic<double>(d, lat, lon, h);
  lat = g[0];
  lon = g[1];
  h = g[2];
}

/// NED displacement (m) from geodetic point b to point a, a - b about b, in double and returned
/// in S: geodetic_to_ned with the longitude difference wrapped to [-pi, pi] (a and b on either
/// side of the antimeridian).
template <class S>
Vec3<S> geodetic_diff(double lat_a, double lon_a, double h_a, double lat_b, double lon_b, double h_b) {
  const Radii<double> r = radii<double>(lat_b);
  return Vec3<double>((lat_a - lat_b) * (r.R_M + h_b), quat::wrap_pi(lon_a - lon_b) * (r.R_N + h_b) * std::cos(lat_b),
                      -(h_a - h_b))
      .template cast<S>();
}

/// Earth-centred Earth-fixed position (m) of geodetic coordinates.
template <class S> Vec3<S> geodetic_to_ecef(S lat, S lon, S h) {
  using std::cos;
  using std::sin;
  const S R_N = radii(lat).R_N;
  return Vec3<S>((R_N + h) * cos(lat) * cos(lon), (R_N + h) * cos(lat) * sin(lon),
                 (R_N * (S(1) - S(kE2)) + h) * sin(lat));
}

}  // namespace earth
}  // namespace quatnav
