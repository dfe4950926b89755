// QuaternionEKF (paper 000's filter in 6-state error-state form) for float32 and float64; its
// parameters, QuaternionEKFParams, are bound in bind_attitude.cpp (attitude_binding.hpp).
#include <quatnav/attitude/quaternion_ekf.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {

void bind_eskf(py::module_& m) {
  bind_quaternion_kf<quatnav::QuaternionEKF<double>>(m, "QuaternionEKF");
  bind_quaternion_kf<quatnav::QuaternionEKF<float>>(m, "QuaternionEKF");
}

}  // namespace quatnav_py
