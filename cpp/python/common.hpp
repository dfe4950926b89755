// Helpers shared by the binding translation units of quatnav._core.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>

#include <quatnav/core/types.hpp>

namespace quatnav_py {
namespace py = pybind11;

/// A C-contiguous array of S, converted (once, with the GIL held) from whatever was given.
template <class S> using carray = py::array_t<S, py::array::c_style | py::array::forcecast>;

template <class S> constexpr const char* dtype_suffix() { return sizeof(S) == 4 ? "_f32" : "_f64"; }

template <class S> std::string cls_name(const char* base) { return std::string(base) + dtype_suffix<S>(); }

/// Check that `a` has shape (n, cols) (cols < 0: shape (n,)); raise ValueError naming it.
template <class S>
void require_shape(const carray<S>& a, const char* name, py::ssize_t n, py::ssize_t cols) {
  const bool ok = cols < 0 ? (a.ndim() == 1 && a.shape(0) == n)
                           : (a.ndim() == 2 && a.shape(0) == n && a.shape(1) == cols);
  if (!ok) {
    std::string want = cols < 0 ? "(" + std::to_string(n) + ",)"
                                : "(" + std::to_string(n) + ", " + std::to_string(cols) + ")";
    throw py::value_error(std::string(name) + ": expected shape " + want);
  }
}

template <class S> py::array_t<S> empty(py::ssize_t n, py::ssize_t cols) {
  return cols < 0 ? py::array_t<S>({n}) : py::array_t<S>({n, cols});
}

/// Bind UpdateResult<S, M> once per (S, M).
template <class S, int M> void bind_update_result(py::module_& m) {
  using R = quatnav::UpdateResult<S, M>;
  const std::string name = "UpdateResult" + std::to_string(M) + dtype_suffix<S>();
  if (py::hasattr(m, name.c_str())) return;
  py::class_<R>(m, name.c_str(), "Outcome of one measurement update.")
      .def_property_readonly("status", [](const R& r) { return std::string(quatnav::to_string(r.status)); })
      .def_property_readonly("accepted", &R::accepted)
      .def_readonly("innovation", &R::innovation)
      .def_readonly("innovation_cov", &R::innovation_cov)
      .def_readonly("nis", &R::nis)
      .def("__repr__", [](const R& r) {
        return "<UpdateResult status=" + std::string(quatnav::to_string(r.status)) +
               " nis=" + std::to_string(double(r.nis)) + ">";
      });
}

inline std::string status_str(quatnav::Status s) { return quatnav::to_string(s); }

}  // namespace quatnav_py
