// QuaternionESKF (paper 000's filter in 6-state error-state form) for float32 and float64; its
// parameters, QuaternionEKFParams, are bound in bind_attitude.cpp (attitude_binding.hpp).
#include <quatnav/attitude/quaternion_eskf.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {

void bind_eskf(py::module_& m) {
  bind_quaternion_kf<quatnav::QuaternionESKF<double>>(m, "QuaternionESKF");
  bind_quaternion_kf<quatnav::QuaternionESKF<float>>(m, "QuaternionESKF");
}

}  // namespace quatnav_py
