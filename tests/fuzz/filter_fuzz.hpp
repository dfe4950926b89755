// quatnav: the generic fault-injection driver shared by the libFuzzer targets (tests/fuzz/) and
// the GoogleTest that replays random inputs under ctest (tests/cpp/test_robustness/).
//
// A byte string is read as: filter parameters (valid, spread over decades), then a sequence of
// operations (initialize, predict, updates, reset, set_state with arbitrary content), each with
// arbitrary scalars: NaN, +-inf, +-0, huge, denormal, epsilon, raw bit patterns and ordinary
// values. After every operation the driver checks the contract of every filter:
//   * a status other than Ok or Rejected left the state bit for bit as it was;
//   * after Ok (or Rejected), the whole state is finite, the quaternion has unit norm, P is symmetric,
//     and it is a state set_state() takes back (a fresh filter with the same parameters accepts it);
//   * an accepted update reports a finite innovation, innovation covariance and NIS.
// A violation calls `fail(message)` (abort in the fuzzer, a test failure under GoogleTest).
//
// Adding a filter: one `FuzzAdapter<Filter<S>>` specialization with `params`, `same`, `healthy`
// and `step` (its operations), then one line in each fuzz target / test.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include <quatnav/quatnav.hpp>

namespace quatnav_fuzz {
using namespace quatnav;

/// Reads typed values from the fuzzer's bytes; past the end everything reads as zero bytes.
struct Reader {
  const std::uint8_t* p;
  std::size_t n;
  Reader(const std::uint8_t* data, std::size_t size) : p(data), n(size) {}
  bool empty() const { return n == 0; }
  std::uint8_t byte() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
  template <class T> T raw() {
    unsigned char b[sizeof(T)] = {};
    for (auto& c : b) c = byte();
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
  /// An arbitrary scalar, with the values that break numerical code over-represented.
  template <class S> S scalar() {
    using L = std::numeric_limits<S>;
    switch (byte() % 20) {
      case 0: return S(0);
      case 1: return -S(0);
      case 2: return L::quiet_NaN();
      case 3: return L::infinity();
      case 4: return -L::infinity();
      case 5: return L::max();
      case 6: return -L::max();
      case 7: return L::denorm_min();
      case 8: return L::min();
      case 9: return L::epsilon();
      case 10: return S(1e30f);
      case 11: return raw<S>();  // any bit pattern (signalling NaNs included)
      case 12: return S(raw<std::int8_t>()) / S(1000);
      default: return S(raw<std::int16_t>()) / S(256);  // ordinary values in [-128, 128)
    }
  }
  /// A positive finite parameter spread over decades around `typical`.
  template <class S> S positive(S typical) {
    const int e = int(byte() % 9) - 4;  // 1e-4 .. 1e4 times typical
    return typical * S(std::pow(10.0, e));
  }
  template <class S> Vec3<S> vec3() { return Vec3<S>(scalar<S>(), scalar<S>(), scalar<S>()); }
  /// A measurement: mostly a plausible sensor vector (so the filter gets deep), else arbitrary.
  template <class S> Vec3<S> reading(const Vec3<S>& typical) {
    const std::uint8_t k = byte() % 4;
    if (k == 0) return vec3<S>();
    const Vec3<S> noise(S(raw<std::int8_t>()), S(raw<std::int8_t>()), S(raw<std::int8_t>()));
    return typical + noise * (k == 1 ? S(0.001) : k == 2 ? S(0.05) : S(1)) * typical.norm() / S(128);
  }
};

template <class T> bool bits_equal(const T& a, const T& b) {
  return std::memcmp(static_cast<const void*>(&a), static_cast<const void*>(&b), sizeof(T)) == 0;
}

template <class S, int N> bool symmetric(const Mat<S, N, N>& P) { return P == P.transpose(); }

/// Every field of a struct declared with QUATNAV_FIELDS bit for bit (nested ones field by field,
/// so that padding does not count), but the one named `skip`.
template <class T> bool fields_bits_equal(const T& a, const T& b, const char* skip = nullptr) {
  bool eq = true;
  T::for_each_member([&](const FieldInfo& info, auto member) {
    if (skip && std::strcmp(info.name, skip) == 0) return;
    using M = std::remove_cv_t<std::remove_reference_t<decltype(a.*member)>>;
    if constexpr (has_fields_v<M>)
      eq = eq && fields_bits_equal(a.*member, b.*member);
    else
      eq = eq && bits_equal(a.*member, b.*member);
  });
  return eq;
}

template <class S> bool same_mag(const MagRef<S>& a, const MagRef<S>& b) {
  return bits_equal(a.mag_ref, b.mag_ref) && bits_equal(a.mag_sin_dip_sum, b.mag_sin_dip_sum) &&
         a.mag_ref_count == b.mag_ref_count && a.mag_ref_fixed == b.mag_ref_fixed;
}

/// Every state a filter keeps is one it takes back: a fresh filter with the same parameters
/// accepts it through set_state() (its checks: every field finite, the quaternion of unit norm, P
/// exactly symmetric with a non-negative diagonal, the filter's own ranges). The last check of
/// every adapter's `healthy`.
template <class F> bool taken_back(const F& f, std::string& why) {
  F g(f.params());
  if (g.set_state(f.state()) != Status::Ok) return why = "a state set_state refuses", false;
  return true;
}

template <class F> struct FuzzAdapter;  // one specialization per filter

/// What a step reported: its status and, for updates, whether the outputs are finite.
struct StepOutcome {
  Status status = Status::Ok;
  bool outputs_finite = true;
  const char* op = "";
  /// A documented exception to "not Ok leaves the state": GpsInsFilter records an aid used for
  /// its initialization (compass heading, GPS course, altimeter height) and returns
  /// NotInitialized. The state must still be healthy afterwards.
  bool may_record = false;
};

template <class S, int M> StepOutcome outcome(const UpdateResult<S, M>& r, const char* op) {
  StepOutcome o{r.status, true, op};
  if (r.status == Status::Ok)
    o.outputs_finite = r.innovation.allFinite() && r.innovation_cov.allFinite() && std::isfinite(r.nis);
  return o;
}

/// mag_ref_samples, in the magnetometer part's parameters where the filter composes it.
template <class P, class = void> struct has_mag_part : std::false_type {};
template <class P> struct has_mag_part<P, std::void_t<decltype(std::declval<P&>().mag)>> : std::true_type {};
template <class P> std::uint32_t& mag_ref_samples(P& p) {
  if constexpr (has_mag_part<P>::value) {
    return p.mag.mag_ref_samples;
  } else {
    return p.mag_ref_samples;
  }
}

/// The EKF attitude filters (QuaternionEKFPaper, EulerEKF) share their operations.
template <class F> struct AttitudeOps {
  using S = typename F::Scalar;
  static typename F::Params params(Reader& r) {
    typename F::Params p;
    p.gyro_noise = r.positive<S>(p.gyro_noise);
    p.gyro_bias_noise = r.positive<S>(p.gyro_bias_noise);
    p.acc_sigma = r.positive<S>(p.acc_sigma);
    p.mag_sigma = r.positive<S>(p.mag_sigma);
    p.init_att_sigma = r.positive<S>(p.init_att_sigma);
    p.init_gyro_bias_sigma = r.positive<S>(p.init_gyro_bias_sigma);
    mag_ref_samples(p) = 1u + r.byte();
    p.max_dt = r.positive<S>(p.max_dt);
    p.gyro_range = (r.byte() & 1) ? r.positive<S>(S(35)) : S(0);
    p.acc_range = (r.byte() & 1) ? r.positive<S>(S(160)) : S(0);
    p.cov_floor = (r.byte() & 1) ? r.positive<S>(S(1e-12)) : S(0);
    return p;
  }
  /// Operations 0..6 common to both filters.
  static StepOutcome common_step(F& f, Reader& r, int op) {
    const Vec3<S> g_b(S(0.3), S(-0.2), S(-9.8)), m_b(S(20), S(2), S(43)), w_b(S(0.1), S(-0.05), S(0.2));
    switch (op) {
      case 0: return {f.initialize(r.reading<S>(g_b)), true, "initialize(acc)"};
      case 1: {
        const Vec3<S> a = r.reading<S>(g_b), m = r.reading<S>(m_b);
        return {f.initialize(a, m), true, "initialize(acc, mag)"};
      }
      case 2: case 3: {
        const Vec3<S> w = r.reading<S>(w_b);
        const S dt = (r.byte() & 1) ? S(0.01) : r.scalar<S>();
        return {f.predict(w, dt), true, "predict"};
      }
      case 4: {
        const Vec3<S> a = r.reading<S>(g_b);
        return outcome(f.update_acc(a, (r.byte() & 3) == 0 ? r.scalar<S>() : S(0)), "update_acc");
      }
      case 5: {
        const Vec3<S> m = r.reading<S>(m_b);
        return outcome(f.update_mag(m, (r.byte() & 3) == 0 ? r.scalar<S>() : S(0)), "update_mag");
      }
      default: f.set_mag_dip(S(0.5) + S(r.raw<std::int8_t>()) / S(256)); return {Status::Ok, true, "set_mag_dip"};
    }
  }
};

/// The quaternion attitude EKFs (QuaternionEKFPaper: 7 states, QuaternionEKF: 6) share the health
/// test of their estimate and the arbitrary states given to set_state and reset.
template <class F, int N> struct QuaternionStateOps : AttitudeOps<F> {
  using S = typename F::Scalar;
  using State = typename F::State;
  static bool healthy(const F& f, std::string& why) {
    const State& s = f.state();
    // the estimate (the parts' low-passes and timers follow the input, which may be huge)
    if (!s.q_nb.allFinite() || !s.gyro_bias.allFinite() || !s.P.allFinite() || !detail::fields_finite(s.mag.ref))
      return why = "non-finite state", false;
    if (s.initialized && std::abs(s.q_nb.norm() - S(1)) > S(1.001e-3))  // set_state accepts 1e-3
      return why = "quaternion norm off 1", false;
    if (!symmetric<S, N>(s.P)) return why = "P not symmetric", false;
    return taken_back(f, why);
  }
  static State random_state(Reader& r) {
    State s;
    for (int i = 0; i < 4; ++i) s.q_nb[i] = r.scalar<S>();
    if (r.byte() & 1) s.q_nb = quat::from_rotvec(Vec3<S>(r.scalar<S>(), S(0.1), S(0.2)));
    s.gyro_bias = r.vec3<S>();
    for (int i = 0; i < N; ++i)
      for (int j = 0; j <= i; ++j) s.P(i, j) = s.P(j, i) = (r.byte() & 1) ? S(i == j) * S(1e-3) : r.scalar<S>();
    s.mag.ref.mag_ref = r.vec3<S>();
    s.mag.ref.mag_ref_count = r.byte();
    s.initialized = r.byte() & 1;
    return s;
  }
};

template <class S> struct FuzzAdapter<QuaternionEKFPaper<S>> : QuaternionStateOps<QuaternionEKFPaper<S>, 7> {
  using F = QuaternionEKFPaper<S>;
  using State = typename F::State;
  using Ops = QuaternionStateOps<F, 7>;
  using Ops::healthy;
  using Ops::random_state;
  static constexpr const char* name = "QuaternionEKFPaper";
  static bool same(const State& a, const State& b) {
    return bits_equal(a.q_nb, b.q_nb) && bits_equal(a.gyro_bias, b.gyro_bias) && bits_equal(a.P, b.P) &&
           same_mag(a.mag.ref, b.mag.ref) && a.initialized == b.initialized;
  }
  static StepOutcome step(F& f, Reader& r) {
    const int op = r.byte() % 10;
    switch (op) {
      case 7: {
        const Vec3<S> a = r.reading<S>(Vec3<S>(S(0.3), S(-0.2), S(-9.8))), m = r.reading<S>(Vec3<S>(S(20), S(2), S(43)));
        return outcome(f.update_acc_mag(a, m), "update_acc_mag");
      }
      case 8: return {f.set_state(random_state(r)), true, "set_state"};
      case 9: {
        const State s = random_state(r);
        return {f.reset(s.q_nb, s.gyro_bias, s.P), true, "reset"};
      }
      default: return AttitudeOps<F>::common_step(f, r, op);
    }
  }
};

/// The default QuaternionEKF (the error-state filter with its robustness parts): the common
/// operations with the parts switched on and off (rest detection and its zero-rate update run
/// inside predict), plus the joint update, set_state and reset. Its state is compared field by field, the parts' states included.
template <class S> struct FuzzAdapter<QuaternionEKF<S>> : QuaternionStateOps<QuaternionEKF<S>, 6> {
  using F = QuaternionEKF<S>;
  using State = typename F::State;
  using Ops = QuaternionStateOps<F, 6>;
  using Ops::healthy;
  using Ops::random_state;
  static constexpr const char* name = "QuaternionEKF";
  static typename F::Params params(Reader& r) {
    typename F::Params p = AttitudeOps<F>::params(r);
    p.gyro_rate_noise = (r.byte() & 1) ? r.positive<S>(p.gyro_rate_noise) : S(0);
    p.mag_heading_only = r.byte() & 1;
    p.acc_tilt_only = r.byte() & 1;
    p.acc_gate = (r.byte() & 3) == 0 ? r.positive<S>(S(11)) : S(0);
    p.mag_gate = (r.byte() & 1) ? r.positive<S>(S(9)) : S(0);
    p.declination = (r.byte() & 3) == 0 ? S(r.raw<std::int8_t>()) / S(40) : S(0);
    p.clip.gyro_clip = r.byte() & 1;
    p.clip.gyro_clip_repeats = 1 + r.byte() % 3;
    p.clip.gyro_clip_min_rate = r.positive<S>(p.clip.gyro_clip_min_rate);
    return p;
  }
  static bool same(const State& a, const State& b) { return fields_bits_equal(a, b); }
  static StepOutcome step(F& f, Reader& r) {
    const int op = r.byte() % 10;
    switch (op) {
      case 7: {
        const Vec3<S> a = r.reading<S>(Vec3<S>(S(0.3), S(-0.2), S(-9.8))), m = r.reading<S>(Vec3<S>(S(20), S(2), S(43)));
        return outcome(f.update_acc_mag(a, m, (r.byte() & 3) == 0 ? r.scalar<S>() : S(0)), "update_acc_mag");
      }
      case 8: return {f.set_state(random_state(r)), true, "set_state"};
      case 9: {
        const State s = random_state(r);
        return {f.reset(s.q_nb, s.gyro_bias, s.P), true, "reset"};
      }
      default: return AttitudeOps<F>::common_step(f, r, op);
    }
  }
};

template <class S> struct FuzzAdapter<EulerEKF<S>> : AttitudeOps<EulerEKF<S>> {
  using F = EulerEKF<S>;
  using State = typename F::State;
  static constexpr const char* name = "EulerEKF";
  static bool same(const State& a, const State& b) {
    return bits_equal(a.euler, b.euler) && bits_equal(a.gyro_bias, b.gyro_bias) && bits_equal(a.P, b.P) &&
           same_mag(a.mag.ref, b.mag.ref) && a.initialized == b.initialized;
  }
  static bool healthy(const F& f, std::string& why) {
    const State& s = f.state();
    if (!s.euler.allFinite() || !s.gyro_bias.allFinite() || !s.P.allFinite() || !detail::fields_finite(s.mag.ref))
      return why = "non-finite state", false;
    if (!f.quat().allFinite()) return why = "non-finite quaternion", false;
    if (!symmetric<S, 6>(s.P)) return why = "P not symmetric", false;
    return taken_back(f, why);
  }
  static State random_state(Reader& r) {
    State s;
    s.euler = r.vec3<S>();
    s.gyro_bias = r.vec3<S>();
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j <= i; ++j) s.P(i, j) = s.P(j, i) = (r.byte() & 1) ? S(i == j) * S(1e-3) : r.scalar<S>();
    s.mag.ref.mag_ref = r.vec3<S>();
    s.mag.ref.mag_ref_count = r.byte();
    s.initialized = r.byte() & 1;
    return s;
  }
  static StepOutcome step(F& f, Reader& r) {
    const int op = r.byte() % 9;
    switch (op) {
      case 7: return {f.set_state(random_state(r)), true, "set_state"};
      case 8: {
        const State s = random_state(r);
        return {f.reset(s.euler, s.gyro_bias, s.P), true, "reset"};
      }
      default: return AttitudeOps<F>::common_step(f, r, op);
    }
  }
};

template <class S> StepOutcome marg_outcome(const MargUpdateResult<S>& r, const char* op) {
  StepOutcome o{r.status, true, op};
  if (r.status == Status::Ok) o.outputs_finite = std::isfinite(r.residual) && std::isfinite(r.residual_final);
  return o;
}

template <class S> struct FuzzAdapter<MargFilter<S>> {
  using F = MargFilter<S>;
  using State = typename F::State;
  static constexpr const char* name = "MargFilter";
  static typename F::Params params(Reader& r) {
    typename F::Params p;
    p.gain = (r.byte() & 1) ? r.positive<S>(S(1)) : S(0);
    p.bias_gain = (r.byte() & 1) ? r.positive<S>(S(0.01)) : S(0);
    p.gn_max_iter = 1 + r.byte() % 8;
    p.gn_tol = r.positive<S>(p.gn_tol);
    p.gps_correction = r.byte() & 1;
    p.gps_acc_tau = (r.byte() & 1) ? r.positive<S>(p.gps_acc_tau) : S(0);
    p.omega_dot_tau = (r.byte() & 1) ? r.positive<S>(p.omega_dot_tau) : S(0);
    p.gps_timeout = r.positive<S>(p.gps_timeout);
    p.lever_arm_b = Vec3<S>(S(r.raw<std::int8_t>()), S(r.raw<std::int8_t>()), S(r.raw<std::int8_t>())) / S(64);
    p.max_dt = r.positive<S>(p.max_dt);
    mag_ref_samples(p) = 1u + r.byte();
    return p;
  }
  static bool same(const State& a, const State& b) {
    return bits_equal(a.q_nb, b.q_nb) && bits_equal(a.gyro_bias, b.gyro_bias) && same_mag(a.mag.ref, b.mag.ref) &&
           bits_equal(a.omega_b, b.omega_b) && bits_equal(a.omega_dot_b, b.omega_dot_b) &&
           bits_equal(a.gps_vel_n, b.gps_vel_n) && bits_equal(a.gps_acc_n, b.gps_acc_n) &&
           bits_equal(a.gps_t, b.gps_t) && bits_equal(a.time_since_gps, b.time_since_gps) &&
           bits_equal(a.time_since_update, b.time_since_update) && a.gps_fixes == b.gps_fixes &&
           a.omega_set == b.omega_set && a.initialized == b.initialized;
  }
  static bool healthy(const F& f, std::string& why) {
    const State& s = f.state();
    if (!detail::fields_finite(s)) return why = "non-finite state", false;
    if (s.initialized && std::abs(s.q_nb.norm() - S(1)) > S(1.001e-3)) return why = "quaternion norm off 1", false;
    return taken_back(f, why);
  }
  static StepOutcome step(F& f, Reader& r) {
    const Vec3<S> g_b(S(0.3), S(-0.2), S(-9.8)), m_b(S(20), S(2), S(43)), w_b(S(0.1), S(-0.05), S(0.2));
    const int op = r.byte() % 9;
    switch (op) {
      case 0: return {f.initialize(r.reading<S>(g_b)), true, "initialize(acc)"};
      case 1: {
        const Vec3<S> a = r.reading<S>(g_b), m = r.reading<S>(m_b);
        return {f.initialize(a, m), true, "initialize(acc, mag)"};
      }
      case 2: case 3: {
        const Vec3<S> w = r.reading<S>(w_b);
        const S dt = (r.byte() & 1) ? S(0.01) : r.scalar<S>();
        return {f.predict(w, dt), true, "predict"};
      }
      case 4: return marg_outcome(f.update_acc(r.reading<S>(g_b)), "update_acc");
      case 5: {
        const Vec3<S> a = r.reading<S>(g_b), m = r.reading<S>(m_b);
        return marg_outcome(f.update_acc_mag(a, m), "update_acc_mag");
      }
      case 6: {
        const Vec3<S> v = r.reading<S>(Vec3<S>(S(10), S(-3), S(0.5)));
        const S t = (r.byte() & 1) ? S(0.1) * S(r.byte()) : r.scalar<S>();
        return {f.update_gps_velocity(v, t), true, "update_gps_velocity"};
      }
      case 7: {
        Quat<S> q;
        for (int i = 0; i < 4; ++i) q[i] = r.scalar<S>();
        if (r.byte() & 1) q = quat::from_rotvec(Vec3<S>(r.scalar<S>(), S(0.1), S(0.2)));
        return {f.reset(q, r.vec3<S>()), true, "reset"};
      }
      default: {
        State s = f.state();
        switch (r.byte() % 4) {
          case 0: for (int i = 0; i < 4; ++i) s.q_nb[i] = r.scalar<S>(); break;
          case 1: s.gyro_bias = r.vec3<S>(); s.omega_dot_b = r.vec3<S>(); break;
          case 2: s.gps_t = r.scalar<double>(); s.time_since_gps = r.scalar<S>(); s.gps_fixes = int(r.byte() % 5) - 1; break;
          default: s.mag.ref.mag_ref = r.vec3<S>(); s.initialized = r.byte() & 1; break;
        }
        return {f.set_state(s), true, "set_state"};
      }
    }
  }
};


// --- NavFilter13 (all three time updates) ----------------------------------------------------
template <class S, TimeUpdate TU> struct FuzzAdapter<NavFilter13<S, TU>> {
  using F = NavFilter13<S, TU>;
  using State = typename F::State;
  static constexpr const char* name = TU == TimeUpdate::Ekf           ? "NavFilter13<ekf>"
                                      : TU == TimeUpdate::SecondOrder ? "NavFilter13<second_order>"
                                                                      : "NavFilter13<ukf>";
  static typename F::Params params(Reader& r) {
    typename F::Params p;
    // The paper's noise is tiny (30 ug, 0.3 deg/h); spread it and the aids over decades.
    p.acc_noise = r.positive<S>(S(1e-3));
    p.gyro_noise = r.positive<S>(S(1e-4));
    p.acc_bias_noise = (r.byte() & 1) ? r.positive<S>(S(1e-4)) : S(0);
    p.gyro_bias_noise = (r.byte() & 1) ? r.positive<S>(S(1e-5)) : S(0);
    p.gps_vel_sigma = r.positive<S>(p.gps_vel_sigma);
    p.yaw_sigma = r.positive<S>(p.yaw_sigma);
    p.max_dt = r.positive<S>(p.max_dt);
    p.gyro_range = (r.byte() & 1) ? r.positive<S>(S(35)) : S(0);
    p.acc_range = (r.byte() & 1) ? r.positive<S>(S(160)) : S(0);
    p.cov_floor = (r.byte() & 1) ? r.positive<S>(S(1e-12)) : S(0);
    p.earth_rotation = r.byte() & 1;
    return p;
  }
  static bool same(const State& a, const State& b) {
    return bits_equal(a.v_n, b.v_n) && bits_equal(a.q_nb, b.q_nb) && bits_equal(a.acc_bias, b.acc_bias) &&
           bits_equal(a.gyro_bias, b.gyro_bias) && bits_equal(a.P, b.P) && bits_equal(a.lat, b.lat) &&
           bits_equal(a.lon, b.lon) && bits_equal(a.h, b.h) && a.initialized == b.initialized;
  }
  static bool healthy(const F& f, std::string& why) {
    const State& s = f.state();
    if (!s.v_n.allFinite() || !s.q_nb.allFinite() || !s.acc_bias.allFinite() || !s.gyro_bias.allFinite() ||
        !s.P.allFinite() || !std::isfinite(s.lat) || !std::isfinite(s.lon) || !std::isfinite(s.h))
      return why = "non-finite state", false;
    if (s.initialized && std::abs(s.q_nb.norm() - S(1)) > S(1.001e-3)) return why = "quaternion norm off 1", false;
    if (!symmetric<S, 13>(s.P)) return why = "P not symmetric", false;
    if (!(std::abs(s.lat) < S(1.5))) return why = "latitude at a pole", false;
    return taken_back(f, why);
  }
  static Mat<S, 13, 13> random_P(Reader& r) {
    Mat<S, 13, 13> P = Mat<S, 13, 13>::Identity() * S(1e-4);
    const int k = r.byte() % 4;
    if (k == 0) return P;
    for (int i = 0; i < 13; ++i)
      for (int j = 0; j <= i; ++j)
        if (k == 3 || i == j || (r.byte() & 7) == 0) P(i, j) = P(j, i) = r.scalar<S>();
    return P;
  }
  static StepOutcome step(F& f, Reader& r) {
    const Vec3<S> f_b(S(0.3), S(-0.2), S(-9.8)), w_b(S(0.1), S(-0.05), S(0.2)), v_n(S(3), S(-1), S(0.2));
    const int op = r.byte() % 9;
    switch (op) {
      case 0: {  // reset: mostly plausible, sometimes arbitrary
        const bool arb = (r.byte() & 3) == 0;
        Quat<S> q = quat::from_rotvec(Vec3<S>(S(0.2), S(-0.1), S(r.raw<std::int8_t>()) / S(40)));
        if (arb) for (int i = 0; i < 4; ++i) q[i] = r.scalar<S>();
        const Vec3<S> v = arb ? r.vec3<S>() : r.reading<S>(v_n);
        const Vec3<S> ba = arb ? r.vec3<S>() : Vec3<S>::Zero();
        const Vec3<S> bg = arb ? r.vec3<S>() : Vec3<S>::Zero();
        const S lat = arb ? r.scalar<S>() : S(0.6), lon = arb ? r.scalar<S>() : S(0.2), h = arb ? r.scalar<S>() : S(100);
        return {f.reset(v, q, ba, bg, random_P(r), lat, lon, h), true, "reset"};
      }
      case 1: case 2: case 3: {
        const Vec3<S> a = r.reading<S>(f_b), w = r.reading<S>(w_b);
        const S dt = (r.byte() & 1) ? S(0.01) : r.scalar<S>();
        return {f.predict(w, a, dt), true, "predict"};
      }
      case 4: return outcome(f.update_velocity(r.reading<S>(v_n), (r.byte() & 3) == 0 ? r.scalar<S>() : S(0)),
                             "update_velocity");
      case 5: {
        const S yaw = (r.byte() & 1) ? S(r.raw<std::int8_t>()) / S(40) : r.scalar<S>();
        return outcome(f.update_yaw(yaw, (r.byte() & 3) == 0 ? r.scalar<S>() : S(0)), "update_yaw");
      }
      case 6: {
        const Vec3<S> v = r.reading<S>(v_n);
        const S yaw = (r.byte() & 1) ? S(r.raw<std::int8_t>()) / S(40) : r.scalar<S>();
        return outcome(f.update_velocity_yaw(v, yaw, (r.byte() & 3) == 0 ? r.scalar<S>() : S(0)),
                       "update_velocity_yaw");
      }
      case 7: {
        const S lat = (r.byte() & 1) ? S(r.raw<std::int8_t>()) / S(100) : r.scalar<S>();
        return {f.set_position(lat, r.scalar<S>(), r.scalar<S>()), true, "set_position"};
      }
      default: {
        State s = f.state();
        switch (r.byte() % 4) {
          case 0: for (int i = 0; i < 4; ++i) s.q_nb[i] = r.scalar<S>(); break;
          case 1: s.v_n = r.vec3<S>(); s.acc_bias = r.vec3<S>(); s.gyro_bias = r.vec3<S>(); break;
          case 2: s.P = random_P(r); break;
          default: s.lat = r.scalar<S>(); s.h = r.scalar<S>(); s.initialized = r.byte() & 1; break;
        }
        return {f.set_state(s), true, "set_state"};
      }
    }
  }
};

// --- GpsInsFilter (16 states, and 22 with the scale-factor states) -----------------------------
template <class S, bool SF> struct FuzzAdapter<GpsInsFilter<S, SF>> {
  using F = GpsInsFilter<S, SF>;
  using State = typename F::State;
  static constexpr const char* name = SF ? "GpsInsFilter (scale factors)" : "GpsInsFilter";
  static typename F::Params params(Reader& r) {
    typename F::Params p;
    p.gyro_noise = r.positive<S>(p.gyro_noise);
    p.acc_noise = r.positive<S>(p.acc_noise);
    p.gyro_bias_noise = r.positive<S>(p.gyro_bias_noise);
    p.acc_bias_noise = r.positive<S>(p.acc_bias_noise);
    p.gyro_bias_tau = (r.byte() & 1) ? r.positive<S>(S(100)) : S(0);
    p.acc_bias_tau = (r.byte() & 1) ? r.positive<S>(S(100)) : S(0);
    p.gps_pos_sigma_h = r.positive<S>(p.gps_pos_sigma_h);
    p.gps_vel_sigma = r.positive<S>(p.gps_vel_sigma);
    p.lever_arm_b = Vec3<S>(S(r.raw<std::int8_t>()), S(r.raw<std::int8_t>()), S(r.raw<std::int8_t>())) / S(64);
    p.baro_sigma = r.positive<S>(p.baro_sigma);
    p.baro_rate_baseline = (r.byte() & 1) ? S(0.1) * S(r.byte() % 20) : S(0);
    p.baro_offset_noise = (r.byte() & 1) ? r.positive<S>(p.baro_offset_noise) : S(0);
    p.inflate_after = S(r.byte() % 3);
    p.adapt_q_max = (r.byte() & 1) ? S(100) : S(1);
    p.zupt = r.byte() & 1;
    p.nhc = r.byte() & 1;
    if (r.byte() & 1) p.imu_rotation = quat::to_rotmat(quat::from_euler(S(3.14159265), S(0), S(r.byte()) / S(40)));
    p.compass_sigma = r.positive<S>(p.compass_sigma);
    if (r.byte() & 1) p.gate_gps_pos = p.gate_gps_vel = p.gate_baro = p.gate_compass = S(0);
    p.align_time = S(0.01) * S(r.byte() % 50);
    p.heading_from_gps = r.byte() & 1;
    p.earth_rotation = r.byte() & 1;
    p.max_dt = r.positive<S>(p.max_dt);
    p.gyro_range = (r.byte() & 1) ? r.positive<S>(S(35)) : S(0);
    p.acc_range = (r.byte() & 1) ? r.positive<S>(S(160)) : S(0);
    p.cov_floor = (r.byte() & 1) ? r.positive<S>(S(1e-12)) : S(0);
    if (SF) {
      p.gyro_scale_noise = r.positive<S>(p.gyro_scale_noise);
      p.acc_scale_noise = r.positive<S>(p.acc_scale_noise);
      p.init_gyro_scale_sigma = r.positive<S>(p.init_gyro_scale_sigma);
    }
    return p;
  }
  /// Everything but the counters (diagnostics that count refused samples too), every field of
  /// the declaration (params.hpp).
  static bool same(const State& a, const State& b) { return fields_bits_equal(a, b, "counters"); }
  static bool healthy(const F& f, std::string& why) {
    const State& s = f.state();
    if (!s.nav.q_nb.allFinite() || !s.nav.v_n.allFinite() || !std::isfinite(s.nav.lat) ||
        !std::isfinite(s.nav.lon) || !std::isfinite(s.nav.h) || !s.acc_bias.allFinite() || !s.gyro_bias.allFinite() ||
        !s.P.allFinite() || !std::isfinite(s.t) || !s.omega_b.allFinite() || !s.f_b.allFinite() ||
        !s.align_sum.allFinite() || !std::isfinite(s.baro_offset) || !std::isfinite(s.baro_last) ||
        !std::isfinite(s.baro_ref_h) || !s.acc_scale.allFinite() || !s.gyro_scale.allFinite())
      return why = "non-finite state", false;
    if (!((s.acc_scale.array().abs() < S(0.5)).all() && (s.gyro_scale.array().abs() < S(0.5)).all()))
      return why = "scale factor out of (-0.5, 0.5)", false;
    if (std::abs(s.nav.q_nb.norm() - S(1)) > S(1.001e-3)) return why = "quaternion norm off 1", false;
    if (!symmetric<S, F::kStates>(s.P)) return why = "P not symmetric", false;
    if (s.phase == GpsInsPhase::Navigating && !(std::abs(s.nav.lat) < 1.5707)) return why = "latitude at a pole", false;
    // set_state also checks the enums in range.
    return taken_back(f, why);
  }
  static double angle(Reader& r, double typical) {
    return (r.byte() & 1) ? typical + double(r.raw<std::int8_t>()) * 1e-6 : double(r.scalar<S>());
  }
  static StepOutcome step(F& f, Reader& r) {
    const Vec3<S> f_b(S(0.3), S(-0.2), S(-9.8)), w_b(S(0.01), S(-0.005), S(0.02)), v_n(S(3), S(-1), S(0.2));
    const int op = r.byte() % 10;
    switch (op) {
      case 0: case 1: case 2: case 3: {
        const Vec3<S> w = r.reading<S>(w_b), a = r.reading<S>(f_b);
        const S dt = (r.byte() & 1) ? S(0.01) : (r.byte() & 1) ? S(0.1) : r.scalar<S>();
        return {f.predict(w, a, dt), true, "predict"};
      }
      case 4: {
        const double lat = angle(r, 0.6), lon = angle(r, 0.2), h = (r.byte() & 1) ? 100.0 : double(r.scalar<S>());
        const Vec3<S> v = (r.byte() & 1) ? r.reading<S>(v_n) : Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN());
        const Vec3<S> ps = (r.byte() & 1) ? Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN()) : r.vec3<S>();
        const Vec3<S> vs = (r.byte() & 1) ? Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN()) : r.vec3<S>();
        const GpsResult<S> g = f.update_gps(lat, lon, h, v, ps, vs);
        // Two updates: Ok when either was applied, Rejected when either was rejected (a rejected
        // one may reset its block by the documented gate lockout), else the position's failure
        // (a failed update left its part unchanged).
        StepOutcome o = outcome(g.pos, "update_gps");
        const StepOutcome ov = outcome(g.vel, "update_gps");
        o.outputs_finite = o.outputs_finite && ov.outputs_finite;
        o.status = (g.pos.status == Status::Ok || g.vel.status == Status::Ok)               ? Status::Ok
                   : (g.pos.status == Status::Rejected || g.vel.status == Status::Rejected) ? Status::Rejected
                                                                                            : g.pos.status;
        o.may_record = g.pos.status == Status::NotInitialized || g.vel.status == Status::NotInitialized;
        return o;
      }
      case 5: {
        const double lat = angle(r, 0.6), lon = angle(r, 0.2), h = (r.byte() & 1) ? 100.0 : double(r.scalar<S>());
        const Vec3<S> ps = (r.byte() & 1) ? Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN()) : r.vec3<S>();
        StepOutcome o = outcome(f.update_gps_position(lat, lon, h, ps), "update_gps_position");
        o.may_record = o.status == Status::NotInitialized;
        return o;
      }
      case 6: {
        const Vec3<S> vs = (r.byte() & 1) ? Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN()) : r.vec3<S>();
        StepOutcome o = outcome(f.update_gps_velocity(r.reading<S>(v_n), vs), "update_gps_velocity");
        o.may_record = o.status == Status::NotInitialized;
        return o;
      }
      case 7: {
        const double hb = (r.byte() & 1) ? 100.0 + double(r.raw<std::int8_t>()) / 16 : double(r.scalar<double>());
        const BaroResult<S> b = f.update_baro(hb);
        StepOutcome o = outcome(b.height, "update_baro");
        const StepOutcome ov = outcome(b.vd, "update_baro");
        o.outputs_finite = o.outputs_finite && ov.outputs_finite;
        // The height update failing undoes the whole step; after it, the v_D update may fail alone.
        if (b.height.status == Status::Ok || b.height.status == Status::Rejected) o.status = Status::Ok;
        o.may_record = b.height.status == Status::NotInitialized;
        return o;
      }
      case 8: {
        const S hd = (r.byte() & 1) ? S(r.raw<std::int8_t>()) / S(40) : r.scalar<S>();
        StepOutcome o = outcome(f.update_compass(hd), "update_compass");
        o.may_record = o.status == Status::NotInitialized;
        return o;
      }
      default: {
        if (r.byte() & 1) {
          Quat<S> q = quat::from_rotvec(Vec3<S>(S(0.1), S(0.05), S(r.raw<std::int8_t>()) / S(40)));
          if ((r.byte() & 3) == 0)
            for (int i = 0; i < 4; ++i) q[i] = r.scalar<S>();
          Mat<S, F::kStates, F::kStates> P = f.initial_covariance(Vec3<S>(S(3), S(3), S(5)), S(0.5));
          if ((r.byte() & 3) == 0)
            for (int i = 0; i < F::kStates; ++i)
              for (int j = 0; j <= i; ++j)
                if (i == j || (r.byte() & 7) == 0) P(i, j) = P(j, i) = r.scalar<S>();
          const bool arb = (r.byte() & 3) == 0;
          return {f.reset(q, arb ? r.vec3<S>() : r.reading<S>(v_n), angle(r, 0.6), angle(r, 0.2),
                               arb ? double(r.scalar<S>()) : 100.0, arb ? r.vec3<S>() : Vec3<S>::Zero(),
                               arb ? r.vec3<S>() : Vec3<S>::Zero(), P),
                  true, "reset"};
        }
        State s = f.state();
        switch (r.byte() % 4) {
          case 0: for (int i = 0; i < 4; ++i) s.nav.q_nb[i] = r.scalar<S>(); break;
          case 1:
            s.nav.v_n = r.vec3<S>();
            s.acc_bias = r.vec3<S>();
            s.gyro_bias = r.vec3<S>();
            if (r.byte() & 1) s.gyro_scale = r.vec3<S>() * S(1e-3);  // refused without the states
            break;
          case 2:
            for (int i = 0; i < F::kStates; ++i)
              for (int j = 0; j <= i; ++j)
                if (i == j || (r.byte() & 7) == 0) s.P(i, j) = s.P(j, i) = r.scalar<S>();
            break;
          default: s.nav.lat = double(r.scalar<S>()); s.nav.h = double(r.scalar<S>()); s.t = double(r.scalar<S>()); break;
        }
        return {f.set_state(s), true, "set_state"};
      }
    }
  }
};

