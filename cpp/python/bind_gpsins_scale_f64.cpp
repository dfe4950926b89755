// GpsInsFilterScale_f64: GpsInsFilter with the gyro and accelerometer scale-factor states
// (gpsins_binding.hpp); the _f32 class is in bind_gpsins_scale_f32.cpp, so that the two compile
// side by side (one unit for both was the longest of the extension's build).
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_scale_f64(py::module_& m) { bind_gpsins_filter<double, true>(m); }

}  // namespace quatnav_py
