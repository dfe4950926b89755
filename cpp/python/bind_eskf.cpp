// QuaternionESKF (paper 000's filter in 6-state error-state form) for float32 and float64.
#include <quatnav/attitude/quaternion_eskf.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {
namespace {

template <class S> void bind_eskf(py::module_& m) {
  using F = quatnav::QuaternionESKF<S>;
  using P = typename F::Params;  // QuaternionEKFParams, bound in bind_attitude.cpp
  using St = typename F::State;
  py::class_<F> cls(m, cls_name<S>("QuaternionESKF").c_str());
  cls.def(py::init<const P&>(), py::arg("params"));
  def_attitude_common<F>(cls);
  cls.def("reset", [](F& f, const quatnav::Quat<S>& q, const quatnav::Vec3<S>& b, const typename F::Mat6& P) {
        return status_str(f.reset(q, b, P));
      }, py::arg("quat"), py::arg("bias"), py::arg("P"))
      .def("update_acc_mag", [](F& f, const quatnav::Vec3<S>& a, const quatnav::Vec3<S>& mg, S gate) {
        return f.update_acc_mag(a, mg, gate);
      }, py::arg("acc"), py::arg("mag"), py::arg("gate") = S(0))
      .def("get_state", [](const F& f) {
        const St& s = f.state();
        py::dict d;
        d["quat"] = quatnav::Quat<S>(s.q);
        d["bias"] = quatnav::Vec3<S>(s.bias);
        d["P"] = typename F::Mat6(s.P);
        put_mag_ref(d, s.mag);
        d["initialized"] = s.initialized;
        d["mag_norm_ref"] = s.mag_norm_ref;
        d["gyr_last"] = quatnav::Vec3<S>(s.gyr_last);
        d["dt_last"] = s.dt_last;
        d["gyr_lp"] = quatnav::Vec3<S>(s.gyr_lp);
        d["acc_lp"] = quatnav::Vec3<S>(s.acc_lp);
        d["lp_init"] = s.lp_init;
        d["rest_t"] = s.rest_t;
        d["acc_reject_t"] = s.acc_reject_t;
        d["mag_reject_t"] = s.mag_reject_t;
        d["mag_ok_t"] = s.mag_ok_t;
        d["q_i"] = quatnav::Quat<S>(s.q_i);
        d["acc_i_lp"] = quatnav::Vec3<S>(s.acc_i_lp);
        d["acc_lp_init"] = s.acc_lp_init;
        return d;
      })
      .def("set_state", [](F& f, const py::dict& d) {
        St s;
        s.mag_norm_ref = d["mag_norm_ref"].cast<S>();
        s.gyr_last = d["gyr_last"].cast<quatnav::Vec3<S>>();
        s.dt_last = d["dt_last"].cast<S>();
        s.gyr_lp = d["gyr_lp"].cast<quatnav::Vec3<S>>();
        s.acc_lp = d["acc_lp"].cast<quatnav::Vec3<S>>();
        s.lp_init = d["lp_init"].cast<bool>();
        s.rest_t = d["rest_t"].cast<S>();
        s.acc_reject_t = d["acc_reject_t"].cast<S>();
        s.mag_reject_t = d["mag_reject_t"].cast<S>();
        s.mag_ok_t = d["mag_ok_t"].cast<S>();
        s.q_i = d["q_i"].cast<quatnav::Quat<S>>();
        s.acc_i_lp = d["acc_i_lp"].cast<quatnav::Vec3<S>>();
        s.acc_lp_init = d["acc_lp_init"].cast<bool>();
        s.q = d["quat"].cast<quatnav::Quat<S>>();
        s.bias = d["bias"].cast<quatnav::Vec3<S>>();
        s.P = d["P"].cast<typename F::Mat6>();
        s.mag = get_mag_ref<S>(d);
        s.initialized = d["initialized"].cast<bool>();
        return status_str(f.set_state(s));
      }, py::arg("state"))
      .def_property_readonly("at_rest", &F::at_rest)
      .def_property_readonly("extra_flags", &F::extra_flags);
}

}  // namespace

void bind_eskf(py::module_& m) {
  bind_eskf<double>(m);
  bind_eskf<float>(m);
}

}  // namespace quatnav_py
