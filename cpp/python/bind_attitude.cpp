// QuaternionEKF (paper 000) for float32 and float64 (EulerEKF: bind_euler.cpp).
#include <quatnav/attitude/quaternion_ekf.hpp>

#include "attitude_binding.hpp"

namespace quatnav_py {
namespace {

template <class S> void bind_qekf(py::module_& m) {
  using F = quatnav::QuaternionEKF<S>;
  using P = typename F::Params;
  using St = typename F::State;
  bind_update_result<S, 3>(m);
  bind_update_result<S, 6>(m);
  py::class_<P>(m, cls_name<S>("QuaternionEKFParams").c_str())
      .def(py::init<>())
      .def_readwrite("gyro_noise", &P::gyro_noise)
      .def_readwrite("gyro_bias_noise", &P::gyro_bias_noise)
      .def_readwrite("acc_noise", &P::acc_noise)
      .def_readwrite("mag_noise", &P::mag_noise)
      .def_readwrite("init_att_sigma", &P::init_att_sigma)
      .def_readwrite("init_bias_sigma", &P::init_bias_sigma)
      .def_readwrite("mag_ref_samples", &P::mag_ref_samples)
      .def_readwrite("max_dt", &P::max_dt)
      .def_readwrite("gyro_range", &P::gyro_range)
      .def_readwrite("acc_range", &P::acc_range)
      .def_readwrite("cov_floor", &P::cov_floor)
      .def_readwrite("declination", &P::declination)

      .def_readwrite("mag_heading_only", &P::mag_heading_only)
      .def_readwrite("gravity", &P::gravity)
      .def_readwrite("acc_adapt", &P::acc_adapt)
      .def_readwrite("acc_reject", &P::acc_reject)
      .def_readwrite("acc_gate", &P::acc_gate)
      .def_readwrite("acc_recovery_time", &P::acc_recovery_time)
      .def_readwrite("acc_lp_tau", &P::acc_lp_tau)
      .def_readwrite("acc_lp_bias_sigma", &P::acc_lp_bias_sigma)
      .def_readwrite("mag_norm_tol", &P::mag_norm_tol)
      .def_readwrite("mag_dip_tol", &P::mag_dip_tol)
      .def_readwrite("mag_gate", &P::mag_gate)
      .def_readwrite("mag_settle_time", &P::mag_settle_time)
      .def_readwrite("mag_ref_tau", &P::mag_ref_tau)
      .def_readwrite("mag_recovery_time", &P::mag_recovery_time)
      .def_readwrite("rest_detection", &P::rest_detection)
      .def_readwrite("rest_gyr_th", &P::rest_gyr_th)
      .def_readwrite("rest_acc_th", &P::rest_acc_th)
      .def_readwrite("rest_time", &P::rest_time)
      .def_readwrite("rest_tau", &P::rest_tau)
      .def_readwrite("rest_rate_noise", &P::rest_rate_noise)
      .def_static("paper", &P::paper, "Parameters of the plain paper-000 filter (robustness off).");
  py::class_<F> cls(m, cls_name<S>("QuaternionEKF").c_str());
  cls.def(py::init<const P&>(), py::arg("params"));
  def_attitude_common<F>(cls);
  cls.def("reset", [](F& f, const quatnav::Quat<S>& q, const quatnav::Vec3<S>& b, const typename F::Mat7& P) {
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
        d["P"] = typename F::Mat7(s.P);
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
      .def_property_readonly("at_rest", &F::at_rest)
      .def_property_readonly("extra_flags", &F::extra_flags)
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
        s.P = d["P"].cast<typename F::Mat7>();
        s.mag = get_mag_ref<S>(d);
        s.initialized = d["initialized"].cast<bool>();
        return status_str(f.set_state(s));
      }, py::arg("state"));
}

}  // namespace

void bind_attitude(py::module_& m) {
  bind_qekf<double>(m);
  bind_qekf<float>(m);
}

}  // namespace quatnav_py
