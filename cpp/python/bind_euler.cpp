// EulerEKF (paper 000's baseline) for float32 and float64 (attitude_binding.hpp).
#include <quatnav/attitude/euler_ekf.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {
namespace {

template <class S> void bind_euler_t(py::module_& m) {
  using F = quatnav::EulerEKF<S>;
  using P = typename F::Params;
  bind_fields_struct<P>(m, cls_name<S>("EulerEKFParams"), "Parameters of EulerEKF (euler_ekf.hpp).")
      .def_static("paper", &P::paper, "Parameters of the plain paper-000 baseline (robustness parts off).");
  bind_attitude_kf<F>(m, "EulerEKF", "euler")
      .def_property_readonly("euler", [](const F& f) { return quatnav::Vec3<S>(f.euler()); })
      .def_property_readonly("near_singularity", &F::near_singularity)
      .def_property_readonly("at_rest", &F::at_rest);
}

}  // namespace

void bind_euler(py::module_& m) {
  bind_euler_t<double>(m);
  bind_euler_t<float>(m);
}

}  // namespace quatnav_py
