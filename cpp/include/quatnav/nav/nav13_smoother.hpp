// quatnav: the Rauch-Tung-Striebel smoother of NavFilter13 (paper 002), for every time update.
//
// The model of core/smoother.hpp for the 13-state filter. Error state (12): [dv, dtheta, db_a,
// db_g], dtheta the body-frame rotation vector (q_true = q * exp(dtheta)), the filter's own
// error_covariance(); the smoothed attitude is the forward quaternion turned by the smoothed
// error rotation (quat_block.hpp's retract), the covariance mapped back to the 13-state form by
// dq = 1/2 Xi(q) dtheta.
//
// The backward gain of the EKF and second-order time updates uses the EKF transition
// Phi = T(q_{k+1}) J F T'(q_k), F = nav13_jacobian at the posterior with the step's input
// (NavFilter13::step_input: the rotation-corrected specific force and the Earth terms), J the
// Jacobian of the renormalization that follows the Euler step (the quaternion rows scaled by
// (I - q q^T)/|q|), T and T' the maps to and from the error state (quat_block.hpp); the second-
// order filter's covariance is the EKF's, so the gain is consistent with it. The unscented time
// update's gain is its own: the cross-covariance D of its sigma points before and after the step
// (detail::nav13_predict_ukf), C = D P_{k+1|k}^-1 (the unscented RTS smoother, Särkkä 2008).
// Why not the EKF transition there too: with 10-20 deg initial attitude errors the unscented
// prior is smaller than Phi P Phi^T + Q in the attitude directions, the joint covariance of
// (x_k, x_{k+1}) that the EKF gain implies is then not positive semi-definite, and the smoothed
// attitude variance came out negative over the first 13 samples (tests/python/test_nav13_smoother.py's
// run); with D it cannot. The prior x_{k+1|k}, P_{k+1|k} is always the one the filter computed.
// The carried position is not estimated: the smoothed output keeps the forward one.
//
// Record (compact posterior): x (13), the upper triangle of P (91) in S, lat, lon, h (double):
// 856 bytes in double, 440 in float, plus 16 per record (core/smoother.hpp). Records are made
// at the samples where a velocity or yaw measurement changed the state and every `segment`
// samples; a 1e7-sample log with 10 Hz aids at 100 Hz holds about 1.0e6 + 4e4 records, under
// 1 GB (docs/SMOOTHING.md).
#pragma once

#include <cstddef>
#include <cstdint>

#include "../core/quat_block.hpp"
#include "../core/smoother.hpp"
#include "../core/types.hpp"
#include "nav_filter13.hpp"

