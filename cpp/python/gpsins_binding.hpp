// The binding of GpsInsFilter (paper 004) for one scalar type S, with its batch run (GIL
// released). Instantiated once per S, in bind_gpsins_f64.cpp and bind_gpsins_f32.cpp (one
// translation unit each, so that they compile in parallel). Parameters and state come from their
// declarations (fields_binding.hpp).
#pragma once

#include <algorithm>

#include <quatnav/nav/gps_ins.hpp>
#include <quatnav/nav/gps_ins/smoother.hpp>

#include "common.hpp"
#include "fields_binding.hpp"
#include "smoother_binding.hpp"

namespace quatnav_py {

/// A solution kind from its code (quatnav::GnssSolution); an unknown code is Unknown.
inline quatnav::GnssSolution gnss_solution(int kind) {
  return kind >= 0 && kind < quatnav::kGnssSolutions ? quatnav::GnssSolution(kind) : quatnav::GnssSolution::Unknown;
}

/// The counters as {aid kind: {"accepted", "rejected", "skipped", "inflated", "resets"}}.
inline py::dict counters_dict(const quatnav::GpsInsCounters& c) {
  py::dict d;
  for (int k = 0; k < quatnav::kGpsInsAidKinds; ++k) {
    py::dict e;
    e["accepted"] = c.accepted[k];
    e["rejected"] = c.rejected[k];
    e["skipped"] = c.skipped[k];
    e["inflated"] = c.inflated[k];
    e["resets"] = c.resets[k];
    e["weighted"] = c.weighted[k];
    d[quatnav::kGpsInsAidNames[k]] = e;
  }
  return d;
}

/// GpsInsUpdate<S, M>: an UpdateResult with the filter's decision and inflation.
template <class S, int M> void bind_gpsins_update(py::module_& m) {
  using R = quatnav::GpsInsUpdate<S, M>;
  const std::string name = "GpsInsUpdate" + std::to_string(M) + dtype_suffix<S>();
  py::class_<R>(m, name.c_str(), "Outcome of one GpsInsFilter update: status, innovation (INS minus aid), "
                                 "its covariance, NIS, decision (code, see decision_names()), inflation.")
      .def_property_readonly("status", [](const R& r) { return std::string(quatnav::to_string(r.status)); })
      .def_property_readonly("accepted", &R::accepted)
      .def_readonly("innovation", &R::innovation)
      .def_readonly("innovation_cov", &R::innovation_cov)
      .def_readonly("nis", &R::nis)
      .def_property_readonly("decision", [](const R& r) { return int(r.decision); })
      .def_readonly("inflation", &R::inflation)
      .def("__repr__", [](const R& r) {
        return "<GpsInsUpdate status=" + std::string(quatnav::to_string(r.status)) +
               " decision=" + std::to_string(int(r.decision)) + " nis=" + std::to_string(double(r.nis)) + ">";
      });
}

namespace {  // (internal linkage: the members are pybind11 objects, hidden)
/// An aid's report arrays (rows, cols updates of m rows each) and the pointers the batch writes.
template <class S> struct AidOutArrays {
  py::array_t<S> innovation, nis, inflation;
  py::array_t<std::uint8_t> status, decision;
  AidOutArrays(py::ssize_t rows, py::ssize_t cols, py::ssize_t m)
      : innovation({rows, cols * m}), nis({rows, cols}), inflation({rows, cols}), status({rows, cols}),
        decision({rows, cols}) {}
  quatnav::GpsInsAidOut<S> out() {
    quatnav::GpsInsAidOut<S> o;
    o.innovation = innovation.mutable_data();
    o.nis = nis.mutable_data();
    o.inflation = inflation.mutable_data();
    o.status = status.mutable_data();
    o.decision = decision.mutable_data();
    return o;
  }
  py::dict dict() const {
    py::dict d;
    d["innovation"] = innovation;
    d["nis"] = nis;
    d["status"] = status;
    d["decision"] = decision;
    d["inflation"] = inflation;
    return d;
  }
};
}  // namespace

/// The filter class GpsInsFilter_<dtype> (16 error states) or, with SF, GpsInsFilterScale_<dtype>
/// (22: the gyro and accelerometer scale factors); the update and parameter types are bound once
/// per dtype by bind_gpsins_scalar.
template <class S, bool SF> void bind_gpsins_filter(py::module_& m) {
  using namespace quatnav;
  using F = GpsInsFilter<S, SF>;
  using P = GpsInsParams<S>;
  using V3 = Vec3<S>;
  constexpr int N = F::kStates;

  py::class_<F> cls(m, cls_name<S>(SF ? "GpsInsFilterScale" : "GpsInsFilter").c_str());
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
      .def_property_readonly("acc_scale", [](const F& f) { return V3(f.acc_scale()); })
      .def_property_readonly("gyro_scale", [](const F& f) { return V3(f.gyro_scale()); })
      .def_property_readonly("n_states", [](const F&) { return N; })
      .def_property_readonly("baro_offset", &F::baro_offset)
      .def_property_readonly("at_rest", &F::at_rest)
      .def_property_readonly("align_method", [](const F& f) { return std::string(to_string(f.align_method())); })
      .def_property_readonly("heading_source", [](const F& f) { return std::string(to_string(f.heading_source())); })
      .def_property_readonly("q_scale", &F::q_scale)
      .def_property_readonly("covariance", [](const F& f) { return typename F::Mat16(f.covariance()); })
      .def_property_readonly("time", &F::time)
      .def_property_readonly("counters", [](const F& f) { return counters_dict(f.state().counters); })
      .def("clear", &F::clear, "Back to the start of alignment (parameters kept).")
      .def("reset",
           [](F& f, const Quat<S>& q, const V3& v, double lat, double lon, double h, const V3& ba, const V3& bg,
              const typename F::Mat16& Pm) { return status_str(f.reset(q, v, lat, lon, h, ba, bg, Pm)); },
           py::arg("q_nb"), py::arg("v_n"), py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("acc_bias"),
           py::arg("gyro_bias"), py::arg("P"))
      .def("set_initial",
           [](F& f, const Quat<S>& q, const V3& v, bool v_valid, const V3& ba, const V3& bg) {
             return status_str(f.set_initial(q, v, v_valid, ba, bg));
           },
           py::arg("q_nb"), py::arg("v_n"), py::arg("v_valid"), py::arg("acc_bias"), py::arg("gyro_bias"))
      .def("predict", [](F& f, const V3& w, const V3& a, S dt) { return status_str(f.predict(w, a, dt)); },
           py::arg("omega_ib_b"), py::arg("f_ib_b"), py::arg("dt"))
      .def("update_constraints",
           [](F& f) {
             const ConstraintResult<S> r = f.update_constraints();
             return py::make_tuple(r.zupt, r.zaru, r.nhc);
           })
      .def("update_mag", [](F& f, const V3& m_imu) { return f.update_mag(m_imu); }, py::arg("m"))
      .def("update_odometer", [](F& f, S speed) { return f.update_odometer(speed); }, py::arg("speed"))
      .def("update_gps_position",
           [](F& f, double lat, double lon, double h, const V3& sig, S age, int kind) {
             return f.update_gps_position(lat, lon, h, sig, age, gnss_solution(kind));
           },
           py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("sigma"), py::arg("age") = S(0), py::arg("solution") = 0)
      .def("update_gps_velocity", [](F& f, const V3& v, const V3& sig, S age) { return f.update_gps_velocity(v, sig, age); },
           py::arg("v_n"), py::arg("sigma"), py::arg("age") = S(0))
      .def("update_gps",
           [](F& f, double lat, double lon, double h, const V3& v, const V3& ps, const V3& vs, S age, int kind) {
             const GpsResult<S> r = f.update_gps(lat, lon, h, v, ps, vs, age, gnss_solution(kind));
             return py::make_tuple(r.pos, r.vel);
           },
           py::arg("lat"), py::arg("lon"), py::arg("h"), py::arg("v_n"), py::arg("pos_sigma"), py::arg("vel_sigma"),
           py::arg("age") = S(0), py::arg("solution") = 0)
      .def("update_baro",
           [](F& f, double h) {
             const BaroResult<S> r = f.update_baro(h);
             return py::make_tuple(r.height, r.vd);
           },
           py::arg("h"))
      .def("update_compass", [](F& f, S yaw) { return f.update_compass(yaw); }, py::arg("heading"))
      .def(
          "run",
          [](F& f, const carray<double>& t, const carray<S>& gyro, const carray<S>& accel, const py::object& mag_obj,
             bool increments, const carray<double>& gps_t, const carray<double>& gps_llh, const carray<S>& gps_vel,
             const carray<S>& gps_pos_sigma, const carray<S>& gps_vel_sigma, const carray<double>& baro_t,
             const carray<double>& baro_h, const carray<double>& compass_t, const carray<S>& compass_yaw,
             const carray<double>& odo_t, const carray<S>& odo_speed, bool smooth, std::size_t segment,
             const py::object& solution_obj) {
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
            py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> solution;
            if (!solution_obj.is_none()) {
              solution = solution_obj.cast<py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>>();
              if (solution.ndim() != 1 || solution.shape(0) != ng)
                throw py::value_error("gps_solution: expected shape (len(gps_t),)");
            }
            if (baro_h.ndim() != 1 || baro_h.shape(0) != nb) throw py::value_error("baro_h: expected shape (len(baro_t),)");
            require_shape<S>(compass_yaw, "compass_yaw", nc, -1);
            const py::ssize_t no = odo_t.shape(0);
            require_shape<S>(odo_speed, "odo_speed", no, -1);
            carray<S> mag;
            if (!mag_obj.is_none()) {
              mag = mag_obj.cast<carray<S>>();
              require_shape<S>(mag, "mag", n, 3);
            }
            py::array_t<double> llh({n, py::ssize_t(3)}), bo({n});
            auto v = empty<S>(n, 3), q = empty<S>(n, 4), ba = empty<S>(n, 3), bg = empty<S>(n, 3),
                 sig = empty<S>(n, N), qs = empty<S>(n, -1);
            py::array_t<std::uint32_t> fl({n});
            AidOutArrays<S> go(ng, 2, 3), bo_(nb, 2, 1), co(nc, 1, 1), oo(no, 1, 1), mo(mag_obj.is_none() ? 0 : n, 1, 1),
                zu(n, 1, 3), za(n, 1, 3), nh(n, 1, 2);
            GpsInsBatchIo<S> io;
            io.t = t.data();
            io.gyro = gyro.data();
            io.accel = accel.data();
            io.mag = mag_obj.is_none() ? nullptr : mag.data();
            io.n = std::size_t(n);
            io.increments = increments;
            io.gps_t = gps_t.data();
            io.gps_llh = gps_llh.data();
            io.gps_vel = gps_vel.data();
            io.gps_pos_sigma = gps_pos_sigma.data();
            io.gps_vel_sigma = gps_vel_sigma.data();
            io.gps_solution = solution_obj.is_none() ? nullptr : solution.data();
            io.ng = std::size_t(ng);
            io.baro_t = baro_t.data();
            io.baro_h = baro_h.data();
            io.nb = std::size_t(nb);
            io.compass_t = compass_t.data();
            io.compass_yaw = compass_yaw.data();
            io.nc = std::size_t(nc);
            io.odo_t = odo_t.data();
            io.odo_speed = odo_speed.data();
            io.no = std::size_t(no);
            io.llh = llh.mutable_data();
            io.v_n = v.mutable_data();
            io.q_nb = q.mutable_data();
            io.acc_bias = ba.mutable_data();
            io.gyro_bias = bg.mutable_data();
            auto sa = empty<S>(SF ? n : 0, 3), sg = empty<S>(SF ? n : 0, 3);
            if (SF) {
              io.acc_scale = sa.mutable_data();
              io.gyro_scale = sg.mutable_data();
            }
            io.sigma = sig.mutable_data();
            io.baro_offset = bo.mutable_data();
            io.q_scale = qs.mutable_data();
            io.flags = fl.mutable_data();
            io.report.gps = go.out();
            io.report.baro = bo_.out();
            io.report.compass = co.out();
            io.report.odometer = oo.out();
            if (!mag_obj.is_none()) io.report.mag = mo.out();
            io.report.zupt = zu.out();
            io.report.zaru = za.out();
            io.report.nhc = nh.out();
            py::dict d;
            if (smooth) {
              // The smoothed arrays start as copies of the forward ones (written by the forward
              // loop): the samples the backward pass does not visit (before navigation) keep them.
              py::array_t<double> sllh({n, py::ssize_t(3)}), sbo({n});
              auto sv = empty<S>(n, 3), sq = empty<S>(n, 4), sba = empty<S>(n, 3), sbg = empty<S>(n, 3),
                   ssig = empty<S>(n, N), ssa = empty<S>(SF ? n : 0, 3), ssg = empty<S>(SF ? n : 0, 3);
              GpsInsSmoothedOutput<S, SF> out;
              out.out.llh = sllh.mutable_data();
              out.out.v_n = sv.mutable_data();
              out.out.q_nb = sq.mutable_data();
              out.out.acc_bias = sba.mutable_data();
              out.out.gyro_bias = sbg.mutable_data();
              if (SF) {
                out.out.acc_scale = ssa.mutable_data();
                out.out.gyro_scale = ssg.mutable_data();
              }
              out.out.sigma = ssig.mutable_data();
              out.out.baro_offset = sbo.mutable_data();
              GpsInsRtsModel<S, SF> model(f, io.t, io.gyro, io.accel, io.increments);
              auto forward = [&](auto&& obs) {
                gpsins_batch(f, io, obs);
                const GpsInsBatchIo<S>& o = out.out;
                std::copy(io.llh, io.llh + 3 * n, o.llh);
                std::copy(io.v_n, io.v_n + 3 * n, o.v_n);
                std::copy(io.q_nb, io.q_nb + 4 * n, o.q_nb);
                std::copy(io.acc_bias, io.acc_bias + 3 * n, o.acc_bias);
                std::copy(io.gyro_bias, io.gyro_bias + 3 * n, o.gyro_bias);
                if (SF) {
                  std::copy(io.acc_scale, io.acc_scale + 3 * n, o.acc_scale);
                  std::copy(io.gyro_scale, io.gyro_scale + 3 * n, o.gyro_scale);
                }
                std::copy(io.sigma, io.sigma + N * n, o.sigma);
                std::copy(io.baro_offset, io.baro_offset + n, o.baro_offset);
              };
              const py::dict info =
                  run_smoothed(model, std::size_t(n), gpsins_max_epochs(f.params(), io), segment, forward, out);
              py::dict sd;
              sd["llh"] = sllh;
              sd["v_n"] = sv;
              sd["q_nb"] = sq;
              sd["acc_bias"] = sba;
              sd["gyro_bias"] = sbg;
              if (SF) {
                sd["acc_scale"] = ssa;
                sd["gyro_scale"] = ssg;
              }
              sd["sigma"] = ssig;
              sd["baro_offset"] = sbo;
              sd["info"] = info;
              d["smoothed"] = sd;
            } else {
              py::gil_scoped_release release;
              gpsins_batch(f, io);
            }
            d["llh"] = llh;
            d["v_n"] = v;
            d["q_nb"] = q;
            d["acc_bias"] = ba;
            d["gyro_bias"] = bg;
            if (SF) {
              d["acc_scale"] = sa;
              d["gyro_scale"] = sg;
            }
            d["sigma"] = sig;
            d["baro_offset"] = bo;
            d["q_scale"] = qs;
            d["flags"] = fl;
            d["gps"] = go.dict();
            d["baro"] = bo_.dict();
            d["compass"] = co.dict();
            d["odometer"] = oo.dict();
            d["mag"] = mo.dict();
            d["zupt"] = zu.dict();
            d["zaru"] = za.dict();
            d["nhc"] = nh.dict();
            d["align_method"] = std::string(to_string(f.align_method()));
            d["heading_source"] = std::string(to_string(f.heading_source()));
            return d;
          },
          py::arg("t"), py::arg("gyro"), py::arg("accel"), py::arg("mag"), py::arg("increments"), py::arg("gps_t"),
          py::arg("gps_llh"), py::arg("gps_vel"), py::arg("gps_pos_sigma"), py::arg("gps_vel_sigma"), py::arg("baro_t"),
          py::arg("baro_h"), py::arg("compass_t"), py::arg("compass_yaw"), py::arg("odo_t"), py::arg("odo_speed"),
          py::arg("smooth") = false, py::arg("segment") = std::size_t(256), py::arg("gps_solution") = py::none(),
          "Batch run in C++ with the GIL released (see quatnav::gpsins_batch). Returns a dict of arrays; "
          "each aid's report is a dict (innovation, nis, status, decision, inflation). With smooth, also "
          "'smoothed': the Rauch-Tung-Striebel estimates (llh, v_n, q_nb, acc_bias, gyro_bias, sigma, "
          "baro_offset; acc_scale, gyro_scale with the scale-factor states) and the smoother's 'info' "
          "(nav/gps_ins/smoother.hpp).");
  def_state_dict<F>(cls);
}

/// GpsInsParams_<dtype>, the update results and GpsInsFilter_<dtype> (16 states).
template <class S> void bind_gpsins_scalar(py::module_& m) {
  bind_gpsins_update<S, 1>(m);
  bind_gpsins_update<S, 2>(m);
  bind_gpsins_update<S, 3>(m);
  bind_fields_struct<quatnav::GpsInsParams<S>>(m, cls_name<S>("GpsInsParams"),
                                               "Parameters of GpsInsFilter (nav/gps_ins/params.hpp).");
  bind_gpsins_filter<S, false>(m);
}

}  // namespace quatnav_py
