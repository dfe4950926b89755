// The binding of NavFilter13 (paper 002) for one scalar type S, one class per time update:
// NavFilter13Ekf_f64, NavFilter13SecondOrder_f64, NavFilter13Ukf_f64 (and _f32). Instantiated
// once per S, in bind_nav13_f64.cpp (with the timing helper nav13_time_update_cost_ns) and
// bind_nav13_f32.cpp (one translation unit each, so that they compile in parallel).
#pragma once

#include <quatnav/nav/nav13_smoother.hpp>
#include <quatnav/nav/nav_filter13.hpp>

#include "common.hpp"
#include "fields_binding.hpp"
#include "smoother_binding.hpp"

namespace quatnav_py {

template <class S> void bind_params(py::module_& m) {
  bind_fields_struct<quatnav::NavFilter13Params<S>>(m, cls_name<S>("NavFilter13Params"),
                                                     "Parameters of NavFilter13 (nav_filter13.hpp).");
}

template <class F> py::dict nav13_run(F& f, const carray<typename F::Scalar>& wb, const carray<typename F::Scalar>& fb,
                                      const carray<double>& t, const carray<typename F::Scalar>& dt,
                                      const carray<double>& vel_t, const carray<typename F::Scalar>& vel,
                                      const carray<double>& yaw_t, const carray<typename F::Scalar>& yaw,
                                      typename F::Scalar gate_vel, typename F::Scalar gate_yaw, bool return_cov,
                                      bool smooth, std::size_t segment, bool apply_at_start) {
  using S = typename F::Scalar;
  const py::ssize_t n = fb.ndim() == 2 ? fb.shape(0) : -1;
  if (n < 0) throw py::value_error("f_ib_b: expected shape (N, 3)");
  require_shape<S>(fb, "f_ib_b", n, 3);
  require_shape<S>(wb, "omega_ib_b", n, 3);
  require_shape<double>(t, "t", n, -1);
  require_shape<S>(dt, "dt", n, -1);
  const py::ssize_t nv = vel_t.ndim() == 1 ? vel_t.shape(0) : -1;
  const py::ssize_t ny = yaw_t.ndim() == 1 ? yaw_t.shape(0) : -1;
  if (nv < 0) throw py::value_error("vel_t: expected shape (K,)");
  if (ny < 0) throw py::value_error("yaw_t: expected shape (K,)");
  require_shape<S>(vel, "vel", nv, 3);
  require_shape<S>(yaw, "yaw", ny, -1);
  auto x = empty<S>(n, 13), sigma = empty<S>(n, 13), att_sigma = empty<S>(n, 3);
  py::array_t<S> P;
  if (return_cov) P = py::array_t<S>({n, py::ssize_t(13), py::ssize_t(13)});
  py::array_t<std::uint32_t> fl({n});
  auto vi = empty<S>(nv, 3), vn = empty<S>(nv, -1), yi = empty<S>(ny, -1), yn = empty<S>(ny, -1);
  py::array_t<std::uint8_t> vs({nv}), ys({ny});
  py::array_t<S> xs, ss, as, Ps;
  py::dict info;
  {
    const S *pf = fb.data(), *pw = wb.data(), *pd = dt.data(), *pv = vel.data(), *py_ = yaw.data();
    const double *pt = t.data(), *pvt = vel_t.data(), *pyt = yaw_t.data();  // times in double for every S
    S *px = x.mutable_data(), *ps = sigma.mutable_data(), *pas = att_sigma.mutable_data();
    S* pP = return_cov ? P.mutable_data() : nullptr;
    std::uint32_t* pfl = fl.mutable_data();
    S *pvi = vi.mutable_data(), *pvn = vn.mutable_data(), *pyi = yi.mutable_data(), *pyn = yn.mutable_data();
    std::uint8_t *pvs = vs.mutable_data(), *pys = ys.mutable_data();
    auto forward = [&](auto&& obs) {
      quatnav::run_nav13_batch(f, pw, pf, pt, pd, std::size_t(n), pvt, pv, std::size_t(nv), pyt, py_, std::size_t(ny),
                               gate_vel, gate_yaw, px, ps, pP, pas, pfl, pvi, pvn, pvs, pyi, pyn, pys, apply_at_start,
                               obs);
    };
    if (smooth) {
      // The backward pass visits every sample (the filter is initialized before the run).
      xs = empty<S>(n, 13), ss = empty<S>(n, 13), as = empty<S>(n, 3);
      if (return_cov) Ps = py::array_t<S>({n, py::ssize_t(13), py::ssize_t(13)});
      quatnav::Nav13RtsModel<F> model(f, pw, pf, pd);
      quatnav::Nav13SmoothedOutput<S> out{xs.mutable_data(), ss.mutable_data(), return_cov ? Ps.mutable_data() : nullptr,
                                          as.mutable_data()};
      info = run_smoothed(model, std::size_t(n), std::size_t(nv + ny + 1), segment, forward, out);
    } else {
      py::gil_scoped_release release;
      forward(quatnav::NoBatchObserver{});
    }
  }
  py::dict d;
  if (smooth) {
    py::dict sd;
    sd["x"] = xs;
    sd["sigma"] = ss;
    sd["att_sigma"] = as;
    sd["P"] = return_cov ? py::object(Ps) : py::object(py::none());
    sd["info"] = info;
    d["smoothed"] = sd;
  }
  d["x"] = x;
  d["sigma"] = sigma;
  d["att_sigma"] = att_sigma;
  d["P"] = return_cov ? py::object(P) : py::object(py::none());
  d["flags"] = fl;
  d["vel_innovation"] = vi;
  d["vel_nis"] = vn;
  d["vel_status"] = vs;
  d["yaw_innovation"] = yi;
  d["yaw_nis"] = yn;
  d["yaw_status"] = ys;
  return d;
}

template <class S, quatnav::TimeUpdate TU> void bind_filter(py::module_& m, const char* base) {
  using F = quatnav::NavFilter13<S, TU>;
  using V3 = quatnav::Vec3<S>;
  using Q4 = quatnav::Quat<S>;
  using M13 = typename F::Mat13;
  py::class_<F> cls(m, cls_name<S>(base).c_str());
  cls.def(py::init<const typename F::Params&>(), py::arg("params"))
      .def_property_readonly("params", &F::params)
      .def_property_readonly("params_valid", &F::params_valid)
      .def_property_readonly("time_update", [](const F&) { return std::string(quatnav::to_string(TU)); })
      .def_property_readonly("initialized", &F::initialized)
      .def_property_readonly("x", [](const F& f) { return typename F::Vec13(f.x()); })
      .def_property_readonly("covariance", [](const F& f) { return M13(f.covariance()); })
      .def_property_readonly("error_covariance", [](const F& f) { return quatnav::Mat<S, 12, 12>(f.error_covariance()); })
      .def("reset", [](F& f, const V3& v, const Q4& q, const V3& ba, const V3& bg, const M13& P, double lat, double lon, double h) {
            return status_str(f.reset(v, q, ba, bg, P, lat, lon, h));
          }, py::arg("v_n"), py::arg("q_nb"), py::arg("acc_bias"), py::arg("gyro_bias"), py::arg("P"),
          py::arg("lat"), py::arg("lon"), py::arg("h"))
      .def("set_position", [](F& f, double lat, double lon, double h) { return status_str(f.set_position(lat, lon, h)); },
           py::arg("lat"), py::arg("lon"), py::arg("h"))
      .def("predict", [](F& f, const V3& wb, const V3& fb, S dt) { return status_str(f.predict(wb, fb, dt)); },
           py::arg("omega_ib_b"), py::arg("f_ib_b"), py::arg("dt"))
      .def("update_velocity", [](F& f, const V3& v, S gate) { return f.update_velocity(v, gate); },
           py::arg("v_n"), py::arg("gate") = S(0))
      .def("update_yaw", [](F& f, S yaw, S gate) { return f.update_yaw(yaw, gate); }, py::arg("yaw"),
           py::arg("gate") = S(0))
      .def("update_velocity_yaw", [](F& f, const V3& v, S yaw, S gate) { return f.update_velocity_yaw(v, yaw, gate); },
           py::arg("v_n"), py::arg("yaw"), py::arg("gate") = S(0))
      .def("run", &nav13_run<F>, py::arg("omega_ib_b"), py::arg("f_ib_b"), py::arg("t"), py::arg("dt"),
           py::arg("vel_t"), py::arg("vel"), py::arg("yaw_t"), py::arg("yaw"), py::arg("gate_vel") = S(0),
           py::arg("gate_yaw") = S(0), py::arg("return_covariance") = false, py::arg("smooth") = false,
           py::arg("segment") = std::size_t(256), py::arg("apply_at_start") = true,
           "Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the "
           "Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. "
           "apply_at_start: apply measurements at the state's time before the first step (a run "
           "from a reset state; false for a run that continues a previous one).");
  def_state_dict<F>(cls);
}

template <class S> void bind_all(py::module_& m) {
  bind_update_result<S, 1>(m);
  bind_update_result<S, 3>(m);
  bind_update_result<S, 4>(m);
  bind_params<S>(m);
  bind_filter<S, quatnav::TimeUpdate::Ekf>(m, "NavFilter13Ekf");
  bind_filter<S, quatnav::TimeUpdate::SecondOrder>(m, "NavFilter13SecondOrder");
  bind_filter<S, quatnav::TimeUpdate::Ukf>(m, "NavFilter13Ukf");
}

}  // namespace quatnav_py