/// Run one input through filter F; returns false (after calling fail) on a contract violation.
template <class F, class Fail> bool run_one(Reader& r, Fail&& fail) {
  using A = FuzzAdapter<F>;
  F f(A::params(r));
  for (int k = 0; k < 4096 && !r.empty(); ++k) {
    const typename F::State before = f.state();
    const StepOutcome o = A::step(f, r);
    std::string why;
    if (o.status != Status::Ok && o.status != Status::Rejected && !o.may_record && !A::same(before, f.state())) {
      fail(std::string(A::name) + ": " + o.op + " returned " + to_string(o.status) + " but changed the state");
      return false;
    }
    if (o.status == Status::Ok && !o.outputs_finite) {
      fail(std::string(A::name) + ": " + o.op + " accepted with non-finite outputs");
      return false;
    }
    if ((o.status == Status::Ok || o.status == Status::Rejected || o.may_record) && !A::healthy(f, why)) {
      fail(std::string(A::name) + ": after " + o.op + ": " + why);
      return false;
    }
  }
  return true;
}

/// A contract violation's report (the fuzz target aborts; the GoogleTest replay fails the test).
using FailFn = void (*)(const std::string& message);

/// The fuzz target's units (tests/fuzz/fuzz_*.cpp), each compiled on its own so that the target
/// builds on every core: the filter `which` (0..5) of a family on the input `r`.
bool fuzz_attitude(Reader& r, int which, FailFn fail);   // QuaternionEKF, QuaternionEKFPaper, EulerEKF
bool fuzz_marg_gpsins(Reader& r, int which, FailFn fail);  // MargFilter, GpsInsFilter (+ scale factors)
bool fuzz_nav13(Reader& r, int which, FailFn fail);      // NavFilter13: EKF, second-order, UKF

}  // namespace quatnav_fuzz
