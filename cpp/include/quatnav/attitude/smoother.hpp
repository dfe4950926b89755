// quatnav: the Rauch-Tung-Striebel smoothers of the attitude filters: QuaternionEKF (the
// default, 6-state multiplicative error state) and EulerEKF.
//
// The models of core/smoother.hpp, written on the filters' public API: a copy of the filter
// recomputes the time update of a sample from a stored posterior (set_state, predict), and the
// transition is the one the time update uses:
//  * QuaternionEKF: error state [dtheta (body frame, q_true = q * exp(dtheta)), db], Phi =
//    [C(dq)^T  -dt I; 0  I] (detail::eskf_propagate); the smoothed attitude is the forward
//    quaternion turned by the smoothed error rotation, q^s = q * exp(d_theta), the smoothed bias
//    b + d_b. Record: q, b and the upper triangle of the 6x6 P: 28 scalars (224 bytes in
//    double, 112 in float; 16 more per record, core/smoother.hpp), and the clip recognition's
//    state (parts/gyro_clip.hpp: 7 scalars and a flag, 64 bytes in double, 32 in float), which
//    the recomputed time update reads.
//  * EulerEKF: state [roll, pitch, yaw, b] with additive errors (roll and yaw differences wrapped
//    to (-pi, pi]), Phi = the Jacobian of the Euler-rate step (detail::euler_propagate). Record:
//    Euler angles, b, P: 27 scalars.
// Both filters update with the accelerometer at every sample, so every sample is a record: 1e7
// samples take 2.4 GB in double (docs/SMOOTHING.md has the measured figures).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "../core/quaternion.hpp"
#include "../core/smoother.hpp"
#include "../core/types.hpp"
#include "euler_ekf.hpp"
#include "quaternion_ekf.hpp"

