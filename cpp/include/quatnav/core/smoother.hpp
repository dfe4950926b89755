// quatnav: the Rauch-Tung-Striebel backward pass in error-state form, once for every filter.
//
// A forward filter gives, at every sample k, the posterior (the nominal state x_k and the
// covariance P_k of its error state) and, from it, the prior of the next sample: the nominal
// x_{k+1|k} and P_{k+1|k} of its time update, and the transition Phi_k of the error state over
// that step. The backward pass (Rauch, Tung & Striebel 1965; Särkkä 2013, ch. 8, in error-state
// form) runs from the last sample to the first:
//     C_k    = P_k Phi_k^T P_{k+1|k}^-1                       (the smoother gain; D_k P_{k+1|k}^-1
//                                                               with the cross-covariance D_k of
//                                                               a sigma-point time update)
//     d_k    = C_k (x^s_{k+1} [-] x_{k+1|k})                 (a correction of the posterior)
//     x^s_k  = x_k [+] d_k
//     P^s_k  = P_k + C_k (P^s_{k+1} - P_{k+1|k}) C_k^T
// where [+] and [-] are the filter's own error-state chart: for the attitude the multiplicative
// form (q^s = q * exp(dtheta), the correction an error rotation applied to the forward estimate,
// quat_block.hpp), for Euclidean parts addition. P^s_{k+1} is taken in the error coordinates of
// x_{k+1|k} (not transported to those of x^s_{k+1}: the transport differs from I by
// [d/2 x] for an attitude correction d, a second-order term, as the covariance reset that the
// feedback filters leave out).
//
// What the backward pass needs is not stored per sample. The forward pass keeps a record
// (nominal and covariance, compact: the symmetric covariance as its upper triangle) only
//   * at an epoch: a sample whose posterior differs from the prediction of the previous one
//     (a measurement was applied, a reset made; a rejected measurement changes nothing and
//     leaves no record), and
//   * every `segment` samples otherwise (a checkpoint),
// and recomputes the pure-prediction stretch between two records, one segment at a time, by
// the filter's own time update (the same code on the same state and input: the same bits); the
// posterior of a sample inside such a stretch is the prior of the step into it. The transition
// of every step, and the prior of a step into a record, are recomputed from the posterior and
// the IMU sample.
// What the forward pass decided is kept: a rejected measurement left the state as it was, a
// skipped time update (saturated or invalid sample) is recomputed as skipped (the link is
// "same": the state did not move, so neither does the smoothed one), a reset or a
// (re)initialization is a record that the backward pass does not cross (restart: the smoothed
// estimate before it uses the data up to it).
//
// Memory (the one heap allocation, made once before the forward loop, RtsSmoother::reserve):
//   (max_epochs + n / segment + 2) records + segment records,
// a record being the model's compact posterior plus 16 bytes; max_epochs is at most the number
// of samples at which an aid was applied (every sample for the attitude filters, which update
// with the accelerometer at each sample; the GNSS/velocity/heading samples for the navigation
// filters). docs/SMOOTHING.md has the figures per filter.
//
// A model (one per filter, next to it: attitude/smoother.hpp, nav/nav13_smoother.hpp, ...)
// provides:
//   using Scalar; static constexpr int kErr;     error-state dimension N
//   struct Record;                                the compact posterior (trivially copyable)
//   bool capture(const Filter&, Record&) const;   false while the filter has no estimate to smooth
//   bool same(const Record&, const Record&) const;  bit-for-bit equal
//   bool restart(const Record& predicted, const Record& post) const;
//       the steps of a sample made a reset (not a measurement): the backward pass does not cross it
//   RtsLink predict(std::size_t k, const Record& post, Record& prior);
//       the time update of sample k from the posterior of sample k - 1, with the filter's own
//       predict: Predict, or Same when the filter refuses it (the state does not move)
//   RtsLink transition(std::size_t k, const Record& post, const Record& prior, Mat<S, N, N>& Phi);
//       of that time update (prior: its result), the error-state transition (link Predict), or,
//       for a sigma-point time update, the cross-covariance of the error states before and after
//       the step (link Cross: the gain is then D P_{k+1|k}^-1, the unscented RTS smoother of
//       Särkkä 2008); Restart when it cannot be had
//   Mat<S, N, N> error_covariance(const Record&) const;
//   Vec<S, N> local(const Record& base, const Record& x) const;   x [-] base
//   void retract(const Record& base, const Vec<S, N>& d, const Mat<S, N, N>& Ps, Record& out) const;
//       out = base [+] d with the error covariance Ps
// Fixed-size Eigen inside the recursion; no allocation after reserve().
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>

#include "kalman.hpp"
#include "types.hpp"

