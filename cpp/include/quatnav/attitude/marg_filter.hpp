// quatnav: MARG attitude filter by Gauss-Newton iteration, blended with gyro integration, with
// the accelerometer corrected for the vehicle's acceleration by GPS (Shin & Hong, "Small attitude
// sensor development using quaternion and attitude error correction"; called paper 001 in the
// docs).
//
// Per sample:
//  1. predict: q- = q * exp((w - b) T)  (gyro integration, the 1/2 q * w term of eq. 6);
//  2. the measured unit vectors y0 = [m0_b; n0_b] and their navigation-frame references
//     [m_n; n_n] (eq. 1, 3); the accelerometer is first corrected with the GPS antenna
//     acceleration and the lever-arm terms (eq. 7, see below);
//  3. Gauss-Newton from q-: eps = y0 - y(q) (eq. 3), X = dy/dq (eq. 4),
//     dq = (X^T X)^-1 X^T eps (eq. 5), q <- q + dq, until |dq| < gn_tol or gn_max_iter steps;
//  4. blend (eq. 6): q+ = normalize(q- + alpha (q_GN - q-)), alpha = 1 - exp(-k T);
//  5. optionally the gyro bias: b <- b - k_b T e, e = 2 vec(conj(q-) * q_GN) (body frame).
//
// Deviations from the paper, each deliberate:
//  * eq. (5) needs X of full column rank 4. In 6D mode (no magnetometer) X is 3x4 and X^T X is
//    singular (rotation about gravity is unobservable); we use the Moore-Penrose pseudo-inverse
//    of that case, dq = X^T (X X^T)^-1 eps, the minimum-norm step, which leaves the heading
//    untouched.
//  * eq. (6) is a continuous-time blend q_dot = 1/2 q * w + k dq. Integrated over one step with
//    q_GN held, its correction part is q <- q + (1 - exp(-k T)) (q_GN - q), which equals k T dq
//    to first order and never overshoots (alpha < 1 for any T); the gyro part is integrated
//    exactly for a rate constant over the step.
//  * eq. (7) as printed mixes frames and drops terms. With d = r_g - r_i the lever arm from the
//    IMU to the GPS antenna in the body frame, rigid-body kinematics give
//        a_g_n = a_i_n + C_nb (w_dot x d + w x (w x d)),
//    and the accelerometer senses f_b = C_bn (a_i_n - g_n). Hence
//        f_b + w_dot x d + w x (w x d) = C_bn (a_g_n - g_n),                        (7')
//    i.e. measurement side n0_b = unit(f_b + w_dot x d + w x (w x d)) and reference side
//    n_n = unit(a_g_n - g_n). The printed eq. (7) (i) multiplies the body-frame lever arm by
//    R = R^{n->b} inside the navigation-frame bracket (it must be R^T = C_nb), (ii) loses one
//    w~ of the centripetal term w~ w~^T d in its third line, and (iii) writes the angular
//    acceleration term as w~ d instead of w_dot~ d. We use (7'); a_g_n comes from differences of
//    GPS velocity, low-pass filtered (time constant gps_acc_tau) and held between fixes; w_dot
//    from differences of the bias-corrected gyro, low-pass filtered (omega_dot_tau). The Earth
//    rate in w (7e-5 rad/s) is neglected in the lever-arm terms.
//  * The paper scales by 1/g; we normalize both sides of each vector pair instead, so that the
//    Gauss-Newton residual compares directions only, as in eq. (3) for the magnetic field.
//
// The robustness parts of the other attitude filters (parts/*.hpp), with the same parameter
// and state names and flags; paper() switches them off (the plain filter of paper 001):
//  * rest (rest.hpp): the filter has no covariance, so at rest the low-passed gyro of the rest
//    test is taken as the gyro bias (flag kAtRest);
//  * the accelerometer part (acc_filter.hpp): the low-passed sample replaces the raw one, a sample
//    it rejects skips the whole Gauss-Newton update (status Rejected, flag kAccRejected; the
//    gyro integration goes on), its adaptive noise lowers the gain, k / (1 + sigma_add). While
//    eq. (7) corrects the sample with the GPS acceleration the raw sample is used (the part
//    still follows the signal); its `gravity` is the g of eq. (7);
//  * the magnetometer part (mag_disturbance.hpp): a disturbed field is not used, the update
//    runs on gravity alone (6D mode: the heading is left as the gyro carried it; flag
//    kMagRejected).
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "attitude.hpp"
#include "parts/parts.hpp"
#include "../core/fields.hpp"
#include "../core/quaternion.hpp"
#include "../core/types.hpp"

