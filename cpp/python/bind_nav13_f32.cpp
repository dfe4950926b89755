// NavFilter13Ekf_f32, NavFilter13SecondOrder_f32, NavFilter13Ukf_f32 and their parameter and
// result classes (nav13_binding.hpp; the _f64 ones are in bind_nav13_f64.cpp).
#include "nav13_binding.hpp"

namespace quatnav_py {

void bind_nav13_f32(py::module_& m) { bind_all<float>(m); }

}  // namespace quatnav_py
