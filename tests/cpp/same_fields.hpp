// Bit-for-bit equality of two structs declared with QUATNAV_FIELDS (core/fields.hpp), field by
// field (nested field structs included), so that padding after a bool does not count.
#pragma once

#include <cstring>
#include <type_traits>

#include <quatnav/core/fields.hpp>

namespace quatnav_test {

template <class T> bool same_fields(const T& a, const T& b) {
  bool same = true;
  T::for_each_member([&](const quatnav::FieldInfo&, auto member) {
    using M = std::decay_t<decltype(a.*member)>;
    if constexpr (quatnav::has_fields_v<M>) {
      same = same && same_fields(a.*member, b.*member);
    } else {
      same = same && std::memcmp(static_cast<const void*>(&(a.*member)), static_cast<const void*>(&(b.*member)),
                                 sizeof(M)) == 0;
    }
  });
  return same;
}

}  // namespace quatnav_test
