// quatnav: input checks shared by every filter (saturation, checked normalization), the
// levelling of an accelerometer sample, the mapping of an update's status to batch flags, and
// the observer a batch loop reports its samples to.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "fields.hpp"
#include "types.hpp"

namespace quatnav {
namespace detail {

/// True when a finite reading reaches the sensor's range on any axis (|v_i| >= range); a
/// range <= 0 means unlimited. Non-finite readings are not "saturated" (they are NonFinite).
template <class S> bool saturated(const Vec3<S>& v, S range) {
  return range > S(0) && v.allFinite() && v.cwiseAbs().maxCoeff() >= range;
}

/// Normalize a vector that must not be zero: NonFinite on non-finite input and on finite input
/// whose norm overflows (|v| beyond the largest S, e.g. 2e19 in float: v / inf would be the zero
/// vector, and the parts that keep |v| would keep inf), ZeroNorm on (near) zero input.
template <class S> Status unit_vector(const Vec3<S>& v, Vec3<S>& u) {
  if (!v.allFinite()) return Status::NonFinite;
  const S n = v.norm();
  if (!std::isfinite(n)) return Status::NonFinite;
  if (!(n > std::sqrt(std::numeric_limits<S>::min()))) return Status::ZeroNorm;
  u = v / n;
  return Status::Ok;
}

/// Levelling: roll and pitch (rad, ZYX) of a body at rest from its specific force f_b (body FRD,
/// any scale: at rest f_b = -C_bn g_n points up in the body frame):
///     roll = atan2(-f_y, -f_z),  pitch = atan2(f_x, sqrt(f_y^2 + f_z^2)).
/// The caller decides whether f_b is normalized first (the result is the same up to rounding).
template <class S> void level_from_acc(const Vec3<S>& f_b, S& roll, S& pitch) {
  roll = std::atan2(-f_b[1], -f_b[2]);
  pitch = std::atan2(f_b[0], std::sqrt(f_b[1] * f_b[1] + f_b[2] * f_b[2]));
}

/// True when every floating-point field of a struct declared with QUATNAV_FIELDS (fields.hpp),
/// nested field structs included, is finite: the check of a state before set_state takes it.
template <class T> bool fields_finite(const T& s) {
  bool ok = true;
  for_each_field(s, [&ok](const FieldInfo&, const auto& v) {
    using M = std::decay_t<decltype(v)>;
    if constexpr (has_fields_v<M>) {
      ok = ok && fields_finite(v);
    } else if constexpr (std::is_floating_point_v<M>) {
      ok = ok && std::isfinite(v);
    } else if constexpr (std::is_base_of_v<Eigen::MatrixBase<M>, M>) {
      ok = ok && v.allFinite();
    }
  });
  return ok;
}

}  // namespace detail

/// The batch flags of one update's outcome: 0 when applied, `rejected` when gated out, `skipped`
/// (with flags::kSaturated or flags::kSolveFailed where that was the reason) otherwise.
template <class S, int M>
std::uint32_t update_flags(const UpdateResult<S, M>& r, std::uint32_t skipped, std::uint32_t rejected) {
  switch (r.status) {
    case Status::Ok: return 0;
    case Status::Rejected: return rejected;
    case Status::Saturated: return flags::kSaturated | skipped;
    case Status::SolveFailed:
    case Status::NumericalFailure: return flags::kSolveFailed | skipped;
    default: return skipped;
  }
}

/// What a batch loop reports to an observer: after_predict(k, f) after the time update of sample
/// k (applied or not), after_sample(k, f) after every step of sample k. The default does nothing;
/// the smoother's forward record is one (core/smoother.hpp).
struct NoBatchObserver {
  template <class F> void after_predict(std::size_t, const F&) {}
  template <class F> void after_sample(std::size_t, const F&) {}
};

}  // namespace quatnav
