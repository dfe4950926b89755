// quatnav: the first-order low-passes that the filters' detectors and learned references use.
#pragma once

#include <cmath>

namespace quatnav {
namespace detail {

/// The weight of one step of a first-order low-pass over dt with time constant tau, as the
/// backward-Euler discretization dt / (tau + dt); tau <= 0: no filtering (1).
template <class S> S lowpass_gain(S dt, S tau) { return tau > S(0) ? dt / (tau + dt) : S(1); }

/// One low-pass step y = y + a (x - y), with a = lowpass_gain(dt, tau).
template <class S, class V> void lowpass(V& y, const V& x, S dt, S tau) {
  const S a = lowpass_gain(dt, tau);
  y = y + a * (x - y);
}

/// The weight of one step over T of the exact (zero-order hold) discretization, 1 - exp(-T / tau);
/// tau <= 0: no filtering (1).
template <class S> S lowpass_weight(S T, S tau) { return tau > S(0) ? S(1) - std::exp(-T / tau) : S(1); }

}  // namespace detail
}  // namespace quatnav
