// quatnav: the Rauch-Tung-Striebel smoothers of the attitude filters: QuaternionESKF (the
// default QuaternionEKF, 6-state multiplicative error state) and EulerEKF.
//
// The models of core/smoother.hpp, written on the filters' public API: a copy of the filter
// recomputes the time update of a sample from a stored posterior (set_state, predict), and the
// transition is the one the time update uses:
//  * QuaternionESKF: error state [dtheta (body frame, q_true = q * exp(dtheta)), db], Phi =
//    [C(dq)^T  -dt I; 0  I] (detail::eskf_propagate); the smoothed attitude is the forward
//    quaternion turned by the smoothed error rotation, q^s = q * exp(d_theta), the smoothed bias
//    b + d_b. Record: q, b and the upper triangle of the 6x6 P: 28 scalars (224 bytes in
//    double, 112 in float; 16 more per record, core/smoother.hpp).
//  * EulerEKF: state [roll, pitch, yaw, b] with additive errors (roll and yaw differences wrapped
//    to (-pi, pi]), Phi = the Jacobian of the Euler-rate step (detail::euler_propagate). Record:
//    Euler angles, b, P: 27 scalars.
// Both filters update with the accelerometer at every sample, so every sample is a record: 1e7
// samples take 2.4 GB in double (docs/SMOOTHING.md has the measured figures).
#pragma once

#include <cstddef>
#include <cstdint>

#include "../core/quaternion.hpp"
#include "../core/smoother.hpp"
#include "../core/types.hpp"
#include "euler_ekf.hpp"
#include "quaternion_eskf.hpp"

