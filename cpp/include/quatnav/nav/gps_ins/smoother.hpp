// quatnav: the Rauch-Tung-Striebel smoother of GpsInsFilter (paper 004), the model of
// core/smoother.hpp for the 16-state feedback filter.
//
// Feedback form: after every correction the filter injects its error estimate into the nominal
// state and resets it to zero, so its posteriors are nominal states with a zero-mean error of
// covariance P. The backward pass works on the error states between those stored nominal states,
// in the filter's own error chart (gps_ins/model.hpp, every error estimate minus truth):
//   local(base, x) = the error of `base` if x were the truth: [dp_n (N, E, D metres about base),
//     v_base - v_x, psi with q_x = exp(-psi) q_base (the nav-frame phi-angle), b_base - b_x,
//     offset_base - offset_x];
//   retract(base, d) = the filter's injection of the error d into base (detail::gpsins_inject).
// The sign convention is the filter's, so P, Phi and the gain C = P_k Phi^T P_{k+1|k}^-1 are the
// filter's own; d_k = C local(x_{k+1|k}, x^s_{k+1}) and x^s_k = inject(x_k, d_k) is x_k + C
// (x^s_{k+1} - x_{k+1|k}) in that chart.
//
// predict: the filter's own time update of batch sample k (all its coasting steps,
// detail::gpsins_sample_step) on a copy of the filter loaded with the record: the pure-prediction
// stretches are recomputed bit for bit. transition: the product over those steps of the Phi the
// time update itself uses (GpsInsFilter::transition, detail::gpsins_Phi).
//
// Restarts (the backward pass does not cross them: before one, the smoothed estimate uses the
// data up to it): a reset of the state to a GNSS fix (the inflation needed exceeded
// inflate_max: the position or velocity and its covariance block are replaced, not measured), an
// inflation of the covariance before a fix is applied, the initialization of the altimeter
// offset (its row and column of P are replaced by the height's), and any (re)start of
// navigation (the record starts there). Why an inflation is a restart and not the record: the
// filter inflates when fixes keep failing their gate, i.e. when its own model has been violated
// (the INS drifted beyond its covariance: a false rest detection, an unmodelled error); the fix
// applied after it moves the state by many of the prior's sigmas. Crossing it with the
// uninflated prior's gain makes the backward pass explain that jump with the linear model,
// which it does with large corrections of the states it finds cheap (velocity, attitude,
// biases), carried back far beyond the outage: measured on the simulated paper-004 walk (seed 0,
// outages 20-30 s and 45-75 s, the filter taking the end of the long outage for rest, an
// inflated fix at 75.2 s), the smoothed horizontal error was 12 m at 31-35 s, where fixes were
// being applied and the forward error was 0.3 m. As a restart, the data before the inflation
// are smoothed with the data up to it.
//
// Record (compact posterior): lat, lon, h, baro_offset (double), v_n, q_nb, biases, scale factors
// (zero without the scale-factor states), q_scale (the
// process-noise scale the time update uses) and the strapdown's previous increments (its coning
// and sculling terms: inputs of the next time update) in S, the upper triangle of P (136), the
// count of resets and inflations and the offset's validity: 1344 bytes in double, 696 in float,
// plus 16 per record (with the scale-factor states P has 253 entries: 2280 and 1164 bytes). The reservation (gpsins_max_epochs): every aiding and magnetometer sample,
// a pseudo-measurement every pseudo_interval, a checkpoint every segment samples; a 1-hour 200 Hz
// log with 5 Hz GNSS, 10 Hz altimeter and compass and the 0.1 s pseudo-measurements: 1.3e5
// records, 175 MB in double.
#pragma once

#include <cstddef>
#include <cstdint>

#include "../../core/smoother.hpp"
#include "../../core/types.hpp"
#include "../gps_ins.hpp"

