// quatnav._core: the compiled part of the quatnav Python package.
#include "common.hpp"

namespace quatnav_py {
// One translation unit each (bind_*.cpp), so that the filters compile in parallel.
void bind_math(py::module_& m);
void bind_attitude(py::module_& m);  // QuaternionEKF
void bind_eskf(py::module_& m);  // QuaternionESKF
void bind_euler(py::module_& m);
void bind_strapdown(py::module_& m);
void bind_marg_f64(py::module_& m);
void bind_marg_f32(py::module_& m);
void bind_nav13_f64(py::module_& m);
void bind_nav13_f32(py::module_& m);
void bind_nav13_timing(py::module_& m);
void bind_gpsins_f64(py::module_& m);
void bind_gpsins_f32(py::module_& m);
void bind_gpsins_scale(py::module_& m);
}  // namespace quatnav_py

PYBIND11_MODULE(_core, m) {
  m.doc() = "quatnav compiled core (header-only C++ filters bound for float32 and float64)";
  m.attr("__version__") = QUATNAV_VERSION;
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
  quatnav_py::bind_gpsins_scale(m);
}