namespace quatnav {

namespace detail {

/// What both attitude models share: the filter copy that recomputes a time update from a stored
/// posterior, and the batch run's gyro samples and steps.
template <class Filter> class AttitudeRtsBase {
 public:
  using S = typename Filter::Scalar;
  AttitudeRtsBase(const Filter& f, const S* gyr, const S* dt) : g_(f), st_(f.state()), gyr_(gyr), dt_(dt) {
    st_.initialized = true;
  }

 protected:
  /// The time update of sample k from the state st_ (filled by the model): Predict, Same when
  /// the filter refuses it (as it did in the forward pass), Restart when the state is refused.
  RtsLink predict_from_state(std::size_t k) {
    if (g_.set_state(st_) != Status::Ok) return RtsLink::Restart;
    return g_.predict(gyro(k), dt_[k]) == Status::Ok ? RtsLink::Predict : RtsLink::Same;
  }
  Vec3<S> gyro(std::size_t k) const { return Eigen::Map<const Vec3<S>>(gyr_ + 3 * k); }

  Filter g_;
  typename Filter::State st_;
  const S* gyr_;
  const S* dt_;
};

}  // namespace detail

/// The smoother model of QuaternionESKF<S>.
template <class S> class QuaternionESKFRtsModel : public detail::AttitudeRtsBase<QuaternionESKF<S>> {
  using Base = detail::AttitudeRtsBase<QuaternionESKF<S>>;

 public:
  using Filter = QuaternionESKF<S>;
  using Scalar = S;
  static constexpr int kErr = 6;
  using Mat6 = Mat<S, 6, 6>;
  struct Record {
    Quat<S> q;
    Vec3<S> b;
    PackedSym<S, 6> P;
  };

  /// f: the filter before the run (parameters, and a complete state for set_state); gyr (n x 3),
  /// dt (n): the batch run's samples.
  QuaternionESKFRtsModel(const Filter& f, const S* gyr, const S* dt) : Base(f, gyr, dt) {}

  bool capture(const Filter& f, Record& r) const {
    if (!f.initialized()) return false;
    r.q = f.quat();
    r.b = f.bias();
    r.P.pack(f.covariance());
    return true;
  }
  bool same(const Record& a, const Record& b) const { return a.q == b.q && a.b == b.b && a.P == b.P; }
  bool restart(const Record&, const Record&) const { return false; }

  RtsLink predict(std::size_t k, const Record& post, Record& prior, Mat6* Phi) {
    this->st_.q = post.q;
    this->st_.bias = post.b;
    this->st_.P = post.P.unpack();
    const RtsLink link = this->predict_from_state(k);
    if (link != RtsLink::Predict) return link;
    capture(this->g_, prior);
    if (Phi) {
      Quat<S> q_next;
      Mat3<S> F;
      detail::eskf_propagate(post.q, post.b, this->gyro(k), this->dt_[k], q_next, F);
      Phi->setIdentity();
      Phi->template topLeftCorner<3, 3>() = F;
      Phi->template topRightCorner<3, 3>() = -this->dt_[k] * Mat3<S>::Identity();
    }
    return RtsLink::Predict;
  }

  Mat6 error_covariance(const Record& r) const { return r.P.unpack(); }

  /// x [-] base = [log(q_b^-1 q), b - b_b].
  Vec<S, 6> local(const Record& base, const Record& x) const {
    Vec<S, 6> d;
    d.template head<3>() = quat::to_rotvec(quat::mul(quat::conj(base.q), x.q));
    d.template tail<3>() = x.b - base.b;
    return d;
  }
  void retract(const Record& base, const Vec<S, 6>& d, const Mat6& Ps, Record& out) const {
    const Quat<S> q = quat::mul(base.q, quat::from_rotvec(Vec3<S>(d.template head<3>())));
    out.q = q / q.norm();
    out.b = base.b + d.template tail<3>();
    out.P.pack(Ps);
  }

  static Quat<S> quat_of(const Record& r) { return r.q; }
  static Vec3<S> att_variance(const Record&, const Mat6& Pe) { return Pe.diagonal().template head<3>(); }
};

/// The smoother model of EulerEKF<S>.
template <class S> class EulerEKFRtsModel : public detail::AttitudeRtsBase<EulerEKF<S>> {
  using Base = detail::AttitudeRtsBase<EulerEKF<S>>;

 public:
  using Filter = EulerEKF<S>;
  using Scalar = S;
  static constexpr int kErr = 6;
  using Mat6 = Mat<S, 6, 6>;
  struct Record {
    Vec3<S> e;
    Vec3<S> b;
    PackedSym<S, 6> P;
  };

  EulerEKFRtsModel(const Filter& f, const S* gyr, const S* dt) : Base(f, gyr, dt) {}

  bool capture(const Filter& f, Record& r) const {
    if (!f.initialized()) return false;
    r.e = f.euler();
    r.b = f.bias();
    r.P.pack(f.covariance());
    return true;
  }
  bool same(const Record& a, const Record& b) const { return a.e == b.e && a.b == b.b && a.P == b.P; }
  bool restart(const Record&, const Record&) const { return false; }

  RtsLink predict(std::size_t k, const Record& post, Record& prior, Mat6* Phi) {
    this->st_.euler = post.e;
    this->st_.bias = post.b;
    this->st_.P = post.P.unpack();
    const RtsLink link = this->predict_from_state(k);
    if (link != RtsLink::Predict) return link;
    capture(this->g_, prior);
    if (Phi) {
      Vec3<S> e;
      Mat3<S> E;
      bool singular = false;
      detail::euler_propagate(post.e, post.b, this->gyro(k), this->dt_[k], this->g_.params().singular_cos, e, *Phi, E,
                              singular);
    }
    return RtsLink::Predict;
  }

  Mat6 error_covariance(const Record& r) const { return r.P.unpack(); }

  /// x [-] base: the Euler-angle differences (roll and yaw wrapped to (-pi, pi]) and b - b_b.
  Vec<S, 6> local(const Record& base, const Record& x) const {
    Vec<S, 6> d;
    d.template head<3>() = x.e - base.e;
    d[0] = quat::wrap_pi(d[0]);
    d[2] = quat::wrap_pi(d[2]);
    d.template tail<3>() = x.b - base.b;
    return d;
  }
  void retract(const Record& base, const Vec<S, 6>& d, const Mat6& Ps, Record& out) const {
    out.e = base.e + d.template head<3>();
    out.e[0] = quat::wrap_pi(out.e[0]);
    out.e[2] = quat::wrap_pi(out.e[2]);
    out.b = base.b + d.template tail<3>();
    out.P.pack(Ps);
  }

  static Quat<S> quat_of(const Record& r) { return quat::from_euler(r.e); }
  /// The body-frame rotation-vector variance W P_ee W^T (EulerEKF::attitude_covariance).
  static Vec3<S> att_variance(const Record& r, const Mat6& Pe) {
    const S cr = std::cos(r.e[0]), sr = std::sin(r.e[0]), cp = std::cos(r.e[1]), sp = std::sin(r.e[1]);
    Mat3<S> W;
    W << S(1), S(0), -sp, S(0), cr, sr * cp, S(0), -sr, cr * cp;
    return (W * Pe.template topLeftCorner<3, 3>() * W.transpose()).diagonal();
  }
};

/// The smoother model of an attitude filter (void: the filter has none).
template <class F> struct AttitudeRtsModelOf {
  using type = void;
};
template <class S> struct AttitudeRtsModelOf<QuaternionESKF<S>> {
  using type = QuaternionESKFRtsModel<S>;
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