namespace quatnav {

/// Parameters of MargFilter. Every field has its unit and default.
// X(type, name, default, unit, doc): each field once (core/fields.hpp).
#define QUATNAV_MARG_PARAMS(X)                                                                          \
  X(S, gain, S(1), "1/s", "k of eq. (6): pull towards the Gauss-Newton attitude (0: gyro only)")         \
  X(S, bias_gain, S(0), "1/s^2", "gyro-bias integral gain (0: no bias estimate)")                        \
  X(int, gn_max_iter, 3, "1", "Gauss-Newton iterations per update, at most")                             \
  X(S, gn_tol, S(1e-6), "1", "the iteration stops when |dq| is below it")                                \
  X(Vec3<S>, lever_arm_b, Vec3<S>::Zero(), "m", "GPS antenna relative to the IMU, body FRD")             \
  X(bool, gps_correction, true, "-", "apply eq. (7) when a GPS acceleration is available")               \
  X(S, gps_acc_tau, S(0.05), "s", "low-pass time constant of the GPS acceleration")                      \
  X(S, omega_dot_tau, S(0.1), "s", "low-pass time constant of the angular acceleration")                 \
  X(S, gps_timeout, S(0.5), "s", "a GPS acceleration older than this is not used")                       \
  X(S, max_dt, S(1), "s", "longest accepted IMU step")                                                   \
  /* the filter's navigation frame is NED with x along magnetic north (the reference field is         \
     [m_x, 0, m_z]); GPS velocities are in true NED and are rotated by -declination about down before  \
     use. Left at 0 while the field points 8 deg off true north, a 2 m/s^2 turn acceleration is         \
     misplaced by 0.3 m/s^2. */                                                                        \
  X(S, declination, S(0), "rad",                                                                         \
    "magnetic declination, east of true north (GPS velocities are rotated into the magnetic frame)")     \
  /* the accelerometer part's gravity is the g of eq. (7): 9.80665 m/s^2 here, and its low-pass is     \
     shorter (detail::marg_acc_defaults) */                                                             \
  X(AccFilterParams<S>, acc, detail::marg_acc_defaults<S>(), "-", "accelerometer low-pass, rejection, adaptive noise") \
  X(MagDisturbanceParams<S>, mag, MagDisturbanceParams<S>(), "-", "reference field and disturbance tests") \
  X(RestParams<S>, rest, RestParams<S>(), "-", "rest detection and zero-rate measurement")

namespace detail {
/// The accelerometer part's defaults in MargFilter: eq. (7)'s g, and a 1 s low-pass instead of 3 s.
/// MargFilter has no gyro-bias covariance to shrink the low-pass with (AccFilter::time_constant),
/// so its low-pass frame drifts by the whole bias error over acc_lp_tau. 1 s was chosen on BROAD
/// and the simulated rotation of `quatnav demo` together (docs/broad.md, "The accelerometer
/// low-pass of EulerEKF and MargFilter"): mean total 3.21 deg on BROAD (2.93 with 3 s) and a third
/// of the 3 s error under a 1.5 deg/s gyro bias.
template <class S> AccFilterParams<S> marg_acc_defaults() {
  AccFilterParams<S> p;
  p.gravity = S(9.80665);
  p.acc_lp_tau = S(1);
  return p;
}
}  // namespace detail

template <class S> struct MargFilterParams {
  QUATNAV_FIELDS(MargFilterParams, QUATNAV_MARG_PARAMS)

  /// The plain filter of paper 001: every robustness part off.
  static MargFilterParams paper() {
    MargFilterParams p;
    AccFilter<S>::off(p.acc);
    MagDisturbance<S>::off(p.mag);
    Rest<S>::off(p.rest);
    return p;
  }
};

#define QUATNAV_MARG_STATE(X)                                                                           \
  X(Quat<S>, q_nb, quat::identity<S>(), "1", "attitude q_nb [w, x, y, z]")                               \
  X(Vec3<S>, gyro_bias, Vec3<S>::Zero(), "rad/s", "gyro bias")                                          \
  X(Vec3<S>, omega_b, Vec3<S>::Zero(), "rad/s", "last bias-corrected body rate")                         \
  X(Vec3<S>, omega_dot_b, Vec3<S>::Zero(), "rad/s^2", "low-passed angular acceleration")                 \
  X(Vec3<S>, gps_vel_n, Vec3<S>::Zero(), "m/s", "last GPS velocity, magnetic NED")                       \
  X(Vec3<S>, gps_acc_n, Vec3<S>::Zero(), "m/s^2", "low-passed GPS antenna acceleration, magnetic NED")   \
  X(double, gps_t, 0.0, "s", "time of the last GPS fix (double for every S: GPS and Unix clocks)")      \
  X(S, time_since_gps, S(0), "s", "time since the last GPS fix")                                        \
  X(S, time_since_update, S(0), "s", "time integrated since the last update")                           \
  X(int, gps_fixes, 0, "-", "0: none, 1: velocity only, 2: acceleration")                               \
  X(bool, omega_set, false, "-", "omega_b holds a rate (w_dot can be formed)")                          \
  X(bool, initialized, false, "-", "the filter has a state")                                            \
  X(S, dt_last, S(0), "s", "step of the last predict")                                                  \
  X(MagDisturbanceState<S>, mag, MagDisturbanceState<S>(), "-", "reference field and disturbance tests") \
  X(AccFilterState<S>, acc, AccFilterState<S>(), "-", "accelerometer low-pass and rejection timer")      \
  X(RestState<S>, rest, RestState<S>(), "-", "rest detection")

/// The complete filter state; state()/set_state() round-trip exactly.
template <class S> struct MargFilterState {
  QUATNAV_FIELDS(MargFilterState, QUATNAV_MARG_STATE)
};

/// The outcome of one Gauss-Newton update.
template <class S> struct MargUpdateResult {
  Status status = Status::NotInitialized;
  int iterations = 0;          ///< Gauss-Newton steps taken
  bool converged = false;      ///< |dq| fell below gn_tol
  bool gps_corrected = false;  ///< the accelerometer was corrected with eq. (7)
  S residual = S(0);           ///< |eps| at the predicted attitude (eq. 3)
  S residual_final = S(0);     ///< |eps| at the Gauss-Newton attitude
  Vec3<S> correction = Vec3<S>::Zero();  ///< rotation applied to q-, body frame [rad]
  bool accepted() const { return status == Status::Ok; }
};

namespace detail {

/// eq. (1)-(2): y = R^{n->b}(q) r for a reference vector r, in the homogeneous quadratic form of
/// eq. (2) (for a non-unit q it is |q|^2 times the rotation):
///   y = (q0^2 - |v|^2) r + 2 (v.r) v - 2 q0 (v x r),  v = [q1, q2, q3].
template <class S> Vec3<S> marg_h(const Quat<S>& q, const Vec3<S>& r) {
  const S q0 = q[0];
  const Vec3<S> v(q[1], q[2], q[3]);
  return (q0 * q0 - v.squaredNorm()) * r + S(2) * v.dot(r) * v - S(2) * q0 * v.cross(r);
}

/// eq. (4): X = dy/dq (3x4) of marg_h.
template <class S> Mat34<S> marg_jacobian(const Quat<S>& q, const Vec3<S>& r) {
  const S q0 = q[0];
  const Vec3<S> v(q[1], q[2], q[3]);
  Mat34<S> X;
  X.col(0) = S(2) * q0 * r - S(2) * v.cross(r);
  X.template rightCols<3>() = S(2) * (v * r.transpose() - r * v.transpose() +
                                      v.dot(r) * Mat3<S>::Identity() + q0 * quat::skew(r));
  return X;
}

/// A Cholesky factor fit for solving: success and a pivot ratio above sqrt(epsilon), i.e. a
/// condition number below about 1/epsilon (rank-deficient X, e.g. a reference field parallel to
/// gravity, is refused rather than solved into a huge step).
template <class Llt> bool well_conditioned(const Llt& llt) {
  using S = typename Llt::Scalar;
  if (llt.info() != Eigen::Success) return false;
  const auto d = llt.matrixLLT().diagonal();
  return d.allFinite() && d.minCoeff() > d.maxCoeff() * std::sqrt(std::numeric_limits<S>::epsilon());
}

/// Gauss-Newton iteration of eq. (3)-(5) on K vector pairs (K = 1: gravity only, K = 2: field
/// and gravity). meas and refs hold unit vectors in their columns (body and navigation frame).
/// Starts from q0; writes the (unnormalized) solution, the step count and convergence.
/// Returns SolveFailed (outputs meaningless) when the normal equations are singular.
template <class S, int K>
Status marg_gauss_newton(const Quat<S>& q0, const Mat<S, 3, K>& meas, const Mat<S, 3, K>& refs,
                         int max_iter, S tol, Quat<S>& q_out, int& iterations, bool& converged) {
  constexpr int M = 3 * K;
  Quat<S> q = q0;
  q_out = q0;
  iterations = 0;
  converged = false;
  for (int it = 0; it < max_iter; ++it) {
    Vec<S, M> eps;
    Mat<S, M, 4> X;
    for (int j = 0; j < K; ++j) {
      const Vec3<S> r = refs.col(j);
      eps.template segment<3>(3 * j) = meas.col(j) - marg_h(q, r);   // eq. (3)
      X.template block<3, 4>(3 * j, 0) = marg_jacobian(q, r);          // eq. (4)
    }
    Quat<S> dq;
    if constexpr (M >= 4) {
      // eq. (5): dq = (X^T X)^-1 X^T eps, by a Cholesky solve.
      const Eigen::LLT<Mat4<S>> llt(X.transpose() * X);
      if (!well_conditioned(llt)) return Status::SolveFailed;
      dq = llt.solve(X.transpose() * eps);
    } else {
      // 6D mode: the minimum-norm pseudo-inverse X^T (X X^T)^-1 (see the header comment).
      const Eigen::LLT<Mat<S, M, M>> llt(X * X.transpose());
      if (!well_conditioned(llt)) return Status::SolveFailed;
      dq = X.transpose() * llt.solve(eps);
    }
    if (!dq.allFinite() || !(dq.norm() < S(2))) return Status::SolveFailed;
    q += dq;
    ++iterations;
    if (dq.norm() < tol) {
      converged = true;
      break;
    }
  }
  q_out = q;
  return Status::Ok;
}

/// |eps| of eq. (3) at q.
template <class S, int K>
S marg_residual(const Quat<S>& q, const Mat<S, 3, K>& meas, const Mat<S, 3, K>& refs) {
  S s = S(0);
  for (int j = 0; j < K; ++j) s += (meas.col(j) - marg_h(q, Vec3<S>(refs.col(j)))).squaredNorm();
  return std::sqrt(s);
}

/// eq. (7'): the accelerometer side f_b + w_dot x d + w x (w x d) [m/s^2].
template <class S>
Vec3<S> marg_lever_corrected(const Vec3<S>& f_b, const Vec3<S>& omega_b, const Vec3<S>& omega_dot_b,
                             const Vec3<S>& d_b) {
  return f_b + omega_dot_b.cross(d_b) + omega_b.cross(omega_b.cross(d_b));
}

}  // namespace detail

template <class S> class MargFilter {
 public:
  using Scalar = S;
  using Params = MargFilterParams<S>;
  using State = MargFilterState<S>;
  using Result = MargUpdateResult<S>;

  MargFilter() = default;
  explicit MargFilter(const Params& p) : params_(p) {}

  /// True when every parameter is in its range (the constructor does not check).
  static bool valid_params(const Params& p) {
    return p.gain >= S(0) && p.bias_gain >= S(0) && p.gn_max_iter >= 1 && p.gn_tol > S(0) &&
           p.acc.gravity > S(0) && p.lever_arm_b.allFinite() && p.gps_acc_tau >= S(0) &&
           p.omega_dot_tau >= S(0) && p.gps_timeout > S(0) && p.max_dt > S(0) && std::isfinite(p.declination) &&
           std::isfinite(p.gain) && std::isfinite(p.bias_gain) && std::isfinite(p.gps_acc_tau) &&
           std::isfinite(p.omega_dot_tau) && std::isfinite(p.acc.gravity);
  }

  const Params& params() const { return params_; }
  const State& state() const { return st_; }
  const Quat<S>& quat() const { return st_.q_nb; }
  const Vec3<S>& bias() const { return st_.gyro_bias; }
  bool initialized() const { return st_.initialized; }
  /// Flags of the last sample beyond the update status (kAtRest, kAccRejected, kMagRejected).
  std::uint32_t extra_flags() const { return flags_; }
  bool at_rest() const { return Rest<S>::at_rest(params_.rest, st_.rest); }
  /// The GPS antenna acceleration eq. (7) would use now, if any [m/s^2].
  bool gps_acc_available() const {
    return params_.gps_correction && st_.gps_fixes >= 2 && st_.time_since_gps <= params_.gps_timeout;
  }
  const Vec3<S>& gps_acc_n() const { return st_.gps_acc_n; }

  /// Restore a state previously read with state(). Refused when the quaternion is not unit
  /// length (InvalidArgument) or anything is non-finite (NonFinite).
  Status set_state(const State& s) {
    if (!detail::fields_finite(s)) return Status::NonFinite;
    if (std::abs(s.q_nb.norm() - S(1)) > S(1e-3) || s.gps_fixes < 0 || s.gps_fixes > 2)
      return Status::InvalidArgument;
    st_ = s;
    return Status::Ok;
  }

  /// Set the normalized reference field from the dip (inclination) angle, positive down [rad].
  void set_mag_dip(S dip) { st_.mag.ref.fix(dip); }

  /// Initialize from one accelerometer (and optionally magnetometer) sample.
  Status initialize(const Vec3<S>& acc) { return init_impl(acc, nullptr); }
  Status initialize(const Vec3<S>& acc, const Vec3<S>& mag) { return init_impl(acc, &mag); }

  /// Start from a given attitude and gyro bias.
  Status reset(const Quat<S>& q, const Vec3<S>& bias) {
    if (!q.allFinite() || !bias.allFinite()) return Status::NonFinite;
    const S n = q.norm();  // overflows to inf for huge finite components: refused
    if (!(n > S(0.5)) || !std::isfinite(n)) return Status::InvalidArgument;
    st_.q_nb = q / n;
    st_.gyro_bias = bias;
    st_.time_since_update = S(0);
    st_.initialized = true;
    return Status::Ok;
  }

  /// Gyro integration over dt [s] with one gyro sample [rad/s] (the 1/2 q * w term of eq. 6);
  /// also forms the angular acceleration for eq. (7).
  Status predict(const Vec3<S>& gyr, S dt) {
    if (!st_.initialized) return Status::NotInitialized;
    if (!gyr.allFinite()) return Status::NonFinite;
    if (!(dt > S(0)) || !(dt <= params_.max_dt)) return Status::InvalidDt;
    const Vec3<S> w = gyr - st_.gyro_bias;
    const Quat<S> q_new = quat::mul(st_.q_nb, quat::from_rotvec(Vec3<S>(w * dt)));
    Vec3<S> wdot = st_.omega_dot_b;
    if (st_.omega_set) {
      const Vec3<S> raw = (w - st_.omega_b) / dt;
      wdot += detail::lowpass_weight(dt, params_.omega_dot_tau) * (raw - wdot);
    }
    if (!q_new.allFinite() || !wdot.allFinite()) return Status::NumericalFailure;
    st_.q_nb = q_new / q_new.norm();
    st_.omega_b = w;
    st_.omega_dot_b = wdot;
    st_.omega_set = true;
    st_.time_since_gps += dt;
    st_.time_since_update += dt;
    st_.dt_last = dt;
    flags_ = 0;
    AccFilter<S>::predict_rate(params_.acc, st_.acc, w, dt);
    Rest<S>::predict(params_.rest, st_.rest, gyr, dt);
    return Status::Ok;
  }

  /// One GPS velocity fix v_true_n [m/s] (of the antenna, true NED) valid at time t [s] (any clock, strictly
  /// increasing from fix to fix; double whatever S, since a float time on a GPS or Unix clock
  /// resolves 64-128 s). The antenna acceleration of eq. (7) is the difference of
  /// successive fixes, low-pass filtered, held until the next fix. A gap longer than gps_timeout
  /// restarts the differencing.
  Status update_gps_velocity(const Vec3<S>& v_true_n, double t) {
    if (!v_true_n.allFinite() || !std::isfinite(t)) return Status::NonFinite;
    // True NED -> the filter's magnetic NED: rotate by -declination about down.
    const S cd = std::cos(params_.declination), sd = std::sin(params_.declination);
    const Vec3<S> v_n(cd * v_true_n[0] + sd * v_true_n[1], -sd * v_true_n[0] + cd * v_true_n[1], v_true_n[2]);
    // Work on copies: a result that overflows (a huge velocity step over a tiny dt) is refused
    // and leaves the state as it was.
    int fixes = st_.gps_fixes;
    Vec3<S> acc_n = st_.gps_acc_n;
    if (fixes == 0) {
      fixes = 1;
    } else {
      const double dt_fix = t - st_.gps_t;  // in double: the two times may be 1e9 s
      if (!(dt_fix > 0.0)) return Status::InvalidDt;
      const S dt = S(dt_fix);
      if (dt > params_.gps_timeout) {
        fixes = 1;
      } else {
        const Vec3<S> raw = (v_n - st_.gps_vel_n) / dt;
        if (fixes == 1) {
          acc_n = raw;
        } else {
          acc_n += detail::lowpass_weight(dt, params_.gps_acc_tau) * (raw - acc_n);
        }
        fixes = 2;
      }
    }
    if (!v_n.allFinite() || !acc_n.allFinite()) return Status::NumericalFailure;
    st_.gps_fixes = fixes;
    st_.gps_acc_n = acc_n;
    st_.gps_vel_n = v_n;
    st_.gps_t = t;
    st_.time_since_gps = S(0);
    return Status::Ok;
  }

  /// Gauss-Newton update with the accelerometer only (6D mode; heading is not observed).
  /// acc: specific force [m/s^2] (units matter only when eq. 7 is applied).
  Result update_acc(const Vec3<S>& acc) { return update_parts(acc, nullptr); }

  /// Gauss-Newton update with accelerometer [m/s^2] and magnetometer (any unit), eq. (1)-(6).
  Result update_acc_mag(const Vec3<S>& acc, const Vec3<S>& mag) { return update_parts(acc, &mag); }

 private:
  Status init_impl(const Vec3<S>& acc, const Vec3<S>* mag) {
    if (!acc.allFinite() || (mag && !mag->allFinite())) return Status::NonFinite;
    Quat<S> q;
    Vec3<S> mref = st_.mag.ref.mag_ref;
    if (!detail::attitude_from_acc_mag(acc, mag, q, mref)) return Status::ZeroNorm;
    st_.q_nb = q;
    st_.gyro_bias.setZero();
    st_.dt_last = S(0);
    // The parts start afresh; the reference field is learned from this sample (unless the user fixed it).
    restart_parts<S>(params_, st_, mag, mref);
    flags_ = 0;
    st_.time_since_update = S(0);
    st_.initialized = true;
    return Status::Ok;
  }

  /// The parts around the Gauss-Newton update (see the top of this file): the rest test, the
  /// accelerometer part's sample, the magnetometer part's tests, update_impl, their finish().
  Result update_parts(const Vec3<S>& acc, const Vec3<S>* mag) {
    Result res;
    if (!st_.initialized) return res;
    if (!acc.allFinite() || (mag && !mag->allFinite())) {
      res.status = Status::NonFinite;
      return res;
    }
    // Bad input leaves the state untouched: checked before the parts follow the sample.
    Vec3<S> m_unit = Vec3<S>::Zero();
    res.status = detail::unit_vector(acc, m_unit);
    if (res.status == Status::Ok && mag) res.status = detail::unit_vector(*mag, m_unit);
    if (res.status != Status::Ok) return res;
    // A reading whose norm overflows (finite components beyond the type's range) is refused like
    // a non-finite one: the parts keep norms and low-passes in their state.
    if (!std::isfinite(acc.norm()) || (mag && !std::isfinite(mag->norm()))) {
      res.status = Status::NonFinite;
      return res;
    }
    const S dt = st_.dt_last;
    // The parts follow the sample before the update; an update that fails (SolveFailed,
    // NumericalFailure) leaves the state as it was, so what they took is put back.
    const RestState<S> rest_before = st_.rest;
    const AccFilterState<S> acc_before = st_.acc;
    const MagDisturbanceState<S> mag_before = st_.mag;
    const Vec3<S> bias_before = st_.gyro_bias;
    const std::uint32_t flags_before = flags_;
    if (Rest<S>::update(params_.rest, st_.rest, acc, st_.gyro_bias, dt)) {
      // No covariance to weigh a zero-rate measurement with: the low-passed gyro is the bias.
      flags_ |= flags::kAtRest;
      st_.gyro_bias = st_.rest.gyr_lp;
    }
    const AccSample<S> in = AccFilter<S>::screen(params_.acc, st_.acc, acc, dt, S(0));
    const bool gps = gps_acc_available();
    MagSample<S> mc;
    mc.use = false;
    if (mag) {
      mc = MagDisturbance<S>::screen(params_.mag, st_.mag, mag->norm(), quat::rotate(st_.q_nb, m_unit), dt);
      if (!mc.use) flags_ |= flags::kMagRejected;
    }
    if (in.rejected && !gps) {
      res.status = Status::Rejected;
    } else {
      const Vec3<S>& a = gps ? acc : in.acc;
      const S gain = gps ? params_.gain : params_.gain / (S(1) + in.sigma_add);
      res = mc.use ? update_impl<2>(a, &m_unit, gain) : update_impl<1>(a, nullptr, gain);
      if (res.status != Status::Ok && res.status != Status::Rejected) {
        st_.rest = rest_before;
        st_.acc = acc_before;
        st_.mag = mag_before;
        st_.gyro_bias = bias_before;
        flags_ = flags_before;
        return res;
      }
    }
    AccFilter<S>::finish(params_.acc, st_.acc, res.status, dt);
    if (res.status == Status::Rejected) flags_ |= flags::kAccRejected;
    if (mc.use && res.status == Status::Rejected) {
      if (!mc.disturbed) st_.mag.ref = mc.before;  // the field was not used (the accelerometer was refused)
    } else if (mc.use) {
      MagDisturbance<S>::finish(params_.mag, st_.mag, mc, res.status, [&] { return Vec3<S>(quat::rotate(st_.q_nb, m_unit)); },
                                dt);
    }
    return res;
  }

  template <int K> Result update_impl(const Vec3<S>& acc, const Vec3<S>* mag, S gain) {
    Result res;
    // Gravity pair, corrected by eq. (7') when the GPS acceleration is available.
    Vec3<S> f = acc, ref_n(S(0), S(0), S(-1));
    res.gps_corrected = gps_acc_available();
    if (res.gps_corrected) {
      f = detail::marg_lever_corrected(acc, st_.omega_b, st_.omega_dot_b, params_.lever_arm_b);
      ref_n = st_.gps_acc_n - Vec3<S>(S(0), S(0), params_.acc.gravity);
    }
    Mat<S, 3, K> meas, refs;
    Vec3<S> u;
    res.status = detail::unit_vector(f, u);
    if (res.status != Status::Ok) return res;
    meas.col(K - 1) = u;
    res.status = detail::unit_vector(ref_n, u);
    if (res.status != Status::Ok) return res;
    refs.col(K - 1) = u;
    if constexpr (K == 2) {
      // The unit field; the reference learned from it by the magnetometer part's screen().
      meas.col(0) = *mag;
      refs.col(0) = MagDisturbance<S>::reference(st_.mag);
    }
    // Gauss-Newton from the predicted attitude, eq. (3)-(5).
    const Quat<S> q_pred = st_.q_nb;
    Quat<S> q_gn;
    res.status = detail::marg_gauss_newton<S, K>(q_pred, meas, refs, params_.gn_max_iter, params_.gn_tol,
                                                 q_gn, res.iterations, res.converged);
    if (res.status != Status::Ok) return res;
    res.residual = detail::marg_residual<S, K>(q_pred, meas, refs);
    res.residual_final = detail::marg_residual<S, K>(q_gn, meas, refs);
    const S n_gn = q_gn.norm();
    if (!(n_gn > S(0.5))) {
      res.status = Status::NumericalFailure;
      return res;
    }
    q_gn /= n_gn;
    // eq. (6), integrated over the time since the last update with q_GN held.
    const S T = st_.time_since_update;
    const S alpha = S(1) - std::exp(-gain * T);
    Quat<S> q_new = q_pred + alpha * (q_gn - q_pred);
    const S n_new = q_new.norm();
    if (!(n_new > S(0.5)) || !q_new.allFinite()) {
      res.status = Status::NumericalFailure;
      return res;
    }
    q_new /= n_new;
    Vec3<S> bias = st_.gyro_bias;
    if (params_.bias_gain > S(0)) {
      const Quat<S> e = quat::canonical(quat::mul(quat::conj(q_pred), q_gn));
      bias -= (params_.bias_gain * T * S(2)) * Vec3<S>(e[1], e[2], e[3]);
    }
    if (!bias.allFinite()) {
      res.status = Status::NumericalFailure;
      return res;
    }
    res.correction = quat::to_rotvec(quat::mul(quat::conj(q_pred), q_new));
    st_.q_nb = q_new;
    st_.gyro_bias = bias;
    st_.time_since_update = S(0);
    return res;
  }

  Params params_{};
  State st_{};
  std::uint32_t flags_ = 0;
};

/// Batch run of MargFilter over n IMU samples with GPS velocity fixes at their own times.
///
/// Inputs (row-major): t (n, IMU sample times [s], double for every S, as gps_t), dt (n, step
/// before each sample [s]), gyr
/// (n x 3, rad/s), acc (n x 3, m/s^2), mag (n x 3 or null; an all-NaN row means "no sample"),
/// gps_t (m, fix times [s], same clock as t, non-decreasing), gps_vel (m x 3, m/s NED; null when
/// m = 0). At sample k: every fix with gps_t <= t[k] not yet used is fed to
/// update_gps_velocity (held in between); then initialize (first sample) or predict + update.
/// Outputs (any may be null): quat (n x 4), bias (n x 3), gps_acc (n x 3: the antenna
/// acceleration used by eq. 7 at that sample, NaN when none), residual (n, |eps| before the
/// update), flags (n). Allocates nothing.
template <class S>
void run_marg_batch(MargFilter<S>& f, const double* t, const S* dt, const S* gyr, const S* acc, const S* mag,
                    std::size_t n, const double* gps_t, const S* gps_vel, std::size_t m, S* quat_out, S* bias_out,
                    S* gps_acc_out, S* residual_out, std::uint32_t* flags_out) {
  std::size_t j = 0;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  for (std::size_t k = 0; k < n; ++k) {
    while (j < m && gps_t[j] <= t[k]) {
      f.update_gps_velocity(Vec3<S>(Eigen::Map<const Vec3<S>>(gps_vel + 3 * j)), gps_t[j]);
      ++j;
    }
    const Vec3<S> a = Eigen::Map<const Vec3<S>>(acc + 3 * k);
    bool have_mag = mag != nullptr;
    if (have_mag) {
      const S* mk = mag + 3 * k;
      have_mag = !(std::isnan(mk[0]) && std::isnan(mk[1]) && std::isnan(mk[2]));
    }
    std::uint32_t fl = have_mag ? 0u : flags::kNoMag;
    S resid = nan;
    bool used_gps = false;
    if (!f.initialized()) {
      const Status s = have_mag ? f.initialize(a, Vec3<S>(Eigen::Map<const Vec3<S>>(mag + 3 * k)))
                                : f.initialize(a);
      fl |= (s == Status::Ok) ? flags::kInitialized : (flags::kAccSkipped | flags::kPredictSkipped);
    } else {
      if (f.predict(Vec3<S>(Eigen::Map<const Vec3<S>>(gyr + 3 * k)), dt[k]) != Status::Ok)
        fl |= flags::kPredictSkipped;
      MargUpdateResult<S> r = have_mag ? f.update_acc_mag(a, Vec3<S>(Eigen::Map<const Vec3<S>>(mag + 3 * k)))
                                       : f.update_acc(a);
      if (r.status == Status::Ok) {
        resid = r.residual;
        used_gps = r.gps_corrected;
        if (r.gps_corrected) fl |= flags::kGpsCorrected;
        if (!r.converged) fl |= flags::kGnNotConverged;
      } else if (r.status == Status::Rejected) {
        // rejected by the accelerometer part: kAccRejected (extra_flags)
      } else if (r.status == Status::SolveFailed || r.status == Status::NumericalFailure) {
        fl |= flags::kSolveFailed | flags::kAccSkipped | (have_mag ? flags::kMagSkipped : 0u);
      } else {
        fl |= flags::kAccSkipped | (have_mag ? flags::kMagSkipped : 0u);
      }
    }
    fl |= f.extra_flags();
    if (quat_out) Eigen::Map<Vec4<S>>(quat_out + 4 * k) = f.quat();
    if (bias_out) Eigen::Map<Vec3<S>>(bias_out + 3 * k) = f.bias();
    if (gps_acc_out)
      Eigen::Map<Vec3<S>>(gps_acc_out + 3 * k) = used_gps ? f.gps_acc_n() : Vec3<S>::Constant(nan);
    if (residual_out) residual_out[k] = resid;
    if (flags_out) flags_out[k] = fl;
  }
}

}  // namespace quatnav
