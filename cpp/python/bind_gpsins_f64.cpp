// GpsInsFilter_f64, GpsInsParams_f64 (gpsins_binding.hpp; the _f32 classes are in
// bind_gpsins_f32.cpp), and gpsins_F, the float64 error-state dynamics matrix.
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_f64(py::module_& m) { bind_gpsins_scalar<double>(m); }

void bind_gpsins_F(py::module_& m) {
  m.def("gpsins_F", [](const quatnav::Quat<double>& q, const quatnav::Vec3<double>& v, double lat, double lon,
                       double h, const quatnav::Vec3<double>& f_b, bool earth_rotation, double accel_bias_tau,
                       double gyro_bias_tau) {
    quatnav::StrapdownState<double> s;
    s.q_nb = q;
    s.v_n = v;
    s.lat = lat;
    s.lon = lon;
    s.h = h;
    quatnav::GpsInsParams<double> p;
    p.earth_rotation = earth_rotation;
    p.accel_bias_tau = accel_bias_tau;
    p.gyro_bias_tau = gyro_bias_tau;
    return quatnav::Mat<double, 15, 15>(quatnav::detail::gpsins_F<double>(s, f_b, p));
  }, py::arg("q_nb"), py::arg("v_n"), py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("f_b"),
     py::arg("earth_rotation") = true, py::arg("accel_bias_tau") = 0.0, py::arg("gyro_bias_tau") = 0.0,
     "Error-state dynamics matrix F (15 x 15, float64) of GpsInsFilter at a nominal state.");
}

}  // namespace quatnav_py
