// The binding of structs declared with QUATNAV_FIELDS (core/fields.hpp): one template for every
// parameter and state struct, so that a field declared in C++ is bound, listed and round-tripped
// through a dict without being named again here.
//
// A nested struct that has fields of its own (a part's parameters, StrapdownState inside
// GpsInsState) is flattened: its fields appear under their own names beside the outer ones, which
// must therefore be unique (checked when the module loads).
#pragma once

#include <quatnav/core/fields.hpp>

#include <array>
#include <set>
#include <string>
#include <type_traits>
#include <utility>

#include "common.hpp"

namespace quatnav_py {

/// Visit every leaf field of Root (nested field structs flattened) as visitor(info, access),
/// where access(Root&) returns a reference to the field.
template <class T, class Root, class Access, class Visitor>
void visit_flat(const Access& access, Visitor& visitor) {
  T::for_each_member([&](const quatnav::FieldInfo& info, auto member) {
    using M = std::remove_reference_t<decltype(std::declval<T&>().*member)>;
    auto inner = [access, member](Root& r) -> M& { return access(r).*member; };
    if constexpr (quatnav::has_fields_v<M>) {
      visit_flat<M, Root>(inner, visitor);
    } else {
      visitor(info, inner);
    }
  });
}

template <class Root, class Visitor> void visit_flat(Visitor&& visitor) {
  auto self = [](Root& r) -> Root& { return r; };
  visit_flat<Root, Root>(self, visitor);
}

/// A field's value as a Python object (Eigen matrices as new numpy arrays, enums as their integer).
template <class M> py::object field_to_py(const M& v) {
  if constexpr (std::is_enum_v<M>) {
    return py::int_(static_cast<std::underlying_type_t<M>>(v));
  } else {
    return py::cast(v);
  }
}

/// Convert `h` to the field's type; a TypeError names the field and says what it expects.
template <class M> M field_from_py(const py::handle& h, const char* name, const char* what) {
  try {
    if constexpr (std::is_same_v<M, bool>) {
      if (!py::isinstance<py::bool_>(h) && !py::isinstance(h, py::module_::import("numpy").attr("bool_")))
        throw py::cast_error();
    }
    if constexpr (std::is_enum_v<M>) {
      if (py::isinstance<py::bool_>(h)) throw py::cast_error();
      return static_cast<M>(h.cast<std::underlying_type_t<M>>());
    } else {
      return h.cast<M>();
    }
  } catch (const py::cast_error&) {
    std::string want;
    if constexpr (std::is_same_v<M, bool>) {
      want = "a bool";
    } else if constexpr (std::is_arithmetic_v<M> || std::is_enum_v<M>) {
      want = "a number";
    } else if constexpr (std::is_base_of_v<Eigen::MatrixBase<M>, M>) {
      want = M::ColsAtCompileTime == 1 ? "an array of shape (" + std::to_string(M::RowsAtCompileTime) + ",)"
                                       : "an array of shape (" + std::to_string(M::RowsAtCompileTime) + ", " +
                                             std::to_string(M::ColsAtCompileTime) + ")";
    } else {
      want = "a value of the field's type";
    }
    throw py::type_error(std::string(what) + ": " + name + ": expected " + want + ", got " +
                         std::string(py::str(py::type::handle_of(h).attr("__name__"))));
  }
}

/// The fields of T as a dict {name: value} (nested structs flattened).
template <class T> py::dict to_dict(const T& obj) {
  py::dict d;
  T& o = const_cast<T&>(obj);  // access() takes Root&; nothing is written
  visit_flat<T>([&](const quatnav::FieldInfo& info, const auto& access) { d[info.name] = field_to_py(access(o)); });
  return d;
}

/// Fill `out` from a dict. Unknown keys are refused (ValueError naming them); with `complete`,
/// every field must be present (a state), otherwise missing keys keep out's values (parameters).
template <class T> void from_dict(const py::dict& d, T& out, bool complete, const char* what) {
  std::set<std::string> known;
  visit_flat<T>([&](const quatnav::FieldInfo& info, const auto& access) {
    using M = std::remove_reference_t<decltype(access(out))>;
    known.insert(info.name);
    if (d.contains(info.name)) {
      access(out) = field_from_py<M>(d[info.name], info.name, what);
    } else if (complete) {
      throw py::value_error(std::string(what) + ": missing key '" + info.name + "'");
    }
  });
  for (const auto& kv : d) {
    const std::string k = py::str(kv.first);
    if (!known.count(k)) throw py::value_error(std::string(what) + ": unknown key '" + k + "'");
  }
}

/// The declaration table of T: a list of (name, default, unit, doc), defaults of T{}.
template <class T> py::list fields_table() {
  py::list rows;
  T proto{};
  visit_flat<T>([&](const quatnav::FieldInfo& info, const auto& access) {
    rows.append(py::make_tuple(info.name, field_to_py(access(proto)), info.unit, info.doc));
  });
  return rows;
}

/// Bind a parameter struct: a class with a property per field (with its unit and meaning as the
/// docstring), `fields()` (the declaration table), `to_dict()` / `from_dict(d)` (unknown keys
/// refused) and a repr listing the fields that differ from the defaults.
template <class T> py::class_<T> bind_fields_struct(py::module_& m, const std::string& name, const char* doc) {
  py::class_<T> cls(m, name.c_str(), doc);
  cls.def(py::init<>());
  std::set<std::string> seen;
  visit_flat<T>([&](const quatnav::FieldInfo& info, const auto& access) {
    using M = std::remove_reference_t<decltype(access(std::declval<T&>()))>;
    if (!seen.insert(info.name).second)
      throw std::runtime_error(name + ": the field name '" + info.name + "' appears twice");
    const std::string help = std::string(info.doc) + " [" + info.unit + "]";
    cls.def_property(
        info.name, [access](T& o) { return M(access(o)); },
        [access, n = std::string(info.name), name](T& o, const py::handle& v) {
          access(o) = field_from_py<M>(v, n.c_str(), name.c_str());
        },
        help.c_str());
  });
  cls.def_static("fields", &fields_table<T>, "The declaration table: a list of (name, default, unit, doc).")
      .def("to_dict", [](const T& o) { return to_dict(o); })
      .def_static(
          "from_dict",
          [name](const py::dict& d) {
            T out{};
            from_dict(d, out, false, name.c_str());
            return out;
          },
          py::arg("d"), "From a dict of some fields (the others keep their defaults); unknown keys refused.")
      .def("__repr__", [name](const T& o) {
        const py::dict cur = to_dict(o), def = to_dict(T{});
        std::string s = name + "(";
        bool first = true;
        for (const auto& kv : cur) {
          if (py::module_::import("numpy").attr("array_equal")(kv.second, def[kv.first]).template cast<bool>()) continue;
          s += std::string(first ? "" : ", ") + std::string(py::str(kv.first)) + "=" + std::string(py::repr(kv.second));
          first = false;
        }
        return s + ")";
      });
  return cls;
}

/// get_state / set_state of a filter F whose State is declared with QUATNAV_FIELDS: a dict of
/// every field; set_state refuses unknown and missing keys and returns the filter's Status name.
template <class F, class Cls> void def_state_dict(Cls& cls) {
  using St = typename F::State;
  cls.def("get_state", [](const F& f) { return to_dict(f.state()); },
          "The complete state as a dict of arrays and numbers (set_state restores it exactly).")
      .def(
          "set_state",
          [](F& f, const py::dict& d) {
            St s{};
            from_dict(d, s, true, "set_state");
            return status_str(f.set_state(s));
          },
          py::arg("state"), "Restore a state from get_state(); unknown and missing keys are refused.")
      .def_static("state_fields", &fields_table<St>, "The state's declaration table: (name, default, unit, doc).");
}

}  // namespace quatnav_py
