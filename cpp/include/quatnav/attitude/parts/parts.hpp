// quatnav: the robustness parts of an attitude filter together (rest detection, the accelerometer
// part, the magnetometer disturbance part), for what every filter that composes them does alike.
#pragma once

#include "acc_filter.hpp"
#include "gyro_clip.hpp"
#include "mag_disturbance.hpp"
#include "rest.hpp"

namespace quatnav {

namespace detail {
/// GyroClip::restart for the filters whose State has the part (the quaternion EKFs), else nothing.
template <class S, class State> auto restart_gyro_clip(State& s, int) -> decltype(s.clip, void()) {
  GyroClip<S>::restart(s.clip);
}
template <class S, class State> void restart_gyro_clip(State&, long) {}
}  // namespace detail

/// When a filter starts (initialize): every part starts afresh and, when the first sample has a
/// magnetometer reading mag, the reference field is learned from it (m_n: that reading in the
/// navigation frame, unless the user fixed the reference). The filter's Params and State carry
/// the parts as the fields rest, acc and mag (and clip, the quaternion EKFs).
template <class S, class Params, class State>
void restart_parts(const Params& p, State& s, const Vec3<S>* mag, const Vec3<S>& m_n) {
  Rest<S>::restart(s.rest);
  AccFilter<S>::restart(s.acc);
  MagDisturbance<S>::restart(s.mag);
  detail::restart_gyro_clip<S>(s, 0);
  if (mag) MagDisturbance<S>::start(p.mag, s.mag, Vec3<S>(m_n / m_n.norm()), mag->norm());
}

}  // namespace quatnav
