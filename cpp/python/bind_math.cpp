// Quaternion helpers, exposed so that tests can compare them with scipy and numpy.
#include <quatnav/core/quaternion.hpp>

#include "common.hpp"

namespace quatnav_py {

void bind_math(py::module_& m) {
  using namespace quatnav;
  using V3 = Vec3<double>;
  using Q = Quat<double>;
  auto mq = m.def_submodule("quat", "Quaternion helpers of the C++ core (float64), [w, x, y, z]");
  mq.def("mul", [](const Q& a, const Q& b) { return Q(quat::mul(a, b)); });
  mq.def("conj", [](const Q& a) { return Q(quat::conj(a)); });
  mq.def("rotate", [](const Q& q, const V3& v) { return V3(quat::rotate(q, v)); });
  mq.def("to_rotmat", [](const Q& q) { return Mat3<double>(quat::to_rotmat(q)); });
  mq.def("from_rotmat", [](const Mat3<double>& c) { return Q(quat::from_rotmat(c)); });
  mq.def("to_euler", [](const Q& q) { return V3(quat::to_euler(q)); });
  mq.def("from_euler", [](double r, double p, double y) { return Q(quat::from_euler(r, p, y)); });
  mq.def("from_rotvec", [](const V3& r) { return Q(quat::from_rotvec(r)); });
  mq.def("from_rotvec_jacobian", [](const V3& r) { return Mat43<double>(quat::from_rotvec_jacobian(r)); });
  mq.def("to_rotvec", [](const Q& q) { return V3(quat::to_rotvec(q)); });
  mq.def("enu_to_ned", [](const Q& q) { return Q(quat::enu_to_ned(q)); });
  mq.def("ned_to_enu", [](const Q& q) { return Q(quat::ned_to_enu(q)); });
  mq.def("skew", [](const V3& v) { return Mat3<double>(quat::skew(v)); });
  mq.def("omega", [](const V3& v) { return Mat4<double>(quat::omega(v)); });
  mq.def("xi", [](const Q& q) { return Mat43<double>(quat::xi(q)); });
  mq.def("wrap_pi", [](double a) { return quat::wrap_pi(a); });
}

}  // namespace quatnav_py
