// quatnav: the magnetometer's reference field and its disturbance tests, a part of the attitude
// filters (QuaternionEKFPaper, QuaternionEKF, EulerEKF, MargFilter compose it).
//
//  * Reference (always): the normalized field [m_x, 0, m_z] (MagRef, attitude.hpp), learned from
//    the dip of the first mag_ref_samples samples unless set_mag_dip() fixed it, and the field's
//    norm mag_norm_ref (the first sample's, in the unit of mag).
//  * Disturbance tests: a sample is disturbed when its norm differs from mag_norm_ref by more than
//    mag_norm_tol (relative) or its dip from the reference's by more than mag_dip_tol. A disturbed
//    sample is not used. The dip is the field's at the estimated attitude, so the filter's own
//    tilt error moves it too: a filter that gives its attitude covariance (QuaternionEKF) widens
//    the tolerance to sqrt(mag_dip_tol^2 + (mag_dip_sigmas sigma_dip)^2), sigma_dip the dip's
//    one-sigma from that covariance (dip_variance()). Off by default (mag_dip_sigmas 0): with the
//    fixed tolerance a tilt error of 2-3 deg in a run's turns rejects every good sample for 10 s
//    at a time while the heading drifts by up to 40 deg, and 3 sigmas halve those rejections
//    (heading 11.4 -> 8.7 deg); but the attitude filters' tilt sigma is an effective one (2-3 deg
//    where the error is a few tenths), so the wider tolerance also lets in a magnet's field:
//    BROAD's attached-magnet trial 3.40 -> 4.70 deg, the 9D mean 1.63 -> 1.82 (docs/broad.md).
//  * Settling (mag_settle_time > 0): after a disturbance the field must pass the tests this long
//    before it is used again (a field passing them by chance inside a disturbance is not trusted).
//  * Recovery (mag_recovery_time > 0): after that long with every sample rejected, the current
//    field is taken as the new reference (a steady new field, e.g. another building).
//  * Learning (mag_ref_tau > 0): while samples are accepted, the reference norm and dip follow the
//    field with this time constant.
//
// A sample the filter does not accept leaves the reference as it was (the timers follow the
// input signal); the filter's own gate and update come between screen() and finish().
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "../attitude.hpp"
#include "../../core/fields.hpp"
#include "../../core/types.hpp"