namespace quatnav {

/// The smoother model of NavFilter13<S, TU> (core/smoother.hpp): recomputes the time update of
/// a sample with a copy of the filter (same parameters) on the inputs of the batch run.
template <class Filter> struct Nav13RtsModel {
  using Scalar = typename Filter::Scalar;
  using S = Scalar;
  static constexpr int kErr = 12;
  using Block = detail::Nav13Block<S>;
  using Vec13 = Vec<S, 13>;
  using Mat13 = Mat<S, 13, 13>;
  using Mat12 = Mat<S, 12, 12>;

  struct Record {
    Vec13 x;              ///< [v_n, q_nb, b_a, b_g]
    PackedSym<S, 13> P;   ///< covariance of x
    double lat, lon, h;   ///< carried position
  };

  /// f: the filter before the run (its parameters); omega_ib_b, f_ib_b (n x 3), dt (n): the
  /// batch run's IMU samples.
  Nav13RtsModel(const Filter& f, const S* omega_ib_b, const S* f_ib_b, const S* dt)
      : g_(f), st_(f.state()), w_(omega_ib_b), f_(f_ib_b), dt_(dt) {}

  bool capture(const Filter& f, Record& r) const {
    if (!f.initialized()) return false;
    r.x = f.x();
    r.P.pack(f.covariance());
    r.lat = f.state().lat;
    r.lon = f.state().lon;
    r.h = f.state().h;
    return true;
  }

  bool same(const Record& a, const Record& b) const {
    return a.x == b.x && a.P == b.P && a.lat == b.lat && a.lon == b.lon && a.h == b.h;
  }

  bool restart(const Record&, const Record&) const { return false; }

  /// The filter's time update of sample k from `post` (Same when it refuses it).
  RtsLink predict(std::size_t k, const Record& post, Record& prior) {
    if (!load(post)) return RtsLink::Restart;
    if (g_.predict(imu_w(k), imu_f(k), dt_[k]) != Status::Ok) return RtsLink::Same;
    capture(g_, prior);
    return RtsLink::Predict;
  }

  /// The gain's transition of that step: the EKF one (Predict) or, for the unscented time
  /// update, its sigma points' cross-covariance (Cross).
  RtsLink transition(std::size_t k, const Record& post, const Record& prior, Mat12& Phi) {
    if (!load(post)) return RtsLink::Restart;
    const Nav13Input<S> u = g_.step_input(imu_w(k), imu_f(k), dt_[k]);
    if constexpr (Filter::kTimeUpdate == TimeUpdate::Ukf) {
      // The same unscented transform as the filter's, on copies.
      Vec13 xc = post.x;
      Mat13 Pc = st_.P;
      if (detail::nav13_predict_ukf(xc, Pc, u, g_.params(), g_.ukf_weights(), &Phi) != Status::Ok)
        return RtsLink::Restart;
      return RtsLink::Cross;
    } else {
      Phi = ekf_transition(post.x, Quat<S>(prior.x.template segment<4>(detail::kQ)), u);
      return RtsLink::Predict;
    }
  }

  /// The error-state transition T(q_next) J F T'(q) of one Euler step from x with input u.
  static Mat12 ekf_transition(const Vec13& x, const Quat<S>& q_next, const Nav13Input<S>& u) {
    const Mat13 F = detail::nav13_jacobian(x, u);
    const Quat<S> qn = detail::nav13_f(x, u).template segment<4>(detail::kQ);
    const S n = qn.norm();
    const Quat<S> qh = qn / n;
    const Mat4<S> Jq = (Mat4<S>::Identity() - qh * qh.transpose()) / n;
    Mat<S, 12, 13> TJ = Block::to_error(q_next);
    TJ.template middleCols<4>(detail::kQ) = (TJ.template middleCols<4>(detail::kQ) * Jq).eval();
    return fixed_mul(fixed_mul(TJ, F), Block::from_error(Quat<S>(x.template segment<4>(detail::kQ))));
  }

  Mat12 error_covariance(const Record& r) const {
    Mat12 Pe = Block::error_covariance(Quat<S>(r.x.template segment<4>(detail::kQ)), r.P.unpack());
    symmetrize(Pe);
    return Pe;
  }

  /// x [-] base: [v - v_b, log(q_b^-1 q), b_a - b_a,b, b_g - b_g,b].
  Vec<S, 12> local(const Record& base, const Record& x) const {
    Vec<S, 12> d;
    d.template segment<3>(0) = x.x.template segment<3>(detail::kV) - base.x.template segment<3>(detail::kV);
    d.template segment<3>(3) = quat::to_rotvec(quat::mul(quat::conj(Quat<S>(base.x.template segment<4>(detail::kQ))),
                                                         Quat<S>(x.x.template segment<4>(detail::kQ))));
    d.template segment<6>(6) = x.x.template tail<6>() - base.x.template tail<6>();
    return d;
  }

  void retract(const Record& base, const Vec<S, 12>& d, const Mat12& Ps, Record& out) const {
    out.x = Block::retract(base.x, d);
    Quat<S> q = out.x.template segment<4>(detail::kQ);
    q /= q.norm();
    out.x.template segment<4>(detail::kQ) = q;
    Mat13 P = Block::from_error_covariance(q, Ps);
    symmetrize(P);
    out.P.pack(P);
    out.lat = base.lat;
    out.lon = base.lon;
    out.h = base.h;
  }

 private:
  /// The filter copy in the state of `post`; false when refused.
  bool load(const Record& post) {
    st_.v_n = post.x.template segment<3>(detail::kV);
    st_.q_nb = post.x.template segment<4>(detail::kQ);
    st_.acc_bias = post.x.template segment<3>(detail::kBa);
    st_.gyro_bias = post.x.template segment<3>(detail::kBg);
    st_.P = post.P.unpack();
    st_.lat = post.lat;
    st_.lon = post.lon;
    st_.h = post.h;
    st_.initialized = true;
    return g_.set_state(st_) == Status::Ok;
  }
  Vec3<S> imu_w(std::size_t k) const { return Eigen::Map<const Vec3<S>>(w_ + 3 * k); }
  Vec3<S> imu_f(std::size_t k) const { return Eigen::Map<const Vec3<S>>(f_ + 3 * k); }

  Filter g_;
  typename Filter::State st_;
  const S* w_;
  const S* f_;
  const S* dt_;
};

/// Writes the smoothed estimates of NavFilter13 in the layout of run_nav13_batch's outputs (any
/// pointer may be null): x (n x 13), sigma (n x 13), P (n x 169), att_sigma (n x 3, rad).
template <class S> struct Nav13SmoothedOutput {
  S* x = nullptr;
  S* sigma = nullptr;
  S* P = nullptr;
  S* att_sigma = nullptr;

  template <class Record> void operator()(std::size_t k, const Record& r, const Mat<S, 12, 12>& Pe) const {
    if (x) Eigen::Map<Vec<S, 13>>(x + 13 * k) = r.x;
    const Mat<S, 13, 13> P13 = r.P.unpack();
    if (sigma) Eigen::Map<Vec<S, 13>>(sigma + 13 * k) = P13.diagonal().cwiseMax(S(0)).cwiseSqrt();
    if (P) Eigen::Map<Mat<S, 13, 13>>(P + 169 * k) = P13;
    if (att_sigma)
      Eigen::Map<Vec3<S>>(att_sigma + 3 * k) = Pe.template block<3, 3>(3, 3).diagonal().cwiseMax(S(0)).cwiseSqrt();
  }
};

}  // namespace quatnav
