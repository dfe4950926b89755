// GpsInsFilter_f64, GpsInsParams_f64 (gpsins_binding.hpp; the _f32 classes are in
// bind_gpsins_f32.cpp).
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_f64(py::module_& m) { bind_gpsins_scalar<double>(m); }

}  // namespace quatnav_py
