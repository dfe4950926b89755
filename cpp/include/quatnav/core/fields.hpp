// quatnav: parameter and state structs whose fields are declared once.
//
// A struct lists its fields in one table macro, one row per field:
//
//     #define QUATNAV_NAV13_PARAMS(X)
//       X(S, acc_noise, S(2.9420e-5), "m/s^2/sqrt(Hz)", "accelerometer white-noise density")
//       X(bool, earth_rotation, true, "-", "include the Earth rate, transport rate and Coriolis")
//
// (each line of the macro ending in a backslash).
//
//     template <class S> struct NavFilter13Params {
//       QUATNAV_FIELDS(NavFilter13Params, QUATNAV_NAV13_PARAMS)
//     };
//
// QUATNAV_FIELDS declares the members with their defaults and a static
// `for_each_member(visitor)` that calls `visitor(FieldInfo{name, unit, doc}, &Struct::member)` for
// every row in order; `for_each_field(obj, visitor)` visits an object's members the same way. Everything else is derived from that one row: the pybind11 properties, the
// dict round trip of get_state/set_state (unknown and missing keys refused), the table that the
// Python parameter tables are tested against (quatnav/filters/tables.py) and docs/PARAMETERS.md.
//
// A type or default with a comma outside parentheses (Mat<S, 6, 6>) needs an alias declared
// before the table. Longer explanations go in /* */ comments inside the table (a // comment would
// swallow the line continuation). for_each_member is a template: a program that never calls it
// (the firmware) carries none of the names or strings.
#pragma once

#include <type_traits>

namespace quatnav {

/// What the table says of one field besides its type and default.
struct FieldInfo {
  const char* name;  ///< the member's name, also its Python name and dict key
  const char* unit;  ///< SI unit ("-" for flags and counts, "1" for dimensionless numbers)
  const char* doc;   ///< one line
};

#define QUATNAV_FIELD_MEMBER_(type, name, def, unit, doc) type name = def;
#define QUATNAV_FIELD_POINTER_(type, name, def, unit, doc) v(::quatnav::FieldInfo{#name, unit, doc}, &Self_::name);

/// Inside struct SELF: the members of TABLE with their defaults, and the static
/// for_each_member(visitor), which calls visitor(FieldInfo, &SELF::member) for every row in order.
#define QUATNAV_FIELDS(SELF, TABLE)                      \
  TABLE(QUATNAV_FIELD_MEMBER_)                           \
  template <class Visitor_>                              \
  static void for_each_member(Visitor_&& v) {            \
    using Self_ = SELF;                                  \
    TABLE(QUATNAV_FIELD_POINTER_)                        \
  }

/// True for a struct declared with QUATNAV_FIELDS.
namespace detail {
struct FieldProbe {
  template <class M> void operator()(const FieldInfo&, M) const {}
};
}  // namespace detail
template <class T, class = void> struct has_fields : std::false_type {};
template <class T>
struct has_fields<T, std::void_t<decltype(T::for_each_member(detail::FieldProbe{}))>> : std::true_type {};
template <class T> inline constexpr bool has_fields_v = has_fields<T>::value;

/// Calls visitor(FieldInfo, obj.member) for every field of obj (const or not), in table order.
template <class T, class Visitor> void for_each_field(T& obj, Visitor&& visitor) {
  std::remove_const_t<T>::for_each_member([&](const FieldInfo& info, auto member) { visitor(info, obj.*member); });
}

}  // namespace quatnav
