// quatnav._core: the compiled part of the quatnav Python package.
#include "common.hpp"

namespace quatnav_py {
void bind_math(py::module_& m);
void bind_attitude(py::module_& m);
void bind_strapdown(py::module_& m);
void bind_marg(py::module_& m);
void bind_nav13(py::module_& m);
void bind_gpsins(py::module_& m);
}  // namespace quatnav_py

PYBIND11_MODULE(_core, m) {
  m.doc() = "quatnav compiled core (header-only C++ filters bound for float32 and float64)";
  m.attr("__version__") = QUATNAV_VERSION;
  quatnav_py::bind_math(m);
  quatnav_py::bind_attitude(m);
  quatnav_py::bind_strapdown(m);
  quatnav_py::bind_marg(m);
  quatnav_py::bind_nav13(m);
  quatnav_py::bind_gpsins(m);
}
