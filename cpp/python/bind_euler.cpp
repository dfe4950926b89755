// EulerEKF (paper 000) for float32 and float64 (QuaternionEKF: bind_attitude.cpp).
#include <quatnav/attitude/euler_ekf.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {
namespace {

template <class S> void bind_euler_t(py::module_& m) {
  using F = quatnav::EulerEKF<S>;
  using P = typename F::Params;
  using St = typename F::State;
  py::class_<P>(m, cls_name<S>("EulerEKFParams").c_str())
      .def(py::init<>())
      .def_readwrite("gyro_noise", &P::gyro_noise)
      .def_readwrite("gyro_bias_noise", &P::gyro_bias_noise)
      .def_readwrite("acc_noise", &P::acc_noise)
      .def_readwrite("mag_noise", &P::mag_noise)
      .def_readwrite("init_att_sigma", &P::init_att_sigma)
      .def_readwrite("init_bias_sigma", &P::init_bias_sigma)
      .def_readwrite("mag_ref_samples", &P::mag_ref_samples)
      .def_readwrite("max_dt", &P::max_dt)
      .def_readwrite("singular_cos", &P::singular_cos)
      .def_readwrite("gyro_range", &P::gyro_range)
      .def_readwrite("acc_range", &P::acc_range)
      .def_readwrite("cov_floor", &P::cov_floor);
  py::class_<F> cls(m, cls_name<S>("EulerEKF").c_str());
  cls.def(py::init<const P&>(), py::arg("params"));
  def_attitude_common<F>(cls);
  cls.def_property_readonly("euler", [](const F& f) { return quatnav::Vec3<S>(f.euler()); })
      .def_property_readonly("near_singularity", &F::near_singularity)
      .def("reset", [](F& f, const quatnav::Vec3<S>& e, const quatnav::Vec3<S>& b, const typename F::Mat6& P) {
        return status_str(f.reset(e, b, P));
      }, py::arg("euler"), py::arg("bias"), py::arg("P"))
      .def("get_state", [](const F& f) {
        const St& s = f.state();
        py::dict d;
        d["euler"] = quatnav::Vec3<S>(s.euler);
        d["bias"] = quatnav::Vec3<S>(s.bias);
        d["P"] = typename F::Mat6(s.P);
        put_mag_ref(d, s.mag);
        d["initialized"] = s.initialized;
        return d;
      })
      .def("set_state", [](F& f, const py::dict& d) {
        St s;
        s.euler = d["euler"].cast<quatnav::Vec3<S>>();
        s.bias = d["bias"].cast<quatnav::Vec3<S>>();
        s.P = d["P"].cast<typename F::Mat6>();
        s.mag = get_mag_ref<S>(d);
        s.initialized = d["initialized"].cast<bool>();
        return status_str(f.set_state(s));
      }, py::arg("state"));
}

}  // namespace

void bind_euler(py::module_& m) {
  bind_euler_t<double>(m);
  bind_euler_t<float>(m);
}

}  // namespace quatnav_py
