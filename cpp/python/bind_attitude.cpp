// QuaternionEKFPaper (paper 000's 7-state filter), the parameters it shares with QuaternionEKF and
// those of the robustness parts, for float32 and float64 (attitude_binding.hpp; QuaternionEKF:
// bind_eskf.cpp, EulerEKF: bind_euler.cpp).
#include <quatnav/attitude/quaternion_ekf_paper.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {
namespace {

template <class S> void bind_qekf(py::module_& m) {
  using P = quatnav::QuaternionEKFParams<S>;
  bind_update_result<S, 3>(m);
  bind_update_result<S, 6>(m);
  bind_fields_struct<quatnav::RestParams<S>>(m, cls_name<S>("RestParams"), "Rest detection (attitude/parts/rest.hpp).");
  bind_fields_struct<quatnav::AccFilterParams<S>>(m, cls_name<S>("AccFilterParams"),
                                                  "The accelerometer part (attitude/parts/acc_filter.hpp).");
  bind_fields_struct<quatnav::MagDisturbanceParams<S>>(m, cls_name<S>("MagDisturbanceParams"),
                                                       "The magnetometer part (attitude/parts/mag_disturbance.hpp).");
  bind_fields_struct<quatnav::GyroClipParams<S>>(m, cls_name<S>("GyroClipParams"),
                                                 "Clipped gyro readings (attitude/parts/gyro_clip.hpp).");
  bind_fields_struct<P>(m, cls_name<S>("QuaternionEKFParams"),
                        "Parameters of QuaternionEKF and of its paper form QuaternionEKFPaper (quaternion_ekf_params.hpp).")
      .def_static("paper", &P::paper, "Parameters of the plain paper-000 filter (robustness off).");
  bind_quaternion_kf<quatnav::QuaternionEKFPaper<S>>(m, "QuaternionEKFPaper");
}

}  // namespace

void bind_attitude(py::module_& m) {
  bind_qekf<double>(m);
  bind_qekf<float>(m);
}

}  // namespace quatnav_py
