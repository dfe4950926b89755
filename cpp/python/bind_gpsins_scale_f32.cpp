// GpsInsFilterScale_f32: GpsInsFilter with the gyro and accelerometer scale-factor states
// (gpsins_binding.hpp); the _f64 class is in bind_gpsins_scale_f64.cpp.
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_scale_f32(py::module_& m) { bind_gpsins_filter<float, true>(m); }

}  // namespace quatnav_py
