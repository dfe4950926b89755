// quatnav: type aliases and the step status shared by every filter.
//
// Conventions (stated once here, in README.md and in python/quatnav/core/quaternion.py):
//  * Quaternions are Hamilton, scalar first: q = [w, x, y, z] in every array.
//  * q_nb rotates body-frame vectors into the navigation frame: v_n = q_nb * v_b * conj(q_nb),
//    i.e. v_n = C_nb v_b with C_nb = to_rotmat(q_nb).
//  * Navigation frame NED (x north, y east, z down) unless a function says otherwise;
//    body frame forward-right-down.
//  * SI units and radians. Euler angles are ZYX: C_nb = Rz(yaw) Ry(pitch) Rx(roll).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "flags.hpp"

namespace quatnav {

template <class S> using Vec2 = Eigen::Matrix<S, 2, 1>;
template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Vec4 = Eigen::Matrix<S, 4, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S> using Mat4 = Eigen::Matrix<S, 4, 4>;
template <class S> using Mat43 = Eigen::Matrix<S, 4, 3>;
template <class S> using Mat34 = Eigen::Matrix<S, 3, 4>;
template <class S, int N> using Vec = Eigen::Matrix<S, N, 1>;
template <class S, int R, int C> using Mat = Eigen::Matrix<S, R, C>;
/// A quaternion stored scalar first, [w, x, y, z] (Hamilton).
template <class S> using Quat = Eigen::Matrix<S, 4, 1>;

/// Product of two fixed-size matrices, evaluated coefficient by coefficient into a fixed-size
/// result (Eigen's lazyProduct). Eigen sends a product with an inner dimension of 8 or more (or
/// both outer dimensions of 8 or more) to its blocked GEMM kernel even at fixed size; that kernel
/// carries a heap fallback that is never taken for fixed sizes but still links malloc and free
/// into a bare-metal image. For products below that size Eigen already evaluates this way, so
/// results there are bit-for-bit those of operator*. The filters with 12 to 15 states use this
/// for every matrix-matrix product of that size (see docs/PORTING.md).
template <class A, class B>
Eigen::Matrix<typename A::Scalar, A::RowsAtCompileTime, B::ColsAtCompileTime> fixed_mul(const Eigen::MatrixBase<A>& a,
                                                                                      const Eigen::MatrixBase<B>& b) {
  static_assert(A::RowsAtCompileTime > 0 && A::ColsAtCompileTime > 0 && B::ColsAtCompileTime > 0,
                "fixed_mul: fixed-size operands only");
  return a.lazyProduct(b);
}

/// What a step did. A step that does not return Ok or Rejected left the state untouched.
enum class Status : std::uint8_t {
  Ok = 0,             ///< step applied
  NotInitialized,     ///< the filter has no attitude yet (call initialize or reset)
  NonFinite,          ///< an input was NaN or infinite (or a vector's norm overflowed); nothing changed
  ZeroNorm,           ///< a vector that must be normalized had (near) zero norm; nothing changed
  InvalidDt,          ///< dt <= 0, non-finite, or above the filter's max_dt; nothing changed
  Saturated,          ///< a reading was at or above the sensor's range; nothing changed
  SolveFailed,        ///< the innovation covariance was not positive definite; nothing changed
  Rejected,           ///< the innovation failed the chi-square gate; nothing changed
  NumericalFailure,   ///< the result would have been non-finite; nothing changed
  InvalidArgument,    ///< a parameter or state given to the filter is malformed; nothing changed
};

inline const char* to_string(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::NotInitialized: return "not_initialized";
    case Status::NonFinite: return "non_finite";
    case Status::ZeroNorm: return "zero_norm";
    case Status::InvalidDt: return "invalid_dt";
    case Status::Saturated: return "saturated";
    case Status::SolveFailed: return "solve_failed";
    case Status::Rejected: return "rejected";
    case Status::NumericalFailure: return "numerical_failure";
    case Status::InvalidArgument: return "invalid_argument";
  }
  return "unknown";
}

/// The outcome of one measurement update with M rows.
template <class S, int M>
struct UpdateResult {
  Status status = Status::NotInitialized;
  Vec<S, M> innovation = Vec<S, M>::Zero();     ///< z - h(x) before the update
  Mat<S, M, M> innovation_cov = Mat<S, M, M>::Zero();  ///< S = H P H^T + R
  S nis = S(0);                                 ///< innovation^T S^-1 innovation
  bool accepted() const { return status == Status::Ok; }
};

}  // namespace quatnav
