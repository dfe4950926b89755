// The binding of GpsInsFilter (paper 004) for one scalar type S, with its batch run (GIL
// released). Instantiated once per S, in bind_gpsins_f64.cpp
// and bind_gpsins_f32.cpp (one translation unit each, so that they compile in parallel).
#pragma once

#include <quatnav/nav/gps_ins.hpp>

#include "common.hpp"
#include "fields_binding.hpp"

namespace quatnav_py {

/// The counters as {aid kind: {"accepted", "rejected", "skipped", "resets"}}.
inline py::dict counters_dict(const quatnav::GpsInsCounters& c) {
  py::dict d;
  for (int k = 0; k < quatnav::kGpsInsAidKinds; ++k) {
    py::dict e;
    e["accepted"] = c.accepted[k];
    e["rejected"] = c.rejected[k];
    e["skipped"] = c.skipped[k];
    e["resets"] = c.resets[k];
    d[quatnav::kGpsInsAidNames[k]] = e;
  }
  return d;
}

template <class S> void bind_gpsins_scalar(py::module_& m) {
  using namespace quatnav;
  using F = GpsInsFilter<S>;
  using P = GpsInsParams<S>;
  using V3 = Vec3<S>;
  bind_update_result<S, 1>(m);
  bind_update_result<S, 3>(m);
  bind_fields_struct<P>(m, cls_name<S>("GpsInsParams"), "Parameters of GpsInsFilter (nav/gps_ins/params.hpp).");

  py::class_<F> cls(m, cls_name<S>("GpsInsFilter").c_str());
  cls.def(py::init<const P&>(), py::arg("params"))
      .def_property_readonly("params", &F::params)
      .def("set_params", &F::set_params, py::arg("params"))
      .def_property_readonly("phase", [](const F& f) { return int(f.phase()); })
      .def_property_readonly("navigating", &F::navigating)
      .def_property_readonly("q_nb", [](const F& f) { return Quat<S>(f.q_nb()); })
      .def_property_readonly("v_n", [](const F& f) { return V3(f.v_n()); })
      .def_property_readonly("llh", &F::llh)
      .def_property_readonly("acc_bias", [](const F& f) { return V3(f.acc_bias()); })
      .def_property_readonly("gyro_bias", [](const F& f) { return V3(f.gyro_bias()); })
      .def_property_readonly("covariance", [](const F& f) { return typename F::Mat15(f.covariance()); })
      .def_property_readonly("time", &F::time)
      .def_property_readonly("counters", [](const F& f) { return counters_dict(f.state().counters); })
      .def("clear", &F::clear, "Back to the start of alignment (parameters kept).")
      .def("reset",
           [](F& f, const Quat<S>& q, const V3& v, double lat, double lon, double h, const V3& ba, const V3& bg,
              const typename F::Mat15& Pm) { return status_str(f.reset(q, v, lat, lon, h, ba, bg, Pm)); },
           py::arg("q_nb"), py::arg("v_n"), py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("acc_bias"),
           py::arg("gyro_bias"), py::arg("P"))
      .def("predict", [](F& f, const V3& w, const V3& a, S dt) { return status_str(f.predict(w, a, dt)); },
           py::arg("omega_ib_b"), py::arg("f_ib_b"), py::arg("dt"))
      .def("update_gps_position",
           [](F& f, double lat, double lon, double h, const V3& sig) { return f.update_gps_position(lat, lon, h, sig); },
           py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("sigma"))
      .def("update_gps_velocity", [](F& f, const V3& v, const V3& sig) { return f.update_gps_velocity(v, sig); },
           py::arg("v_n"), py::arg("sigma"))
      .def("update_gps",
           [](F& f, double lat, double lon, double h, const V3& v, const V3& ps, const V3& vs) {
             const GpsResult<S> r = f.update_gps(lat, lon, h, v, ps, vs);
             return py::make_tuple(r.pos, r.vel);
           },
           py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("v_n"), py::arg("pos_sigma"), py::arg("vel_sigma"))
      .def("update_baro",
           [](F& f, double h) {
             const BaroResult<S> r = f.update_baro(h);
             return py::make_tuple(r.height, r.vd);
           },
           py::arg("h"))
      .def("update_compass", [](F& f, S yaw) { return f.update_compass(yaw); }, py::arg("heading"))
      .def(
          "run",
          [](F& f, const carray<double>& t, const carray<S>& gyro, const carray<S>& accel, const carray<double>& gps_t,
             const carray<double>& gps_llh, const carray<S>& gps_vel, const carray<S>& gps_pos_sigma,
             const carray<S>& gps_vel_sigma, const carray<double>& baro_t, const carray<double>& baro_h,
             const carray<double>& compass_t, const carray<S>& compass_yaw) {
            const py::ssize_t n = t.ndim() == 1 ? t.shape(0) : -1;
            if (n < 0) throw py::value_error("t: expected shape (N,)");
            require_shape<S>(gyro, "gyro", n, 3);
            require_shape<S>(accel, "accel", n, 3);
            const py::ssize_t ng = gps_t.shape(0), nb = baro_t.shape(0), nc = compass_t.shape(0);
            if (gps_llh.ndim() != 2 || gps_llh.shape(0) != ng || gps_llh.shape(1) != 3)
              throw py::value_error("gps_llh: expected shape (len(gps_t), 3)");
            require_shape<S>(gps_vel, "gps_vel", ng, 3);
            require_shape<S>(gps_pos_sigma, "gps_pos_sigma", ng, 3);
            require_shape<S>(gps_vel_sigma, "gps_vel_sigma", ng, 3);
            if (baro_h.ndim() != 1 || baro_h.shape(0) != nb) throw py::value_error("baro_h: expected shape (len(baro_t),)");
            require_shape<S>(compass_yaw, "compass_yaw", nc, -1);
            py::array_t<double> llh({n, py::ssize_t(3)});
            auto v = empty<S>(n, 3), q = empty<S>(n, 4), ba = empty<S>(n, 3), bg = empty<S>(n, 3),
                 sig = empty<S>(n, 15);
            py::array_t<std::uint32_t> fl({n});
            auto gi = empty<S>(ng, 6), gn = empty<S>(ng, 2), bi = empty<S>(nb, 2), bn = empty<S>(nb, 2),
                 ci = empty<S>(nc, -1), cn = empty<S>(nc, -1);
            py::array_t<std::uint8_t> gs({ng, py::ssize_t(2)}), bs({nb, py::ssize_t(2)}), cs({nc});
            GpsInsBatchIo<S> io;
            io.t = t.data();
            io.gyro = gyro.data();
            io.accel = accel.data();
            io.n = std::size_t(n);
            io.gps_t = gps_t.data();
            io.gps_llh = gps_llh.data();
            io.gps_vel = gps_vel.data();
            io.gps_pos_sigma = gps_pos_sigma.data();
            io.gps_vel_sigma = gps_vel_sigma.data();
            io.ng = std::size_t(ng);
            io.baro_t = baro_t.data();
            io.baro_h = baro_h.data();
            io.nb = std::size_t(nb);
            io.compass_t = compass_t.data();
            io.compass_yaw = compass_yaw.data();
            io.nc = std::size_t(nc);
            io.llh = llh.mutable_data();
            io.v_n = v.mutable_data();
            io.q_nb = q.mutable_data();
            io.acc_bias = ba.mutable_data();
            io.gyro_bias = bg.mutable_data();
            io.sigma = sig.mutable_data();
            io.flags = fl.mutable_data();
            io.gps_innov = gi.mutable_data();
            io.gps_nis = gn.mutable_data();
            io.gps_status = gs.mutable_data();
            io.baro_innov = bi.mutable_data();
            io.baro_nis = bn.mutable_data();
            io.baro_status = bs.mutable_data();
            io.compass_innov = ci.mutable_data();
            io.compass_nis = cn.mutable_data();
            io.compass_status = cs.mutable_data();
            {
              py::gil_scoped_release release;
              gpsins_batch(f, io);
            }
            py::dict d;
            d["llh"] = llh;
            d["v_n"] = v;
            d["q_nb"] = q;
            d["acc_bias"] = ba;
            d["gyro_bias"] = bg;
            d["sigma"] = sig;
            d["flags"] = fl;
            d["gps_innov"] = gi;
            d["gps_nis"] = gn;
            d["gps_status"] = gs;
            d["baro_innov"] = bi;
            d["baro_nis"] = bn;
            d["baro_status"] = bs;
            d["compass_innov"] = ci;
            d["compass_nis"] = cn;
            d["compass_status"] = cs;
            return d;
          },
          py::arg("t"), py::arg("gyro"), py::arg("accel"), py::arg("gps_t"), py::arg("gps_llh"), py::arg("gps_vel"),
          py::arg("gps_pos_sigma"), py::arg("gps_vel_sigma"), py::arg("baro_t"), py::arg("baro_h"),
          py::arg("compass_t"), py::arg("compass_yaw"),
          "Batch run in C++ with the GIL released (see quatnav::gpsins_batch). Returns a dict of arrays.");
  def_state_dict<F>(cls);
}

}  // namespace quatnav_py
