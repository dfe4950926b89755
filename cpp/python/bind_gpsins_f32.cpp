// GpsInsFilter_f32, GpsInsParams_f32 (gpsins_binding.hpp; the _f64 classes are in
// bind_gpsins_f64.cpp).
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_f32(py::module_& m) { bind_gpsins_scalar<float>(m); }

}  // namespace quatnav_py