namespace quatnav {

namespace detail {

/// No part state that the time update reads (EulerEKF): an empty base, no bytes in the record.
struct NoTimeUpdateParts {};
template <class Parts> struct RecordParts {
  Parts parts;  ///< the time update's part state
};
template <> struct RecordParts<NoTimeUpdateParts> {};

/// What both attitude models share (CRTP; Derived supplies the attitude part): the record
/// [attitude (NA), gyro bias, P, Parts], the filter copy that recomputes a time update from a
/// stored posterior, and the batch run's gyro samples and steps. Parts: the state of the parts
/// that the time update itself reads (QuaternionEKF: the clip recognition, parts/gyro_clip.hpp,
/// which depends on the readings before), recorded with each posterior and restored before the
/// recomputed time update, so that it adds the forward pass's variance. Derived provides
///   static Vec<S, NA> attitude(const Filter&);  static void set_attitude(State&, const Vec<S, NA>&);
///   Mat6 step_transition(const Record& post, std::size_t k) const;
///   static Vec3<S> attitude_local(base, x);  static Vec<S, NA> attitude_retract(base, d);
template <class Derived, class Filter_, int NA, class Parts = NoTimeUpdateParts> class AttitudeRtsModel {
 public:
  using Filter = Filter_;
  using S = typename Filter::Scalar;
  using Scalar = S;
  static constexpr int kErr = 6;
  using Mat6 = Mat<S, 6, 6>;
  struct Record : RecordParts<Parts> {
    Vec<S, NA> a;  ///< attitude (q_nb, or Euler angles)
    Vec3<S> b;     ///< gyro bias
    PackedSym<S, 6> P;
  };

  /// f: the filter before the run (parameters, and a complete state for set_state); gyr (n x 3),
  /// dt (n): the batch run's samples.
  AttitudeRtsModel(const Filter& f, const S* gyr, const S* dt) : g_(f), st_(f.state()), gyr_(gyr), dt_(dt) {
    st_.initialized = true;
  }

  bool capture(const Filter& f, Record& r) const {
    if (!f.initialized()) return false;
    r.a = Derived::attitude(f);
    r.b = f.bias();
    r.P.pack(f.covariance());
    if constexpr (!std::is_same_v<Parts, NoTimeUpdateParts>) r.parts = f.state().clip;
    return true;
  }
  bool same(const Record& x, const Record& y) const { return x.a == y.a && x.b == y.b && x.P == y.P; }
  bool restart(const Record&, const Record&) const { return false; }

  /// The filter's time update of sample k from `post`: Predict, Same when the filter refuses it
  /// (as it did in the forward pass), Restart when the state is refused.
  RtsLink predict(std::size_t k, const Record& post, Record& prior) {
    Derived::set_attitude(st_, post.a);
    st_.gyro_bias = post.b;
    st_.P = post.P.unpack();
    if constexpr (!std::is_same_v<Parts, NoTimeUpdateParts>) st_.clip = post.parts;
    if (g_.set_state(st_) != Status::Ok) return RtsLink::Restart;
    if (g_.predict(gyro(k), dt_[k]) != Status::Ok) return RtsLink::Same;
    capture(g_, prior);
    return RtsLink::Predict;
  }

  /// The transition of that step (the one the time update uses).
  RtsLink transition(std::size_t k, const Record& post, const Record&, Mat6& Phi) const {
    Phi = static_cast<const Derived&>(*this).step_transition(post, k);
    return RtsLink::Predict;
  }

  Mat6 error_covariance(const Record& r) const { return r.P.unpack(); }

  /// x [-] base: the attitude part (Derived), then b - b_b.
  Vec<S, 6> local(const Record& base, const Record& x) const {
    Vec<S, 6> d;
    d.template head<3>() = Derived::attitude_local(base.a, x.a);
    d.template tail<3>() = x.b - base.b;
    return d;
  }
  void retract(const Record& base, const Vec<S, 6>& d, const Mat6& Ps, Record& out) const {
    out.a = Derived::attitude_retract(base.a, Vec3<S>(d.template head<3>()));
    out.b = base.b + d.template tail<3>();
    out.P.pack(Ps);
    if constexpr (!std::is_same_v<Parts, NoTimeUpdateParts>) out.parts = base.parts;
  }

 protected:
  Vec3<S> gyro(std::size_t k) const { return Eigen::Map<const Vec3<S>>(gyr_ + 3 * k); }

  Filter g_;
  typename Filter::State st_;
  const S* gyr_;
  const S* dt_;
};

}  // namespace detail

/// The smoother model of QuaternionEKF<S>: attitude error dtheta in the body frame,
/// q_true = q * exp(dtheta); Phi = [C(dq)^T  -dt I; 0  I] (detail::eskf_propagate).
template <class S>
class QuaternionEKFRtsModel
    : public detail::AttitudeRtsModel<QuaternionEKFRtsModel<S>, QuaternionEKF<S>, 4, GyroClipState<S>> {
  using Base = detail::AttitudeRtsModel<QuaternionEKFRtsModel<S>, QuaternionEKF<S>, 4, GyroClipState<S>>;

 public:
  using typename Base::Filter;
  using typename Base::Mat6;
  using typename Base::Record;
  using Base::Base;

  static Vec4<S> attitude(const Filter& f) { return f.quat(); }
  static void set_attitude(typename Filter::State& st, const Vec4<S>& q) { st.q_nb = q; }
  Mat6 step_transition(const Record& post, std::size_t k) const {
    Quat<S> q_next;
    Mat3<S> F;
    detail::eskf_propagate(Quat<S>(post.a), post.b, this->gyro(k), this->dt_[k], q_next, F);
    Mat6 Phi = Mat6::Identity();
    Phi.template topLeftCorner<3, 3>() = F;
    Phi.template topRightCorner<3, 3>() = -this->dt_[k] * Mat3<S>::Identity();
    return Phi;
  }
  /// log(q_b^-1 q) and q_b * exp(d).
  static Vec3<S> attitude_local(const Vec4<S>& base, const Vec4<S>& q) {
    return quat::to_rotvec(quat::mul(quat::conj(Quat<S>(base)), Quat<S>(q)));
  }
  static Vec4<S> attitude_retract(const Vec4<S>& base, const Vec3<S>& d) {
    const Quat<S> q = quat::mul(Quat<S>(base), quat::from_rotvec(d));
    return q / q.norm();
  }

  static Quat<S> quat_of(const Record& r) { return r.a; }
  static Vec3<S> att_variance(const Record&, const Mat6& Pe) { return Pe.diagonal().template head<3>(); }
};

/// The smoother model of EulerEKF<S>: additive errors of [roll, pitch, yaw] (roll and yaw
/// differences wrapped to (-pi, pi]); Phi = the Jacobian of the Euler-rate step
/// (detail::euler_propagate).
template <class S> class EulerEKFRtsModel : public detail::AttitudeRtsModel<EulerEKFRtsModel<S>, EulerEKF<S>, 3> {
  using Base = detail::AttitudeRtsModel<EulerEKFRtsModel<S>, EulerEKF<S>, 3>;

 public:
  using typename Base::Filter;
  using typename Base::Mat6;
  using typename Base::Record;
  using Base::Base;

  static Vec3<S> attitude(const Filter& f) { return f.euler(); }
  static void set_attitude(typename Filter::State& st, const Vec3<S>& e) { st.euler = e; }
  Mat6 step_transition(const Record& post, std::size_t k) const {
    Vec3<S> e;
    Mat3<S> E;
    Mat6 F;
    bool singular = false;
    detail::euler_propagate(post.a, post.b, this->gyro(k), this->dt_[k], this->g_.params().singular_cos, false, e, F,
                            E, singular);
    return F;
  }
  static Vec3<S> attitude_local(const Vec3<S>& base, const Vec3<S>& e) {
    Vec3<S> d = e - base;
    d[0] = quat::wrap_pi(d[0]);
    d[2] = quat::wrap_pi(d[2]);
    return d;
  }
  static Vec3<S> attitude_retract(const Vec3<S>& base, const Vec3<S>& d) {
    Vec3<S> e = base + d;
    e[0] = quat::wrap_pi(e[0]);
    e[2] = quat::wrap_pi(e[2]);
    return e;
  }

  static Quat<S> quat_of(const Record& r) { return quat::from_euler(r.a); }
  /// The body-frame rotation-vector variance W P_ee W^T (EulerEKF::attitude_covariance).
  static Vec3<S> att_variance(const Record& r, const Mat6& Pe) {
    const S cr = std::cos(r.a[0]), sr = std::sin(r.a[0]), cp = std::cos(r.a[1]), sp = std::sin(r.a[1]);
    Mat3<S> W;
    W << S(1), S(0), -sp, S(0), cr, sr * cp, S(0), -sr, cr * cp;
    return (W * Pe.template topLeftCorner<3, 3>() * W.transpose()).diagonal();
  }
};

/// The smoother model of an attitude filter (void: the filter has none).
template <class F> struct AttitudeRtsModelOf {
  using type = void;
};
template <class S> struct AttitudeRtsModelOf<QuaternionEKF<S>> {
  using type = QuaternionEKFRtsModel<S>;
};
template <class S> struct AttitudeRtsModelOf<EulerEKF<S>> {
  using type = EulerEKFRtsModel<S>;
};

/// Writes the smoothed estimates of an attitude filter in the layout of run_attitude_batch's
/// outputs (any pointer may be null): quat (n x 4), bias (n x 3), sigma (n x 6), att_sigma (n x 3).
template <class Model> struct AttitudeSmoothedOutput {
  using S = typename Model::Scalar;
  S* quat = nullptr;
  S* bias = nullptr;
  S* sigma = nullptr;
  S* att_sigma = nullptr;

  void operator()(std::size_t k, const typename Model::Record& r, const Mat<S, 6, 6>& Pe) const {
    if (quat) Eigen::Map<Vec4<S>>(quat + 4 * k) = Model::quat_of(r);
    if (bias) Eigen::Map<Vec3<S>>(bias + 3 * k) = r.b;
    if (sigma) Eigen::Map<Vec<S, 6>>(sigma + 6 * k) = Pe.diagonal().cwiseMax(S(0)).cwiseSqrt();
    if (att_sigma) Eigen::Map<Vec3<S>>(att_sigma + 3 * k) = Model::att_variance(r, Pe).cwiseMax(S(0)).cwiseSqrt();
  }
};

}  // namespace quatnav
