// MargFilter_f64, MargFilterParams_f64, MargUpdateResult_f64 (attitude_binding.hpp; the _f32 classes
// are in bind_marg_f32.cpp).
#include "attitude_binding.hpp"

namespace quatnav_py {

void bind_marg_f64(py::module_& m) { bind_marg<double>(m); }

}  // namespace quatnav_py
