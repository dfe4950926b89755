// quatnav: pieces shared by the attitude filters and their parts (parts/): the reference
// magnetic field, the initialization from gravity and field, the first-order low-pass, the
// rate-proportional tilt noise of the quaternion EKFs.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "../core/checks.hpp"
#include "../core/fields.hpp"
#include "../core/lowpass.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

/// The normalized reference field [m_x, 0, m_z] (x = magnetic north, z = down) of an attitude
/// filter. Unless fixed by the user (dip angle), it is learned from the first magnetometer
/// samples: the mean of sin(dip) = z component of the normalized field rotated into the
/// navigation frame by the current attitude, over the first `max_samples` samples.
// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_MAG_REF(X)                                                                             \
  X(Vec3<S>, mag_ref, Vec3<S>(S(1), S(0), S(0)), "1", "reference field [m_x, 0, m_z], normalized")     \
  X(S, mag_sin_dip_sum, S(0), "1", "sum of the sin(dip) samples learned so far")                       \
  X(std::uint32_t, mag_ref_count, 0, "-", "field samples learned so far")                              \
  X(bool, mag_ref_fixed, false, "-", "the dip was set by the user (set_mag_dip) and is not learned")

template <class S> struct MagRef {
  QUATNAV_FIELDS(MagRef, QUATNAV_MAG_REF)

  bool valid() const { return mag_ref_fixed || mag_ref_count > 0; }
  void fix(S dip) {
    mag_ref = Vec3<S>(std::cos(dip), S(0), std::sin(dip));
    mag_ref_fixed = true;
  }
  /// Learn from a unit field vector expressed in the navigation frame.
  void learn(const Vec3<S>& m_n_unit, std::uint32_t max_samples) {
    if (mag_ref_fixed || mag_ref_count >= max_samples) return;
    mag_sin_dip_sum += m_n_unit[2];
    ++mag_ref_count;
    S sd = mag_sin_dip_sum / S(mag_ref_count);
    sd = sd > S(1) ? S(1) : (sd < S(-1) ? S(-1) : sd);
    mag_ref = Vec3<S>(std::sqrt(S(1) - sd * sd), S(0), sd);
  }
  /// Start learning afresh from one unit field vector (navigation frame), unless fixed.
  void restart(const Vec3<S>& m_n_unit, std::uint32_t max_samples) {
    if (!mag_ref_fixed) *this = MagRef();
    learn(m_n_unit, max_samples);
  }
};

namespace detail {

/// Tilt and heading from one accelerometer and magnetometer sample. Returns false for
/// degenerate input. mag may be null (heading 0). mag_ref receives [m_x, 0, m_z] normalized.
template <class S>
bool attitude_from_acc_mag(const Vec3<S>& acc, const Vec3<S>* mag, Quat<S>& q, Vec3<S>& mag_ref) {
  const S an = acc.norm();
  if (!(an > std::numeric_limits<S>::min() * S(1e6))) return false;
  const Vec3<S> a = acc / an;
  S roll, pitch;
  level_from_acc(a, roll, pitch);
  S yaw = S(0);
  if (mag != nullptr) {
    const S mn = mag->norm();
    if (!(mn > std::numeric_limits<S>::min() * S(1e6))) return false;
    const Vec3<S> m = *mag / mn;
    // Level the field: m_h = Ry(pitch) Rx(roll) m_b = Rz(yaw)^T m_n.
    const Quat<S> q_tilt = quat::from_euler(roll, pitch, S(0));
    const Vec3<S> mh = quat::rotate(q_tilt, m);
    const S horiz = std::sqrt(mh[0] * mh[0] + mh[1] * mh[1]);
    if (!(horiz > S(1e-3))) return false;  // field parallel to gravity: no heading
    yaw = std::atan2(-mh[1], mh[0]);
    mag_ref = Vec3<S>(horiz, S(0), mh[2]);
  }
  q = quat::from_euler(roll, pitch, yaw);
  return true;
}

/// The rate-proportional tilt noise (gyro_rate_noise): a scale-factor or misalignment error e
/// of the gyro turns the attitude by e |w - b| dt per step, so the time update's attitude noise
/// grows with the rate. Only its tilt part is added, dt (k |w - b|)^2 (I - u u^T) in the body
/// frame (u = C_nb^T e_z, the vertical at the propagated attitude q, unit): the accelerometer
/// corrects that part, and a heading variance that grows in fast motion would hand the heading
/// to the magnetometer whenever the body turns fast (BROAD 9D: 1.67 -> 1.90 deg with the noise
/// in all three axes, 1.64 in the tilt only). Returns the 3x3 term (exactly symmetric), zero
/// when k = 0.
template <class S> Mat3<S> tilt_rate_noise(const Quat<S>& q, const Vec3<S>& rate, S k, S dt) {
  const S w = k * rate.norm();
  if (!(w > S(0))) return Mat3<S>::Zero();
  const Vec3<S> u = quat::nav_z_in_body(q);
  return (dt * w * w) * (Mat3<S>::Identity() - u * u.transpose());
}

}  // namespace detail
}  // namespace quatnav