namespace quatnav {

/// The smoother model of GpsInsFilter<S, SF> (core/smoother.hpp).
template <class S_, bool SF = false> struct GpsInsRtsModel {
  using Scalar = S_;
  using S = S_;
  using Filter = GpsInsFilter<S, SF>;
  using State = GpsInsState<S, SF>;
  static constexpr int kErr = gpsins::kStates<SF>;
  using Mat16 = Mat<S, kErr, kErr>;
  using Vec16 = Vec<S, kErr>;

  struct Record {
    double lat, lon, h, baro_offset;
    Quat<S> q_nb;
    Vec3<S> v_n, acc_bias, gyro_bias, acc_scale, gyro_scale;
    S q_scale;
    Vec3<S> dtheta_prev, dv_prev;  ///< the strapdown's previous increments (coning, sculling)
    PackedSym<S, kErr> P;
    std::uint32_t breaks;  ///< resets to a fix and covariance inflations so far (all aid kinds)
    bool baro_valid;       ///< the altimeter offset is initialized
    bool has_prev;         ///< dtheta_prev, dv_prev hold a step
  };

  /// f: the filter before the run (its parameters); t (n), gyro, accel (n x 3), increments: the
  /// batch run's IMU record (GpsInsBatchIo).
  GpsInsRtsModel(const Filter& f, const double* t, const S* gyro, const S* accel, bool increments)
      : g_(f), st_(f.state()), t_(t), w_(gyro), a_(accel), inc_(increments) {}

  bool capture(const Filter& f, Record& r) const {
    if (!f.navigating()) return false;
    const State& s = f.state();
    nominal_from(s, r);
    r.q_scale = s.q_scale;
    r.dtheta_prev = s.nav.dtheta_prev;
    r.dv_prev = s.nav.dv_prev;
    r.has_prev = s.nav.has_prev;
    r.P.pack(s.P);
    r.breaks = 0;
    for (int i = 0; i < kGpsInsAidKinds; ++i) r.breaks += s.counters.resets[i] + s.counters.inflated[i];
    r.baro_valid = s.baro_offset_valid;
    return true;
  }

  bool same(const Record& a, const Record& b) const {
    return a.lat == b.lat && a.lon == b.lon && a.h == b.h && a.baro_offset == b.baro_offset && a.q_nb == b.q_nb &&
           a.v_n == b.v_n && a.acc_bias == b.acc_bias && a.gyro_bias == b.gyro_bias && a.acc_scale == b.acc_scale &&
           a.gyro_scale == b.gyro_scale && a.q_scale == b.q_scale &&
           a.dtheta_prev == b.dtheta_prev && a.dv_prev == b.dv_prev && a.has_prev == b.has_prev && a.P == b.P &&
           a.breaks == b.breaks && a.baro_valid == b.baro_valid;
  }

  /// A reset to a fix, a covariance inflation or the initialization of the altimeter offset (see
  /// the file comment).
  bool restart(const Record& predicted, const Record& post) const {
    return post.breaks != predicted.breaks || post.baro_valid != predicted.baro_valid;
  }

  /// The filter's time update of sample k from `post`: Same when its first step is refused.
  RtsLink predict(std::size_t k, const Record& post, Record& prior) {
    if (!load(post)) return RtsLink::Restart;
    const detail::GpsInsSampleStep<S> u = detail::gpsins_sample_step(g_.params(), t_, w_, a_, inc_, k);
    long applied = 0;
    for (; applied < u.m && g_.predict(u.w, u.a, u.dt) == Status::Ok; ++applied) {
    }
    if (applied == 0) return RtsLink::Same;
    capture(g_, prior);
    prior.breaks = post.breaks;
    return RtsLink::Predict;
  }

  /// The error-state transition of that time update: the product of the Phi of its steps.
  RtsLink transition(std::size_t k, const Record& post, const Record&, Mat16& Phi) {
    if (!load(post)) return RtsLink::Restart;
    const detail::GpsInsSampleStep<S> u = detail::gpsins_sample_step(g_.params(), t_, w_, a_, inc_, k);
    if (u.m == 1) {
      // One step (the usual sample: no gap to coast over): its Phi is taken at `post` itself, so
      // neither the step nor a product is needed. predict() already made that step (it is Predict,
      // not Same, only when the step was applied).
      Phi = g_.transition(u.w, u.a, u.dt);
      return RtsLink::Predict;
    }
    Phi.setIdentity();
    for (long j = 0; j < u.m; ++j) {
      const Mat16 Phi_j = g_.transition(u.w, u.a, u.dt);
      if (g_.predict(u.w, u.a, u.dt) != Status::Ok) break;
      Phi = fixed_mul(Phi_j, Phi).eval();
    }
    return RtsLink::Predict;
  }

  Mat16 error_covariance(const Record& r) const { return r.P.unpack(); }

  /// The error of `base` if x were the truth (the filter's chart, estimate minus truth).
  Vec16 local(const Record& base, const Record& x) const {
    Vec16 d;
    d.template segment<3>(gpsins::kPos) = earth::geodetic_diff<S>(base.lat, base.lon, base.h, x.lat, x.lon, x.h);
    d.template segment<3>(gpsins::kVel) = base.v_n - x.v_n;
    // q_x = exp(-psi) q_base: psi = log(q_base q_x^*)
    d.template segment<3>(gpsins::kAtt) = quat::to_rotvec(quat::mul(base.q_nb, quat::conj(x.q_nb)));
    d.template segment<3>(gpsins::kBa) = base.acc_bias - x.acc_bias;
    d.template segment<3>(gpsins::kBg) = base.gyro_bias - x.gyro_bias;
    d[gpsins::kBo] = S(base.baro_offset - x.baro_offset);
    if constexpr (SF) {
      d.template segment<3>(gpsins::kSa) = base.acc_scale - x.acc_scale;
      d.template segment<3>(gpsins::kSg) = base.gyro_scale - x.gyro_scale;
    }
    return d;
  }

  /// out = the filter's injection of the error d into base, with the error covariance Ps.
  void retract(const Record& base, const Vec16& d, const Mat16& Ps, Record& out) const {
    State s;
    nominal_to(base, s);
    detail::gpsins_inject(s, d);
    out = base;
    nominal_from(s, out);
    out.P.pack(Ps);
  }

 private:
  /// The nominal state (position, attitude, velocity, biases, altimeter offset) between a record
  /// and a filter state.
  static void nominal_from(const State& s, Record& r) {
    r.lat = s.nav.lat;
    r.lon = s.nav.lon;
    r.h = s.nav.h;
    r.q_nb = s.nav.q_nb;
    r.v_n = s.nav.v_n;
    r.acc_bias = s.acc_bias;
    r.gyro_bias = s.gyro_bias;
    r.acc_scale = s.acc_scale;
    r.gyro_scale = s.gyro_scale;
    r.baro_offset = s.baro_offset;
  }
  static void nominal_to(const Record& r, State& s) {
    s.nav.lat = r.lat;
    s.nav.lon = r.lon;
    s.nav.h = r.h;
    s.nav.q_nb = r.q_nb;
    s.nav.v_n = r.v_n;
    s.acc_bias = r.acc_bias;
    s.gyro_bias = r.gyro_bias;
    s.acc_scale = r.acc_scale;
    s.gyro_scale = r.gyro_scale;
    s.baro_offset = r.baro_offset;
  }

  /// The filter copy in the state of `post` (navigating); false when refused.
  bool load(const Record& post) {
    nominal_to(post, st_);
    st_.baro_offset_valid = post.baro_valid;
    st_.q_scale = post.q_scale;
    st_.nav.dtheta_prev = post.dtheta_prev;
    st_.nav.dv_prev = post.dv_prev;
    st_.nav.has_prev = post.has_prev;
    st_.P = post.P.unpack();
    st_.phase = GpsInsPhase::Navigating;
    return g_.set_state(st_) == Status::Ok;
  }

  Filter g_;
  State st_;
  const double* t_;
  const S* w_;
  const S* a_;
  bool inc_;
};

/// Writes the smoothed estimates where the output pointers of `out` say, in the layout of
/// gpsins_batch's outputs (llh, v_n, q_nb, acc_bias, gyro_bias, acc_scale, gyro_scale, sigma,
/// baro_offset; any may be null; the other fields of `out` are not used).
template <class S, bool SF = false> struct GpsInsSmoothedOutput {
  GpsInsBatchIo<S> out;
  static constexpr int N = gpsins::kStates<SF>;

  void operator()(std::size_t k, const typename GpsInsRtsModel<S, SF>::Record& r, const Mat<S, N, N>& Ps) const {
    if (out.llh) {
      out.llh[3 * k] = r.lat;
      out.llh[3 * k + 1] = r.lon;
      out.llh[3 * k + 2] = r.h;
    }
    if (out.v_n) Eigen::Map<Vec3<S>>(out.v_n + 3 * k) = r.v_n;
    if (out.q_nb) Eigen::Map<Vec4<S>>(out.q_nb + 4 * k) = r.q_nb;
    if (out.acc_bias) Eigen::Map<Vec3<S>>(out.acc_bias + 3 * k) = r.acc_bias;
    if (out.gyro_bias) Eigen::Map<Vec3<S>>(out.gyro_bias + 3 * k) = r.gyro_bias;
    if (out.acc_scale) Eigen::Map<Vec3<S>>(out.acc_scale + 3 * k) = r.acc_scale;
    if (out.gyro_scale) Eigen::Map<Vec3<S>>(out.gyro_scale + 3 * k) = r.gyro_scale;
    if (out.sigma) Eigen::Map<Vec<S, N>>(out.sigma + N * k) = Ps.diagonal().cwiseMax(S(0)).cwiseSqrt();
    if (out.baro_offset)
      out.baro_offset[k] = r.baro_valid ? r.baro_offset : std::numeric_limits<double>::quiet_NaN();
  }
};

/// An upper bound of the samples of a batch run at which an aid can change the state (the
/// records of the smoother's reserve()): every aiding sample, every magnetometer sample, and the
/// pseudo-measurements at most every pseudo_interval.
template <class S> std::size_t gpsins_max_epochs(const GpsInsParams<S>& p, const GpsInsBatchIo<S>& io) {
  std::size_t e = io.ng + io.nb + io.nc + io.no + (io.mag ? io.n : 0) + 2;
  if ((p.zupt || p.nhc || p.nhc_auto) && io.n > 1) {
    const double T = io.t[io.n - 1] - io.t[0];
    const double pi = double(p.pseudo_interval);
    const double c = pi > 0.0 ? T / (pi * (1.0 - 1e-6)) + 2.0 : double(io.n);
    e += c < double(io.n) ? std::size_t(c) : io.n;
  }
  return e;
}

}  // namespace quatnav