namespace quatnav {

// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_MAG_DISTURBANCE_PARAMS(X)                                                               \
  X(std::uint32_t, mag_ref_samples, 100, "1", "magnetometer samples over which the reference dip is averaged") \
  X(S, mag_norm_tol, S(0.05), "1", "reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off)")    \
  X(S, mag_dip_tol, S(0.05), "rad",                                                                      \
    "reject the magnetometer when its dip differs from the reference by more (0: off)")                  \
  X(S, mag_dip_sigmas, S(0), "1",                                                                       \
    "the dip test's tolerance grows by this many of the filter's own one-sigmas of the dip, in "        \
    "quadrature: sqrt(mag_dip_tol^2 + (mag_dip_sigmas sigma_dip)^2) (0: mag_dip_tol alone)")             \
  X(S, mag_settle_time, S(0), "s", "after a disturbance, the field must pass the tests this long")       \
  X(S, mag_ref_tau, S(30), "s", "time constant with which the reference norm and dip follow the field")   \
  X(S, mag_recovery_time, S(0), "s",                                                                     \
    "after this long with every sample disturbed, the field becomes the reference (0: never)")

/// Parameters of the magnetometer part (the defaults are QuaternionEKF's, chosen on BROAD).
template <class S> struct MagDisturbanceParams {
  QUATNAV_FIELDS(MagDisturbanceParams, QUATNAV_MAG_DISTURBANCE_PARAMS)
};

#define QUATNAV_MAG_DISTURBANCE_STATE(X)                                                                \
  X(MagRef<S>, ref, MagRef<S>(), "-", "reference field, learned or given")                               \
  X(S, mag_norm_ref, S(0), "unit of mag", "learned field norm (0: not yet)")                             \
  X(S, mag_reject_t, S(0), "s", "time every magnetometer update was rejected")                          \
  X(S, mag_ok_t, S(1e9), "s", "time the field has passed the norm and dip tests")

template <class S> struct MagDisturbanceState {
  QUATNAV_FIELDS(MagDisturbanceState, QUATNAV_MAG_DISTURBANCE_STATE)
};

/// What MagDisturbance::screen decided about one sample (kept for finish()).
template <class S> struct MagSample {
  bool use = true;         ///< pass it to the filter's update (false: rejected by the tests)
  bool disturbed = false;  ///< the norm or dip test failed (a recovery may still use it)
  S norm = S(0);           ///< |mag| [unit of mag]
  MagRef<S> before;        ///< the reference before the sample, restored when it is not used
};

/// The steps of the magnetometer part, on a filter's MagDisturbanceParams and MagDisturbanceState.
template <class S> struct MagDisturbance {
  using Params = MagDisturbanceParams<S>;
  using State = MagDisturbanceState<S>;

  /// Switch the disturbance tests off (the plain filters of the papers): every sample is used; the
  /// reference is still learned from the first mag_ref_samples.
  static void off(Params& p) {
    p.mag_norm_tol = p.mag_dip_tol = p.mag_dip_sigmas = p.mag_settle_time = p.mag_ref_tau = p.mag_recovery_time = S(0);
  }

  /// When the filter starts (initialize): the timers start afresh.
  static void restart(State& s) {
    s.mag_reject_t = S(0);
    s.mag_ok_t = S(1e9);
  }

  /// initialize() with a field sample: learn the reference afresh from it (unless fixed) and take
  /// its norm. m_n_unit: the unit field in the navigation frame; norm: |mag|.
  static void start(const Params& p, State& s, const Vec3<S>& m_n_unit, S norm) {
    s.ref.restart(m_n_unit, p.mag_ref_samples);
    s.mag_norm_ref = norm;
  }

  /// The reference field [m_x, 0, m_z] (magnetic north frame).
  static const Vec3<S>& reference(const State& s) { return s.ref.mag_ref; }

  /// At every magnetometer sample, before the filter's update: learn the reference from it
  /// (tentatively), run the disturbance tests and the settle and recovery timers. m_n: the unit
  /// field rotated into the navigation frame by the current attitude; norm: |mag|; dt: the step
  /// of the last predict.
  static MagSample<S> screen(const Params& p, State& s, S norm, const Vec3<S>& m_n, S dt, S dip_var = S(0)) {
    MagSample<S> c;
    c.norm = norm;
    c.before = s.ref;
    s.ref.learn(m_n, p.mag_ref_samples);
    if (!(s.mag_norm_ref > S(0))) s.mag_norm_ref = norm;
    c.disturbed = (p.mag_norm_tol > S(0) && std::abs(norm / s.mag_norm_ref - S(1)) > p.mag_norm_tol) ||
                  (p.mag_dip_tol > S(0) && dip_differs(s.ref.mag_ref, m_n, dip_tolerance(p, dip_var)));
    if (p.mag_settle_time > S(0)) s.mag_ok_t = c.disturbed ? S(0) : s.mag_ok_t + dt;
    if (c.disturbed || s.mag_ok_t < p.mag_settle_time) {
      s.mag_reject_t += dt;
      if (!c.disturbed || !(p.mag_recovery_time > S(0) && s.mag_reject_t >= p.mag_recovery_time)) {
        s.ref = c.before;
        c.use = false;
        return c;
      }
      // A steady new field: take it as the reference and go on.
      s.ref.restart(m_n, p.mag_ref_samples);
      s.mag_norm_ref = norm;
    }
    return c;
  }

  /// After the filter's update of a sample screen() passed, with its status: an accepted sample
  /// clears the rejection timer and (mag_ref_tau) moves the reference norm and dip towards it,
  /// m_n_after() giving the unit field in the navigation frame at the corrected attitude; a sample
  /// not accepted leaves the reference as it was before screen() (unless it became the new one).
  template <class FieldAfter>
  static void finish(const Params& p, State& s, const MagSample<S>& c, Status status, FieldAfter&& m_n_after, S dt) {
    if (status == Status::Ok) {
      s.mag_reject_t = S(0);
      if (p.mag_ref_tau > S(0) && dt > S(0)) {
        if (!s.ref.mag_ref_fixed && s.ref.mag_ref_count >= p.mag_ref_samples) {
          // The dip d_ref + a (d - d_ref): the reference turned by a (d - d_ref) in its plane.
          S cd, sd;
          dip_offset(s.ref.mag_ref, m_n_after(), cd, sd);
          const S phi = detail::lowpass_gain(dt, p.mag_ref_tau) * quat::atan2_small(sd, cd);
          S cp, sincp;
          quat::cos_sinc(phi * phi, cp, sincp);
          const S sp = sincp * phi;
          const Vec3<S>& r = s.ref.mag_ref;
          const Vec3<S> turned(r[0] * cp - r[2] * sp, S(0), r[0] * sp + r[2] * cp);
          s.ref.mag_ref = turned / std::sqrt(turned[0] * turned[0] + turned[2] * turned[2]);
        }
        detail::lowpass(s.mag_norm_ref, c.norm, dt, p.mag_ref_tau);
      }
    } else if (status == Status::Rejected && p.mag_recovery_time > S(0)) {
      s.mag_reject_t += dt;
    }
    if (status != Status::Ok && !c.disturbed) s.ref = c.before;
  }

  /// The magnetometer update of an attitude filter: screen(), the filter's own update
  /// filter_update() -> its result (not called for a rejected sample), finish(); kMagRejected in
  /// sample_flags when the sample was rejected (disturbance tests or the filter's gate). field_n():
  /// the unit field in the navigation frame at the filter's current attitude (before and after
  /// the update); norm: |mag|.
  template <class Field, class Update>
  static auto update(const Params& p, State& s, S norm, const Field& field_n, S dt, std::uint32_t& sample_flags,
                     Update&& filter_update, S dip_var = S(0)) {
    const State before = s;  // an update that fails (SolveFailed, NumericalFailure) leaves the part too
    const MagSample<S> c = screen(p, s, norm, field_n(), dt, dip_var);
    using Result = decltype(filter_update());
    Result res = c.use ? filter_update() : Result{};  // one result, built in place
    if (c.use) {
      if (res.status != Status::Ok && res.status != Status::Rejected) {
        s = before;
        return res;
      }
      finish(p, s, c, res.status, field_n, dt);
    } else {
      res.status = Status::Rejected;
    }
    if (res.status == Status::Rejected) sample_flags |= flags::kMagRejected;
    return res;
  }

  /// Whether the dip test is widened by the filter's dip variance: a filter tests it before it
  /// forms its attitude covariance for dip_variance(), so that the default costs nothing.
  static bool widened(const Params& p) { return p.mag_dip_sigmas > S(0) && p.mag_dip_tol > S(0); }

  /// The dip test's tolerance [rad]: mag_dip_tol, widened in quadrature by mag_dip_sigmas of the
  /// filter's own one-sigma of the dip (dip_var, rad^2: dip_variance()); dip_differs() takes any.
  static S dip_tolerance(const Params& p, S dip_var) {
    if (!(p.mag_dip_sigmas > S(0)) || !(dip_var > S(0))) return p.mag_dip_tol;
    const S k2 = p.mag_dip_sigmas * p.mag_dip_sigmas;
    return std::sqrt(p.mag_dip_tol * p.mag_dip_tol + k2 * dip_var);
  }

  /// The variance of the dip [rad^2] of the unit field m_n (navigation frame, at the attitude
  /// C_nb) that the filter's attitude error dtheta (body frame, q_true = q exp(dtheta), covariance
  /// P_att) gives: dtheta_n = C_nb dtheta turns m_n by dtheta_n x m_n, whose vertical component
  /// dm_z = dtheta_n,x m_y - dtheta_n,y m_x changes the dip d = asin(m_z) by dm_z / cos d, cos d =
  /// |(m_x, m_y)|: d_dip = a . dtheta_n with a = (m_y, -m_x, 0) / cos d, the tilt about the
  /// horizontal normal of the field's vertical plane. 0 for a vertical field (no direction), and
  /// 0 when the widening is off (widened()).
  static S dip_variance(const Params& p, const Mat3<S>& C_nb, const Vec3<S>& m_n, const Mat3<S>& P_att) {
    if (!widened(p)) return S(0);
    const S h2 = m_n[0] * m_n[0] + m_n[1] * m_n[1];
    if (!(h2 > S(1e-12))) return S(0);
    const Vec3<S> a_b = C_nb.transpose() * (Vec3<S>(m_n[1], -m_n[0], S(0)) / std::sqrt(h2));
    return a_b.dot(P_att * a_b);
  }

  /// The dip (inclination, positive down) of a unit field in the navigation frame [rad].
  static S dip(const Vec3<S>& m_n) { return std::asin(std::max(S(-1), std::min(S(1), m_n[2]))); }

  /// The difference d - d_ref of the dip d of a unit field m_n (navigation frame) and d_ref of
  /// the unit reference ref = [cos d_ref, 0, sin d_ref], as its cosine c and sine s, with no libm
  /// call: cos d = sqrt(1 - m_z^2) >= 0 (a dip lies in [-pi/2, pi/2]), sin d = m_z.
  static void dip_offset(const Vec3<S>& ref, const Vec3<S>& m_n, S& c, S& s) {
    const S z = std::max(S(-1), std::min(S(1), m_n[2]));
    const S h = std::sqrt(S(1) - z * z);
    c = h * ref[0] + z * ref[2];
    s = z * ref[0] - h * ref[2];
  }

  /// The dip test |d - d_ref| > tol (tol > 0), as cos(d - d_ref) < cos(tol): both dips lie in
  /// [-pi/2, pi/2], so |d - d_ref| <= pi, where the cosine decreases. cos(tol) by cos_sinc: no libm
  /// call for tol below 0.125 rad (double) or 0.25 rad (float).
  static bool dip_differs(const Vec3<S>& ref, const Vec3<S>& m_n, S tol) {
    if (!(tol < S(3.141592653589793))) return false;
    S c, s, ct, sinct;
    dip_offset(ref, m_n, c, s);
    quat::cos_sinc(tol * tol, ct, sinct);
    return c < ct;
  }
};

}  // namespace quatnav
