// quatnav._core: the compiled part of the quatnav Python package.
#include <limits>

#include "common.hpp"

namespace quatnav_py {
// One translation unit each (bind_*.cpp), so that the filters compile in parallel.
void bind_math(py::module_& m);
void bind_attitude(py::module_& m);  // QuaternionEKFPaper
void bind_eskf(py::module_& m);  // QuaternionEKF
void bind_euler(py::module_& m);
void bind_strapdown(py::module_& m);
void bind_marg_f64(py::module_& m);
void bind_marg_f32(py::module_& m);
void bind_nav13_f64(py::module_& m);
void bind_nav13_f32(py::module_& m);
void bind_nav13_timing(py::module_& m);
void bind_gpsins_f64(py::module_& m);
void bind_gpsins_f32(py::module_& m);
void bind_gpsins_scale_f64(py::module_& m);
void bind_gpsins_scale_f32(py::module_& m);

/// The first row of an (n, 3) array whose Euclidean norm is at most sqrt(tiny) (the squared norm
/// at most the smallest normal number), rows with a non-finite norm left out; -1 if none. One
/// pass without temporaries, for the zero-norm test of the batch runs' inputs (_validate.py).
template <class S> py::ssize_t first_zero_norm_row(const carray<S>& a) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("a: expected shape (N, 3)");
  const S* p = a.data();
  const py::ssize_t n = a.shape(0);
  const S tiny = std::numeric_limits<S>::min();
  py::gil_scoped_release release;
  for (py::ssize_t k = 0; k < n; ++k, p += 3)
    if (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= tiny) return k;  // NaN and inf compare false
  return -1;
}

}  // namespace quatnav_py

PYBIND11_MODULE(_core, m) {
  m.doc() = "quatnav compiled core (header-only C++ filters bound for float32 and float64)";
  m.attr("__version__") = QUATNAV_VERSION;
  // The compiler that built this module (a part of the arithmetic environment that
  // tools/regression.py records beside its reference outputs).
#if defined(__clang__)
  m.attr("compiler") = pybind11::str("clang " __clang_version__).attr("strip")();  // without its trailing space
#elif defined(__GNUC__)
  m.attr("compiler") = "GCC " __VERSION__;
#else
  m.attr("compiler") = "unknown";
#endif
  // The one flag table and the status names, from the C++ declarations (core/flags.hpp, types.hpp);
  // quatnav.Flag and quatnav.Status are tested equal to them.
  m.def("flag_table", []() -> pybind11::list {
    pybind11::list rows;
    for (const auto& f : quatnav::kFlagTable) rows.append(pybind11::make_tuple(f.name, f.bit, f.doc));
    return rows;
  }, "The per-sample flags of every filter: a list of (name, bit mask, meaning).");
  m.def("status_names", []() -> pybind11::list {
    pybind11::list names;
    for (int c = 0; c <= static_cast<int>(quatnav::Status::InvalidArgument); ++c)
      names.append(quatnav::to_string(static_cast<quatnav::Status>(c)));
    return names;
  }, "The names of quatnav::Status by code.");
  // float32 before float64: an array of another dtype converts to the second overload.
  m.def("first_zero_norm_row", &quatnav_py::first_zero_norm_row<float>, pybind11::arg("a").noconvert());
  m.def("first_zero_norm_row", &quatnav_py::first_zero_norm_row<double>, pybind11::arg("a"),
        "The first row of an (N, 3) array with norm <= sqrt(tiny) (non-finite rows left out), or -1.");
  // The order of registration is that of the signatures' type names: a class is bound before
  // the functions that take or return it.
  quatnav_py::bind_math(m);
  quatnav_py::bind_attitude(m);
  quatnav_py::bind_eskf(m);
  quatnav_py::bind_euler(m);
  quatnav_py::bind_strapdown(m);
  quatnav_py::bind_marg_f64(m);
  quatnav_py::bind_marg_f32(m);
  quatnav_py::bind_nav13_f64(m);
  quatnav_py::bind_nav13_f32(m);
  quatnav_py::bind_nav13_timing(m);
  quatnav_py::bind_gpsins_f64(m);
  quatnav_py::bind_gpsins_f32(m);
  quatnav_py::bind_gpsins_scale_f64(m);
  quatnav_py::bind_gpsins_scale_f32(m);
}
