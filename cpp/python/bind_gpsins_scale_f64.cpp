// GpsInsFilterScale_f64 and GpsInsFilterScale_f32: GpsInsFilter with the gyro and accelerometer
// scale-factor states (gpsins_binding.hpp; one unit for both, so the 16-state units stay as they
// were).
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_scale(py::module_& m) {
  bind_gpsins_filter<double, true>(m);
  bind_gpsins_filter<float, true>(m);
}

}  // namespace quatnav_py