namespace quatnav {

/// A symmetric N x N matrix as its upper triangle, column by column (N (N + 1) / 2 coefficients).
template <class S, int N> struct PackedSym {
  static constexpr int kSize = N * (N + 1) / 2;
  S v[kSize];

  void pack(const Mat<S, N, N>& P) {
    int i = 0;
    for (int c = 0; c < N; ++c)
      for (int r = 0; r <= c; ++r) v[i++] = P(r, c);
  }
  /// The matrix, exactly symmetric (the upper triangle mirrored).
  Mat<S, N, N> unpack() const {
    Mat<S, N, N> P;
    int i = 0;
    for (int c = 0; c < N; ++c)
      for (int r = 0; r <= c; ++r) P(r, c) = P(c, r) = v[i++];
    return P;
  }
  /// The diagonal coefficient (i, i).
  S diag(int i) const { return v[i * (i + 1) / 2 + i]; }
  bool operator==(const PackedSym& o) const {
    for (int i = 0; i < kSize; ++i)
      if (!(v[i] == o.v[i])) return false;
    return true;
  }
};

/// How sample k is linked to sample k + 1 in the backward pass.
enum class RtsLink : std::uint8_t {
  Predict = 0,  ///< a time update: the RTS step
  Same = 1,     ///< the time update was refused: the state did not move (x^s_k = x^s_{k+1})
  Restart = 2,  ///< no link (a reset, a (re)initialization, a failed step): x^s_k = x_k
  Cross = 3,    ///< a time update given by the cross-covariance D of the errors before and after it
};

/// One RTS step in error-state form. Inputs: the posterior error covariance P at k, the
/// cross-covariance B of the errors at k and k + 1 (P Phi^T for a transition Phi), the prior
/// P_prior at k + 1, the smoothed correction of the prior d_next = x^s_{k+1} [-] x_{k+1|k} and the
/// smoothed covariance Ps_next at k + 1. Outputs: the correction d of the posterior at k
/// (x^s_k = x_k [+] d) and Ps. The gain is C = B P_prior^-1 by a Cholesky factorization of
/// P_prior and two triangular solves (never an inverse: kalman.hpp's substitution loops).
/// False, outputs untouched, when P_prior is not positive definite or the result is not finite.
/// The time update's prior is used as the filter computed it.
template <class S, int N>
bool rts_step(const Mat<S, N, N>& P, const Mat<S, N, N>& B, const Mat<S, N, N>& P_prior, const Vec<S, N>& d_next,
              const Mat<S, N, N>& Ps_next, Vec<S, N>& d, Mat<S, N, N>& Ps) {
  Mat<S, N, N> L;
  Vec<S, N> inv_diag;
  if (!detail::cholesky_small<S, N>(P_prior, L, inv_diag)) return false;
  Mat<S, N, N> Z, C;
  detail::solve_right_lower_transposed<S, N, N>(L, inv_diag, B, Z);  // Z L^T = B
  detail::solve_right_lower<S, N, N>(L, inv_diag, Z, C);              // C L = Z: C = B P_prior^-1
  Vec<S, N> dn;
  dn.noalias() = C * d_next;
  Mat<S, N, N> D = Ps_next - P_prior, CD, Pn;
  CD.noalias() = C.lazyProduct(D);
  Pn = P;
  Pn.noalias() += CD.lazyProduct(C.transpose());
  symmetrize(Pn);
  if (!all_finite(Pn) || !all_finite(dn)) return false;
  d = dn;
  Ps = Pn;
  return true;
}

/// The forward record and the backward pass for one filter model (see the top of this file).
/// Used by a batch loop as its observer (after_predict / after_sample), then smooth().
template <class Model> class RtsSmoother {
 public:
  using S = typename Model::Scalar;
  static constexpr int N = Model::kErr;
  using Record = typename Model::Record;
  using MatN = Mat<S, N, N>;
  using VecN = Vec<S, N>;

  /// What the smoother did, for the caller's status.
  enum class Result : std::uint8_t { Ok = 0, NothingToSmooth, OutOfCapacity, NotReserved };

  explicit RtsSmoother(Model& model) : m_(model) {}

  /// The one allocation: records for max_epochs epochs of n samples, with a checkpoint every
  /// `segment` samples. False when the memory cannot be had (nothing allocated).
  bool reserve(std::size_t n, std::size_t max_epochs, std::size_t segment = 256) {
    seg_ = segment < 1 ? 1 : segment;
    cap_ = max_epochs + n / seg_ + 2;
    if (cap_ > n + 1) cap_ = n + 1;
    const std::size_t total = cap_ + seg_;
    buf_.reset(new (std::nothrow) Entry[total]);
    if (!buf_) {
      cap_ = 0;
      return false;
    }
    size_ = 0;
    active_ = false;
    ended_ = false;
    overflow_ = false;
    return true;
  }

  /// Bytes held by the records and the segment buffer.
  std::size_t bytes() const { return buf_ ? (cap_ + seg_) * sizeof(Entry) : 0; }
  static constexpr std::size_t record_bytes() { return sizeof(Entry); }
  std::size_t records() const { return size_; }
  std::size_t capacity() const { return cap_; }
  std::size_t segment() const { return seg_; }

  // ---- the forward pass: the batch loop reports every sample ----------------------------

  /// After the time update of sample k (called whether or not it was applied).
  template <class F> void after_predict(std::size_t k, const F& f) {
    pred_k_ = k;
    have_pred_ = m_.capture(f, pred_);
  }

  /// After every step of sample k (time update and measurements).
  template <class F> void after_sample(std::size_t k, const F& f) {
    if (!buf_ || ended_) return;
    Record r;
    if (!m_.capture(f, r)) {
      if (active_) ended_ = true;  // an estimate that stops: the samples from here keep the forward result
      return;
    }
    const bool predicted = have_pred_ && pred_k_ == k;
    const bool restart = !active_ || !predicted || m_.restart(pred_, r);
    const bool pure = predicted && m_.same(pred_, r);
    const bool checkpoint = size_ > 0 && k - buf_[size_ - 1].k >= seg_;
    if (restart || !pure || checkpoint) {
      if (size_ >= cap_) {
        overflow_ = true;
        ended_ = true;
        return;
      }
      Entry& e = buf_[size_++];
      e.x = r;
      e.k = k;
      e.link = restart ? RtsLink::Restart : RtsLink::Predict;
    }
    active_ = true;
    last_k_ = k;
    have_pred_ = false;
  }

  // ---- the backward pass ----------------------------------------------------------------

  /// Run the backward pass; out(k, x^s_k, P^s_k) is called for every smoothed sample, from the
  /// last to the first (samples before the first record, or after the estimate stopped, are not
  /// visited: they keep the forward result). The recursion is computed in double whatever the
  /// filter's scalar: a float32 filter's covariance spans ten decades (velocity against gyro
  /// bias), beyond what a float Cholesky factor of P_{k+1|k} resolves; P^s is handed to the
  /// model and to `out` in S.
  template <class Out> Result smooth(Out&& out) {
    using T = double;
    using MatT = Mat<T, N, N>;
    if (!buf_) return Result::NotReserved;
    if (overflow_) return Result::OutOfCapacity;
    if (size_ == 0) return Result::NothingToSmooth;
    Entry* const segbuf = buf_.get() + cap_;
    Record xs_next = buf_[size_ - 1].x;  // x^s_{k+1} (set at the last sample before any use)
    MatT Ps_next = MatT::Zero();         // P^s_{k+1}
    Record prior = xs_next;
    MatN Phi = MatN::Zero();
    for (std::size_t i = size_; i-- > 0;) {
      const std::size_t a = buf_[i].k;
      const std::size_t b = i + 1 < size_ ? buf_[i + 1].k - 1 : last_k_;
      // The posteriors of the segment [a, b]: its record, then pure predictions (each entry
      // keeps how it was reached: the posterior of k + 1 inside the segment is the prior of the
      // step from k, so the backward pass recomputes only the transition there).
      segbuf[0].x = buf_[i].x;
      for (std::size_t j = 1; j <= b - a; ++j) {
        segbuf[j].link = m_.predict(a + j, segbuf[j - 1].x, segbuf[j].x);
        if (segbuf[j].link != RtsLink::Predict) segbuf[j].x = segbuf[j - 1].x;
      }
      for (std::size_t k = b + 1; k-- > a;) {
        const Record& post = segbuf[k - a].x;
        RtsLink link = RtsLink::Restart;
        const Record* pr = &prior;
        if (k == last_k_ || (k == b && i + 1 < size_ && buf_[i + 1].link == RtsLink::Restart)) {
          link = RtsLink::Restart;  // the last sample, or a restart at k + 1
        } else if (k < b) {
          link = segbuf[k + 1 - a].link;
          pr = &segbuf[k + 1 - a].x;
        } else {
          link = m_.predict(k + 1, post, prior);
        }
        if (link == RtsLink::Predict) link = m_.transition(k + 1, post, *pr, Phi);
        if (link != RtsLink::Same) {  // Same: x^s_k = x^s_{k+1}, P^s_k = P^s_{k+1}
          const MatT P = m_.error_covariance(post).template cast<T>();
          Vec<T, N> d;
          MatT Ps;
          MatT B;
          if (link == RtsLink::Predict) B.noalias() = P.lazyProduct(Phi.template cast<T>().transpose());  // P Phi^T
          if (link == RtsLink::Cross) B = Phi.template cast<T>();
          if ((link == RtsLink::Predict || link == RtsLink::Cross) &&
              rts_step<T, N>(P, B, m_.error_covariance(*pr).template cast<T>(),
                             m_.local(*pr, xs_next).template cast<T>(), Ps_next, d, Ps)) {
            m_.retract(post, VecN(d.template cast<S>()), MatN(Ps.template cast<S>()), xs_next);
            Ps_next = Ps;
          } else {
            xs_next = post;
            Ps_next = P;
          }
        }
        out(k, static_cast<const Record&>(xs_next), MatN(Ps_next.template cast<S>()));
      }
    }
    return Result::Ok;
  }

 private:
  struct Entry {
    Record x;
    std::size_t k;
    RtsLink link;  ///< a record: Restart when the backward pass does not cross into it (else
                   ///< Predict); the segment buffer: how the entry was reached from the previous
  };

  Model& m_;
  std::unique_ptr<Entry[]> buf_;
  std::size_t cap_ = 0, seg_ = 256, size_ = 0, last_k_ = 0, pred_k_ = 0;
  Record pred_{};
  bool have_pred_ = false, active_ = false, ended_ = false, overflow_ = false;
};

}  // namespace quatnav
