// A scalar type that counts its floating-point operations, for the flop column of the C++
// benchmark: a filter instantiated on `Counted` runs the same code as on double (Eigen's
// fixed-size expressions, unvectorized) and every +, -, *, / and every call of sqrt, sin, ... adds
// to a global counter. Counting rules: + - * / and comparisons-free arithmetic 1 flop each;
// sqrt 1; sin, cos, tan, asin, acos, atan2, exp, cbrt, fmod 1 each (a libm call, counted once:
// the flop column is the arithmetic the filter asks for, not the cost of the math library).
// Comparisons, isnan/isfinite and abs are not counted.
//
// This header is for the benchmark only; it adds overloads to namespace std so that the filters'
// explicit std::sqrt(...) calls resolve, which the library itself never needs.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

// <Eigen/Core> is included below, after the std:: overloads: Eigen's `using std::sqrt;`
// declarations only see the overloads declared before them.

namespace quatnav_bench {

inline std::uint64_t& flop_count() {
  static std::uint64_t n = 0;
  return n;
}

struct Counted {
  double v = 0.0;
  Counted() = default;
  template <class T, class = std::enable_if_t<std::is_arithmetic<T>::value>>
  Counted(T x) : v(double(x)) {}  // NOLINT: implicit like a built-in scalar
  explicit operator double() const { return v; }
  explicit operator float() const { return float(v); }
  explicit operator int() const { return int(v); }
  explicit operator long() const { return long(v); }
  explicit operator unsigned() const { return unsigned(v); }
  explicit operator unsigned long() const { return (unsigned long)(v); }
  explicit operator bool() const { return v != 0.0; }
  Counted operator-() const { return Counted(-v); }
  Counted operator+() const { return *this; }
  Counted& operator+=(Counted o) { ++flop_count(); v += o.v; return *this; }
  Counted& operator-=(Counted o) { ++flop_count(); v -= o.v; return *this; }
  Counted& operator*=(Counted o) { ++flop_count(); v *= o.v; return *this; }
  Counted& operator/=(Counted o) { ++flop_count(); v /= o.v; return *this; }
};

inline Counted operator+(Counted a, Counted b) { ++flop_count(); return Counted(a.v + b.v); }
inline Counted operator-(Counted a, Counted b) { ++flop_count(); return Counted(a.v - b.v); }
inline Counted operator*(Counted a, Counted b) { ++flop_count(); return Counted(a.v * b.v); }
inline Counted operator/(Counted a, Counted b) { ++flop_count(); return Counted(a.v / b.v); }
inline bool operator<(Counted a, Counted b) { return a.v < b.v; }
inline bool operator>(Counted a, Counted b) { return a.v > b.v; }
inline bool operator<=(Counted a, Counted b) { return a.v <= b.v; }
inline bool operator>=(Counted a, Counted b) { return a.v >= b.v; }
inline bool operator==(Counted a, Counted b) { return a.v == b.v; }
inline bool operator!=(Counted a, Counted b) { return a.v != b.v; }

// The counting functions live in a nested namespace, out of ADL's reach, so that
// `using std::sqrt; sqrt(x)` (Eigen) finds exactly one overload: the std:: forwarders below.
namespace impl {
#define QUATNAV_BENCH_FN1(name)                                                   \
  inline Counted name(Counted a) { ++flop_count(); return Counted(std::name(a.v)); }
QUATNAV_BENCH_FN1(sqrt)
QUATNAV_BENCH_FN1(sin)
QUATNAV_BENCH_FN1(cos)
QUATNAV_BENCH_FN1(tan)
QUATNAV_BENCH_FN1(asin)
QUATNAV_BENCH_FN1(acos)
QUATNAV_BENCH_FN1(atan)
QUATNAV_BENCH_FN1(exp)
QUATNAV_BENCH_FN1(log)
QUATNAV_BENCH_FN1(cbrt)
QUATNAV_BENCH_FN1(floor)
QUATNAV_BENCH_FN1(ceil)
QUATNAV_BENCH_FN1(round)
#undef QUATNAV_BENCH_FN1
inline Counted atan2(Counted a, Counted b) { ++flop_count(); return Counted(std::atan2(a.v, b.v)); }
inline Counted fmod(Counted a, Counted b) { ++flop_count(); return Counted(std::fmod(a.v, b.v)); }
inline Counted pow(Counted a, Counted b) { ++flop_count(); return Counted(std::pow(a.v, b.v)); }
inline Counted hypot(Counted a, Counted b) { flop_count() += 4; return Counted(std::hypot(a.v, b.v)); }
inline Counted abs(Counted a) { return Counted(std::abs(a.v)); }
inline Counted fabs(Counted a) { return Counted(std::abs(a.v)); }
inline bool isnan(Counted a) { return std::isnan(a.v); }
inline bool isinf(Counted a) { return std::isinf(a.v); }
inline bool isfinite(Counted a) { return std::isfinite(a.v); }
inline bool signbit(Counted a) { return std::signbit(a.v); }
inline Counted copysign(Counted a, Counted b) { return Counted(std::copysign(a.v, b.v)); }
}  // namespace impl

}  // namespace quatnav_bench

