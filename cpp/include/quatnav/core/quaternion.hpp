// quatnav: quaternion and rotation helpers.
//
// Hamilton quaternions stored scalar first [w, x, y, z]; q_nb rotates body vectors into the
// navigation frame (v_n = C_nb v_b). Eigen::Quaternion stores [x, y, z, w] in coeffs(): use
// to_eigen()/from_eigen() to convert, never coeffs() directly.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "types.hpp"

namespace quatnav {
namespace quat {

template <class S> Quat<S> identity() { return Quat<S>(S(1), S(0), S(0), S(0)); }

/// Hamilton product p * q.
template <class S> Quat<S> mul(const Quat<S>& p, const Quat<S>& q) {
  return Quat<S>(p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
                 p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
                 p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
                 p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]);
}

template <class S> Quat<S> conj(const Quat<S>& q) { return Quat<S>(q[0], -q[1], -q[2], -q[3]); }

/// q / |q|; the caller checks that |q| is not zero.
template <class S> Quat<S> normalized(const Quat<S>& q) { return q / q.norm(); }

/// The same rotation with w >= 0.
template <class S> Quat<S> canonical(const Quat<S>& q) { return q[0] < S(0) ? Quat<S>(-q) : q; }

/// Skew-symmetric matrix [v x]: skew(a) b = a x b.
template <class S> Mat3<S> skew(const Vec3<S>& v) {
  Mat3<S> m;
  m << S(0), -v[2], v[1], v[2], S(0), -v[0], -v[1], v[0], S(0);
  return m;
}

/// Left-multiplication matrix: p * q = left(p) q.
template <class S> Mat4<S> left(const Quat<S>& p) {
  Mat4<S> m;
  m << p[0], -p[1], -p[2], -p[3],
       p[1], p[0], -p[3], p[2],
       p[2], p[3], p[0], -p[1],
       p[3], -p[2], p[1], p[0];
  return m;
}

/// Right-multiplication matrix: p * q = right(q) p.
template <class S> Mat4<S> right(const Quat<S>& q) {
  Mat4<S> m;
  m << q[0], -q[1], -q[2], -q[3],
       q[1], q[0], q[3], -q[2],
       q[2], -q[3], q[0], q[1],
       q[3], q[2], -q[1], q[0];
  return m;
}

/// Omega(w) of paper 000 eq. (5): q * [0, w] = omega(w) q, so q_dot = 1/2 omega(w_b) q.
template <class S> Mat4<S> omega(const Vec3<S>& w) { return right(Quat<S>(S(0), w[0], w[1], w[2])); }

/// Xi(q), 4x3: q * [0, v] = xi(q) v (the last three columns of left(q)).
template <class S> Mat43<S> xi(const Quat<S>& q) {
  Mat43<S> m;
  m << -q[1], -q[2], -q[3],
        q[0], -q[3], q[2],
        q[3], q[0], -q[1],
       -q[2], q[1], q[0];
  return m;
}

/// Rotation matrix C_nb of q_nb (exact for unit q; v_n = C_nb v_b).
template <class S> Mat3<S> to_rotmat(const Quat<S>& q) {
  const S w = q[0], x = q[1], y = q[2], z = q[3];
  Mat3<S> c;
  c << S(1) - S(2) * (y * y + z * z), S(2) * (x * y - w * z), S(2) * (x * z + w * y),
       S(2) * (x * y + w * z), S(1) - S(2) * (x * x + z * z), S(2) * (y * z - w * x),
       S(2) * (x * z - w * y), S(2) * (y * z + w * x), S(1) - S(2) * (x * x + y * y);
  return c;
}

/// Quaternion of a rotation matrix (Shepperd's method), w >= 0.
template <class S> Quat<S> from_rotmat(const Mat3<S>& c) {
  const S tr = c.trace();
  Quat<S> q;
  if (tr > c(0, 0) && tr > c(1, 1) && tr > c(2, 2)) {
    const S s = std::sqrt(S(1) + tr) * S(2);
    q << S(0.25) * s, (c(2, 1) - c(1, 2)) / s, (c(0, 2) - c(2, 0)) / s, (c(1, 0) - c(0, 1)) / s;
  } else if (c(0, 0) > c(1, 1) && c(0, 0) > c(2, 2)) {
    const S s = std::sqrt(S(1) + c(0, 0) - c(1, 1) - c(2, 2)) * S(2);
    q << (c(2, 1) - c(1, 2)) / s, S(0.25) * s, (c(0, 1) + c(1, 0)) / s, (c(0, 2) + c(2, 0)) / s;
  } else if (c(1, 1) > c(2, 2)) {
    const S s = std::sqrt(S(1) + c(1, 1) - c(0, 0) - c(2, 2)) * S(2);
    q << (c(0, 2) - c(2, 0)) / s, (c(0, 1) + c(1, 0)) / s, S(0.25) * s, (c(1, 2) + c(2, 1)) / s;
  } else {
    const S s = std::sqrt(S(1) + c(2, 2) - c(0, 0) - c(1, 1)) * S(2);
    q << (c(1, 0) - c(0, 1)) / s, (c(0, 2) + c(2, 0)) / s, (c(1, 2) + c(2, 1)) / s, S(0.25) * s;
  }
  return canonical(normalized(q));
}

/// v_n = C_nb v_b.
template <class S> Vec3<S> rotate(const Quat<S>& q, const Vec3<S>& v) {
  const Vec3<S> u(q[1], q[2], q[3]);
  const Vec3<S> t = S(2) * u.cross(v);
  return v + q[0] * t + u.cross(t);
}

/// v_b = C_nb^T v_n.
template <class S> Vec3<S> rotate_inv(const Quat<S>& q, const Vec3<S>& v) { return rotate(conj(q), v); }

/// C_nb^T e_z: the navigation frame's z axis (down in NED) in the body frame, the last row of
/// to_rotmat(q) (rotate_inv(q, e_z) in a third of its operations).
template <class S> Vec3<S> nav_z_in_body(const Quat<S>& q) {
  const S w = q[0], x = q[1], y = q[2], z = q[3];
  return Vec3<S>(S(2) * (x * z - w * y), S(2) * (y * z + w * x), S(1) - S(2) * (x * x + y * y));
}

/// ZYX Euler angles [roll, pitch, yaw] of q_nb (paper 000 eq. 3; pitch clamped to [-pi/2, pi/2]).
template <class S> Vec3<S> to_euler(const Quat<S>& q) {
  const S w = q[0], x = q[1], y = q[2], z = q[3];
  S sp = S(2) * (w * y - x * z);
  sp = sp > S(1) ? S(1) : (sp < S(-1) ? S(-1) : sp);
  return Vec3<S>(std::atan2(S(2) * (w * x + y * z), S(1) - S(2) * (x * x + y * y)), std::asin(sp),
                 std::atan2(S(2) * (w * z + x * y), S(1) - S(2) * (y * y + z * z)));
}

/// q_nb of ZYX Euler angles: C_nb = Rz(yaw) Ry(pitch) Rx(roll).
template <class S> Quat<S> from_euler(S roll, S pitch, S yaw) {
  const S cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const S cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const S cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  return Quat<S>(cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                 cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy);
}
template <class S> Quat<S> from_euler(const Vec3<S>& rpy) { return from_euler(rpy[0], rpy[1], rpy[2]); }

/// cos(x) and sin(x)/x from x2 = x^2, without a libm call for the angles a step turns through:
/// their Taylor polynomials by Horner in x2, for float through x^6 while x2 < 1/16 (|x| < 0.25
/// rad), for double through x^10 while x2 < 1/64 (|x| < 0.125 rad): the first term left out is
/// below 4e-10 and 2e-20, so the result is as close as libm's. libm beyond.
template <class S> void cos_sinc(S x2, S& c, S& sinc) {
  if (sizeof(S) <= 4 && x2 < S(0.0625)) {
    c = S(1) + x2 * (S(-1) / S(2) + x2 * (S(1) / S(24) + x2 * (S(-1) / S(720))));
    sinc = S(1) + x2 * (S(-1) / S(6) + x2 * (S(1) / S(120) + x2 * (S(-1) / S(5040))));
  } else if (sizeof(S) > 4 && x2 < S(0.015625)) {
    c = S(1) + x2 * (S(-1) / S(2) + x2 * (S(1) / S(24) + x2 * (S(-1) / S(720) + x2 * (S(1) / S(40320) +
          x2 * (S(-1) / S(3628800))))));
    sinc = S(1) + x2 * (S(-1) / S(6) + x2 * (S(1) / S(120) + x2 * (S(-1) / S(5040) + x2 * (S(1) / S(362880) +
             x2 * (S(-1) / S(39916800))))));
  } else {
    const S x = std::sqrt(x2);
    c = std::cos(x);
    sinc = std::sin(x) / x;
  }
}

/// atan2(y, x) without a libm call for the small angles of an innovation or a dip offset: for
/// x > 0 and |y / x| <= 1/8, the Taylor polynomial of atan(t), t = y / x, by Horner in t^2, for
/// float through t^7, for double through t^17 (an alternating series: the first term left out,
/// |t|^9 / 9 and |t|^19 / 19, is below 2^-24 |t| / 9 and 2^-54 |t| / 19, so the result is as
/// close as libm's). libm elsewhere (and for NaN: every test above fails).
template <class S> S atan2_small(S y, S x) {
  const S t = y / x;
  if (x > S(0) && std::abs(t) <= S(0.125)) {
    const S t2 = t * t;
    if (sizeof(S) <= 4) return t * (S(1) + t2 * (S(-1) / S(3) + t2 * (S(1) / S(5) + t2 * (S(-1) / S(7)))));
    return t * (S(1) + t2 * (S(-1) / S(3) + t2 * (S(1) / S(5) + t2 * (S(-1) / S(7) + t2 * (S(1) / S(9) +
           t2 * (S(-1) / S(11) + t2 * (S(1) / S(13) + t2 * (S(-1) / S(15) + t2 * (S(1) / S(17))))))))));
  }
  return std::atan2(y, x);
}

/// Exponential map of a rotation vector: the unit quaternion of a rotation by |r| about r/|r|.
template <class S> Quat<S> from_rotvec(const Vec3<S>& r) {
  S c, sinc;  // cos(|r|/2), sin(|r|/2)/(|r|/2)
  cos_sinc(r.squaredNorm() / S(4), c, sinc);
  const S s = S(0.5) * sinc;  // sin(|r|/2)/|r|
  return Quat<S>(c, s * r[0], s * r[1], s * r[2]);
}

/// Jacobian (4x3) of from_rotvec at r.
template <class S> Mat43<S> from_rotvec_jacobian(const Vec3<S>& r) {
  const S a2 = r.squaredNorm();
  const S h2 = a2 / S(4);
  S s, ds, c_over;  // s = sin(a/2)/a; ds = (ds/da)/a; c_over = -sin(a/2)/(2a) = d cos(a/2)/da / a
  if (h2 < std::cbrt(std::numeric_limits<S>::epsilon())) {
    s = S(0.5) * (S(1) - h2 / S(6) + h2 * h2 / S(120));
    // d/da [sin(a/2)/a] / a = (a/2 cos(a/2) - sin(a/2)) / a^3 = -1/24 + a^2/960 - ...
    ds = S(-1) / S(24) + a2 / S(960);
    c_over = S(-0.5) * s;
  } else {
    const S a = std::sqrt(a2);
    s = std::sin(a / S(2)) / a;
    ds = (a / S(2) * std::cos(a / S(2)) - std::sin(a / S(2))) / (a2 * a);
    c_over = -std::sin(a / S(2)) / (S(2) * a);
  }
  Mat43<S> j;
  j.row(0) = c_over * r.transpose();
  j.template bottomRows<3>() = s * Mat3<S>::Identity() + ds * r * r.transpose();
  return j;
}

/// Logarithm map: the rotation vector of a unit quaternion (angle in [0, pi]).
template <class S> Vec3<S> to_rotvec(const Quat<S>& q_in) {
  const Quat<S> q = canonical(q_in);
  const Vec3<S> v(q[1], q[2], q[3]);
  const S sn = v.norm();
  if (sn < std::sqrt(std::numeric_limits<S>::epsilon())) {
    return (S(2) / q[0]) * (S(1) - sn * sn / (S(3) * q[0] * q[0])) * v;
  }
  return (S(2) * std::atan2(sn, q[0]) / sn) * v;
}

/// Rotation angle (rad, in [0, pi]) between two attitudes.
template <class S> S angle_between(const Quat<S>& a, const Quat<S>& b) {
  S d = std::abs(a.dot(b)) / (a.norm() * b.norm());
  d = d > S(1) ? S(1) : d;
  return S(2) * std::acos(d);
}

/// q_{NED<-ENU}: rotates ENU-frame vectors into NED (x_n = y_e, y_n = x_e, z_n = -z_e).
template <class S> Quat<S> ned_from_enu() {
  const S h = std::sqrt(S(0.5));
  return Quat<S>(S(0), h, h, S(0));
}

/// Attitude with respect to NED from attitude with respect to ENU (same body frame).
template <class S> Quat<S> enu_to_ned(const Quat<S>& q_enu_b) { return mul(ned_from_enu<S>(), q_enu_b); }
/// Attitude with respect to ENU from attitude with respect to NED (same body frame).
template <class S> Quat<S> ned_to_enu(const Quat<S>& q_ned_b) { return mul(conj(ned_from_enu<S>()), q_ned_b); }

/// Conversion to and from Eigen::Quaternion (whose coeffs() are [x, y, z, w]).
template <class S> Eigen::Quaternion<S> to_eigen(const Quat<S>& q) { return Eigen::Quaternion<S>(q[0], q[1], q[2], q[3]); }
template <class S> Quat<S> from_eigen(const Eigen::Quaternion<S>& q) { return Quat<S>(q.w(), q.x(), q.y(), q.z()); }

/// Wrap an angle to (-pi, pi].
template <class S> S wrap_pi(S a) {
  const S pi = S(3.14159265358979323846);
  a = std::fmod(a + pi, S(2) * pi);
  if (a <= S(0)) a += S(2) * pi;
  return a - pi;
}

}  // namespace quat
}  // namespace quatnav
