// MargFilter_f32, MargFilterParams_f32, MargUpdateResult_f32 (attitude_binding.hpp; the _f64 classes
// are in bind_marg_f64.cpp).
#include "attitude_binding.hpp"

namespace quatnav_py {

void bind_marg_f32(py::module_& m) { bind_marg<float>(m); }

}  // namespace quatnav_py
