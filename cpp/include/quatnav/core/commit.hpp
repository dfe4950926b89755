// quatnav: the one path from an accepted Kalman correction to a filter's state.
//
// Every filter corrects the same way (paper 000 eq. 15-17, 002 eq. 22-23, 004's feedback):
//
//   correct    the Kalman correction (kalman.hpp) gives the corrected covariance P and the
//              state increment dx, or refuses (SolveFailed, Rejected, NumericalFailure);
//   inject     dx is applied to a candidate copy of the state (the filter's own state is not
//              touched yet);
//   check      the candidate is one the filter can keep (finite, |q| near 1, within range);
//   condition  the constrained part is renormalized with its covariance projected, the
//              covariance floored (covariance.hpp, quat_block.hpp); this may refuse too;
//   commit     only now the candidate and P replace the filter's state.
//
// inject_and_commit() is that sequence; a filter supplies its inject, check, condition and
// commit steps. A refusal at any step leaves the state bit for bit as it was and reports
// NumericalFailure; a refused correction keeps the status it gave.
#pragma once

#include <cmath>

#include "types.hpp"

namespace quatnav {

/// Run inject -> check -> condition -> commit on a correction whose status is `res.status`
/// (nothing happens unless it is Ok). inject() returns the candidate; check(candidate, P) and
/// condition(candidate, P) return false to refuse; commit(candidate, P) stores both.
/// Returns res.status.
template <class S, int M, class P_t, class Inject, class Check, class Condition, class Commit>
Status inject_and_commit(UpdateResult<S, M>& res, P_t& P, Inject&& inject, Check&& check, Condition&& condition,
                         Commit&& commit) {
  if (res.status != Status::Ok) return res.status;
  // An accepted correction reports finite outputs: an innovation covariance that overflowed
  // (a covariance near the overflow limit) refuses it.
  if (!res.innovation.allFinite() || !res.innovation_cov.allFinite() || !std::isfinite(res.nis)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  auto candidate = inject();
  if (!check(static_cast<const decltype(candidate)&>(candidate), static_cast<const P_t&>(P)) ||
      !condition(candidate, P)) {
    res.status = Status::NumericalFailure;
    return res.status;
  }
  commit(candidate, P);
  return res.status;
}

/// A step that always succeeds (no check, or no conditioning).
struct Always {
  template <class... A> bool operator()(A&&...) const { return true; }
};

}  // namespace quatnav