// The filters call std::sqrt(x) etc. explicitly: forward those to the counting overloads.
namespace std {
#define QUATNAV_BENCH_STD1(name) \
  inline quatnav_bench::Counted name(quatnav_bench::Counted a) { return quatnav_bench::impl::name(a); }
QUATNAV_BENCH_STD1(sqrt)
QUATNAV_BENCH_STD1(sin)
QUATNAV_BENCH_STD1(cos)
QUATNAV_BENCH_STD1(tan)
QUATNAV_BENCH_STD1(asin)
QUATNAV_BENCH_STD1(acos)
QUATNAV_BENCH_STD1(atan)
QUATNAV_BENCH_STD1(exp)
QUATNAV_BENCH_STD1(log)
QUATNAV_BENCH_STD1(cbrt)
QUATNAV_BENCH_STD1(floor)
QUATNAV_BENCH_STD1(ceil)
QUATNAV_BENCH_STD1(round)
QUATNAV_BENCH_STD1(abs)
QUATNAV_BENCH_STD1(fabs)
#undef QUATNAV_BENCH_STD1
inline quatnav_bench::Counted atan2(quatnav_bench::Counted a, quatnav_bench::Counted b) { return quatnav_bench::impl::atan2(a, b); }
inline quatnav_bench::Counted fmod(quatnav_bench::Counted a, quatnav_bench::Counted b) { return quatnav_bench::impl::fmod(a, b); }
inline quatnav_bench::Counted pow(quatnav_bench::Counted a, quatnav_bench::Counted b) { return quatnav_bench::impl::pow(a, b); }
inline quatnav_bench::Counted hypot(quatnav_bench::Counted a, quatnav_bench::Counted b) { return quatnav_bench::impl::hypot(a, b); }
inline quatnav_bench::Counted copysign(quatnav_bench::Counted a, quatnav_bench::Counted b) { return quatnav_bench::impl::copysign(a, b); }
inline bool isnan(quatnav_bench::Counted a) { return quatnav_bench::impl::isnan(a); }
inline bool isinf(quatnav_bench::Counted a) { return quatnav_bench::impl::isinf(a); }
inline bool isfinite(quatnav_bench::Counted a) { return quatnav_bench::impl::isfinite(a); }
inline bool signbit(quatnav_bench::Counted a) { return quatnav_bench::impl::signbit(a); }

template <> class numeric_limits<quatnav_bench::Counted> {
  using C = quatnav_bench::Counted;
  using L = numeric_limits<double>;

 public:
  static constexpr bool is_specialized = true;
  static constexpr bool is_signed = true;
  static constexpr bool is_integer = false;
  static constexpr bool is_exact = false;
  static constexpr bool has_infinity = true;
  static constexpr bool has_quiet_NaN = true;
  static constexpr int digits = L::digits;
  static constexpr int digits10 = L::digits10;
  static constexpr int max_digits10 = L::max_digits10;
  static constexpr int radix = L::radix;
  static constexpr int min_exponent = L::min_exponent;
  static constexpr int max_exponent = L::max_exponent;
  static C min() { return C(L::min()); }
  static C max() { return C(L::max()); }
  static C lowest() { return C(L::lowest()); }
  static C epsilon() { return C(L::epsilon()); }
  static C infinity() { return C(L::infinity()); }
  static C quiet_NaN() { return C(L::quiet_NaN()); }
  static C denorm_min() { return C(L::denorm_min()); }
};
}  // namespace std

#include <Eigen/Core>

namespace Eigen {
template <> struct NumTraits<quatnav_bench::Counted> : GenericNumTraits<quatnav_bench::Counted> {
  using Real = quatnav_bench::Counted;
  using NonInteger = quatnav_bench::Counted;
  using Nested = quatnav_bench::Counted;
  using Literal = quatnav_bench::Counted;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 0,
    ReadCost = 1,
    AddCost = 1,
    MulCost = 1
  };
  static inline Real epsilon() { return Real(std::numeric_limits<double>::epsilon()); }
  static inline Real dummy_precision() { return Real(1e-12); }
  static inline Real highest() { return Real(std::numeric_limits<double>::max()); }
  static inline Real lowest() { return Real(std::numeric_limits<double>::lowest()); }
  static inline int digits10() { return std::numeric_limits<double>::digits10; }
  static inline Real infinity() { return Real(std::numeric_limits<double>::infinity()); }
  static inline Real quiet_NaN() { return Real(std::numeric_limits<double>::quiet_NaN()); }
};
}  // namespace Eigen
