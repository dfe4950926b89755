// MargFilter_f64, MargFilterParams_f64, MargUpdateResult_f64 (marg_binding.hpp; the _f32 classes are
// in bind_marg_f32.cpp).
#include "marg_binding.hpp"

namespace quatnav_py {

void bind_marg_f64(py::module_& m) { bind_marg_t<double>(m); }

}  // namespace quatnav_py
