// The binding of MargFilter (paper 001) for one scalar type S: steps, state as a dict, and the
// batch run with GPS velocity fixes (GIL released). Instantiated once per S, in bind_marg_f64.cpp
// and bind_marg_f32.cpp (one translation unit each, so that they compile in parallel).
#pragma once

#include <quatnav/attitude/marg_filter.hpp>

#include "common.hpp"

namespace quatnav_py {

template <class S> py::tuple marg_run(quatnav::MargFilter<S>& f, const carray<S>& t, const carray<S>& dt,
                                      const carray<S>& gyr, const carray<S>& acc, const py::object& mag_obj,
                                      const carray<S>& gps_t, const carray<S>& gps_vel) {
  const py::ssize_t n = gyr.ndim() == 2 ? gyr.shape(0) : -1;
  if (n < 0) throw py::value_error("gyr: expected shape (N, 3)");
  require_shape<S>(gyr, "gyr", n, 3);
  require_shape<S>(acc, "acc", n, 3);
  require_shape<S>(t, "t", n, -1);
  require_shape<S>(dt, "dt", n, -1);
  const py::ssize_t m = gps_t.ndim() == 1 ? gps_t.shape(0) : -1;
  if (m < 0) throw py::value_error("gps_t: expected shape (M,)");
  require_shape<S>(gps_vel, "gps_vel_n", m, 3);
  carray<S> mag;
  const bool has_mag = !mag_obj.is_none();
  if (has_mag) {
    mag = carray<S>::ensure(mag_obj);
    if (!mag) throw py::type_error("mag: expected a numeric array of shape (N, 3)");
    require_shape<S>(mag, "mag", n, 3);
  }
  auto quat = empty<S>(n, 4), bias = empty<S>(n, 3), gps_acc = empty<S>(n, 3), resid = empty<S>(n, -1);
  py::array_t<std::uint32_t> fl({n});
  {
    const S *pt = t.data(), *pd = dt.data(), *pg = gyr.data(), *pa = acc.data(),
            *pm = has_mag ? mag.data() : nullptr, *pgt = gps_t.data(), *pgv = gps_vel.data();
    S *pq = quat.mutable_data(), *pb = bias.mutable_data(), *pga = gps_acc.mutable_data(),
      *pr = resid.mutable_data();
    std::uint32_t* pf = fl.mutable_data();
    py::gil_scoped_release release;
    quatnav::run_marg_batch(f, pt, pd, pg, pa, pm, std::size_t(n), pgt, m > 0 ? pgv : nullptr, std::size_t(m), pq,
                            pb, pga, pr, pf);
  }
  return py::make_tuple(quat, bias, gps_acc, resid, fl);
}

template <class S> void bind_marg_t(py::module_& m) {
  using F = quatnav::MargFilter<S>;
  using P = typename F::Params;
  using St = typename F::State;
  using R = typename F::Result;
  using V3 = quatnav::Vec3<S>;
  using Q4 = quatnav::Quat<S>;
  py::class_<R>(m, cls_name<S>("MargUpdateResult").c_str(), "Outcome of one Gauss-Newton update.")
      .def_property_readonly("status", [](const R& r) { return status_str(r.status); })
      .def_property_readonly("accepted", &R::accepted)
      .def_readonly("iterations", &R::iterations)
      .def_readonly("converged", &R::converged)
      .def_readonly("gps_corrected", &R::gps_corrected)
      .def_readonly("residual", &R::residual)
      .def_readonly("residual_final", &R::residual_final)
      .def_readonly("correction", &R::correction)
      .def("__repr__", [](const R& r) {
        return "<MargUpdateResult status=" + status_str(r.status) + " iterations=" + std::to_string(r.iterations) +
               " residual=" + std::to_string(double(r.residual)) + ">";
      });
  py::class_<P>(m, cls_name<S>("MargFilterParams").c_str())
      .def(py::init<>())
      .def_readwrite("gain", &P::gain)
      .def_readwrite("bias_gain", &P::bias_gain)
      .def_readwrite("gn_max_iter", &P::gn_max_iter)
      .def_readwrite("gn_tol", &P::gn_tol)
      .def_readwrite("gravity", &P::gravity)
      .def_readwrite("lever_arm_b", &P::lever_arm_b)
      .def_readwrite("gps_correction", &P::gps_correction)
      .def_readwrite("gps_acc_tau", &P::gps_acc_tau)
      .def_readwrite("omega_dot_tau", &P::omega_dot_tau)
      .def_readwrite("gps_timeout", &P::gps_timeout)
      .def_readwrite("max_dt", &P::max_dt)
      .def_readwrite("declination", &P::declination)
      .def_readwrite("mag_ref_samples", &P::mag_ref_samples)
      .def_property_readonly("valid", [](const P& p) { return F::valid_params(p); });
  py::class_<F> cls(m, cls_name<S>("MargFilter").c_str());
  cls.def(py::init<const P&>(), py::arg("params"))
      .def_property_readonly("params", &F::params)
      .def_property_readonly("quat", [](const F& f) { return Q4(f.quat()); }, "q_nb [w, x, y, z]")
      .def_property_readonly("bias", [](const F& f) { return V3(f.bias()); }, "gyro bias [rad/s]")
      .def_property_readonly("initialized", &F::initialized)
      .def_property_readonly("gps_acc_available", &F::gps_acc_available)
      .def_property_readonly("gps_acc_n", [](const F& f) { return V3(f.gps_acc_n()); })
      .def("initialize", [](F& f, const V3& acc, const std::optional<V3>& mag) {
            return status_str(mag ? f.initialize(acc, *mag) : f.initialize(acc));
          }, py::arg("acc"), py::arg("mag") = py::none())
      .def("reset", [](F& f, const Q4& q, const V3& b) { return status_str(f.reset(q, b)); },
           py::arg("quat"), py::arg("bias"))
      .def("set_mag_dip", &F::set_mag_dip, py::arg("dip"))
      .def("predict", [](F& f, const V3& gyr, S dt) { return status_str(f.predict(gyr, dt)); },
           py::arg("gyr"), py::arg("dt"))
      .def("update_gps_velocity", [](F& f, const V3& v, S t) { return status_str(f.update_gps_velocity(v, t)); },
           py::arg("v_n"), py::arg("t"))
      .def("update_acc", &F::update_acc, py::arg("acc"))
      .def("update_acc_mag", &F::update_acc_mag, py::arg("acc"), py::arg("mag"))
      .def("get_state", [](const F& f) {
        const St& s = f.state();
        py::dict d;
        d["quat"] = Q4(s.q);
        d["bias"] = V3(s.bias);
        d["mag_ref"] = V3(s.mag.ref);
        d["mag_sin_dip_sum"] = s.mag.sin_dip_sum;
        d["mag_ref_count"] = s.mag.count;
        d["mag_ref_fixed"] = s.mag.fixed;
        d["omega_b"] = V3(s.omega_b);
        d["omega_dot_b"] = V3(s.omega_dot_b);
        d["gps_vel_n"] = V3(s.gps_vel_n);
        d["gps_acc_n"] = V3(s.gps_acc_n);
        d["gps_t"] = s.gps_t;
        d["time_since_gps"] = s.time_since_gps;
        d["time_since_update"] = s.time_since_update;
        d["gps_fixes"] = s.gps_fixes;
        d["omega_set"] = s.omega_set;
        d["initialized"] = s.initialized;
        return d;
      })
      .def("set_state", [](F& f, const py::dict& d) {
        St s;
        s.q = d["quat"].cast<Q4>();
        s.bias = d["bias"].cast<V3>();
        s.mag.ref = d["mag_ref"].cast<V3>();
        s.mag.sin_dip_sum = d["mag_sin_dip_sum"].cast<S>();
        s.mag.count = d["mag_ref_count"].cast<std::uint32_t>();
        s.mag.fixed = d["mag_ref_fixed"].cast<bool>();
        s.omega_b = d["omega_b"].cast<V3>();
        s.omega_dot_b = d["omega_dot_b"].cast<V3>();
        s.gps_vel_n = d["gps_vel_n"].cast<V3>();
        s.gps_acc_n = d["gps_acc_n"].cast<V3>();
        s.gps_t = d["gps_t"].cast<S>();
        s.time_since_gps = d["time_since_gps"].cast<S>();
        s.time_since_update = d["time_since_update"].cast<S>();
        s.gps_fixes = d["gps_fixes"].cast<int>();
        s.omega_set = d["omega_set"].cast<bool>();
        s.initialized = d["initialized"].cast<bool>();
        return status_str(f.set_state(s));
      }, py::arg("state"))
      .def("run", &marg_run<S>, py::arg("t"), py::arg("dt"), py::arg("gyr"), py::arg("acc"), py::arg("mag"),
           py::arg("gps_t"), py::arg("gps_vel_n"),
           "Batch run (GIL released). Returns (quat, bias, gps_acc_n, residual, flags).");
}

}  // namespace quatnav_py
