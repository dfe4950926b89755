// Bindings of the WGS-84 Earth model (float64) and the strapdown mechanization (float32 and
// float64): StrapdownState_f64/_f32, strapdown_step, and strapdown_batch with the GIL released.
#include <quatnav/core/earth.hpp>
#include <quatnav/nav/strapdown.hpp>

#include "common.hpp"

namespace quatnav_py {

namespace {

template <class S> void bind_strapdown_scalar(py::module_& m) {
  using namespace quatnav;
  using St = StrapdownState<S>;
  using V3 = Vec3<S>;
  py::class_<St>(m, cls_name<S>("StrapdownState").c_str(),
                 "Strapdown navigation state: q_nb [w, x, y, z], v_n (m/s), lat, lon (rad), h (m) "
                 "(double), and the previous increments dtheta_prev (rad), dv_prev (m/s), has_prev.")
      .def(py::init([](const Quat<S>& q_nb, const V3& v_n, double lat, double lon, double h) {
             St s;
             s.q_nb = q_nb;
             s.v_n = v_n;
             s.lat = lat;
             s.lon = lon;
             s.h = h;
             return s;
           }),
           py::arg("q_nb"), py::arg("v_n"), py::arg("lat"), py::arg("lon"), py::arg("h"))
      .def_readwrite("q_nb", &St::q_nb)
      .def_readwrite("v_n", &St::v_n)
      .def_readwrite("lat", &St::lat)
      .def_readwrite("lon", &St::lon)
      .def_readwrite("h", &St::h)
      .def_readwrite("dtheta_prev", &St::dtheta_prev)
      .def_readwrite("dv_prev", &St::dv_prev)
      .def_readwrite("has_prev", &St::has_prev)
      .def("copy", [](const St& s) { return St(s); });

  m.def(
      "strapdown_step",
      [](St& st, const V3& omega_ib_b, const V3& f_ib_b, S dt, bool earth_rotation) {
        StrapdownParams p;
        p.earth_rotation = earth_rotation;
        return status_str(strapdown_step(st, omega_ib_b, f_ib_b, dt, p));
      },
      py::arg("state"), py::arg("omega_ib_b"), py::arg("f_ib_b"), py::arg("dt"),
      py::arg("earth_rotation") = true,
      "One step (in place). Inputs are the mean rate and specific force over the interval. "
      "Returns the status string; the state is untouched unless it is 'ok'.");

  m.def(
      "strapdown_batch",
      [](St& st, const carray<S>& omega_ib_b, const carray<S>& f_ib_b, const carray<S>& dt,
         bool earth_rotation) {
        const py::ssize_t n = omega_ib_b.ndim() == 2 ? omega_ib_b.shape(0) : -1;
        if (n < 0) throw py::value_error("omega_ib_b: expected shape (N, 3)");
        require_shape<S>(omega_ib_b, "omega_ib_b", n, 3);
        require_shape<S>(f_ib_b, "f_ib_b", n, 3);
        require_shape<S>(dt, "dt", n, -1);
        auto q = empty<S>(n, 4), v = empty<S>(n, 3);
        py::array_t<double> llh({n, py::ssize_t(3)});
        py::array_t<std::uint8_t> status({n});
        {
          const S* pw = omega_ib_b.data();
          const S* pf = f_ib_b.data();
          const S* pd = dt.data();
          S *pq = q.mutable_data(), *pv = v.mutable_data();
          double* pl = llh.mutable_data();
          std::uint8_t* ps = status.mutable_data();
          StrapdownParams p;
          p.earth_rotation = earth_rotation;
          py::gil_scoped_release release;
          strapdown_batch(st, pw, pf, pd, std::size_t(n), p, pq, pv, pl, ps);
        }
        return py::make_tuple(q, v, llh, status);
      },
      py::arg("state"), py::arg("omega_ib_b"), py::arg("f_ib_b"), py::arg("dt"),
      py::arg("earth_rotation") = true,
      "Run N steps in C++ with the GIL released (state updated in place). Returns (q_nb (N, 4), "
      "v_n (N, 3), llh (N, 3) float64 [lat, lon, h], status (N,) uint8 quatnav::Status).");
}

}  // namespace

void bind_strapdown(py::module_& m) {
  using namespace quatnav;
  auto me = m.def_submodule("earth", "WGS-84 Earth model of the C++ core (float64)");
  me.def("radii", [](double lat) {
    const auto r = earth::radii(lat);
    return py::make_tuple(r.R_M, r.R_N);
  });
  me.def("gravity", [](double lat, double h) { return earth::gravity(lat, h); });
  me.def("earth_rate_n", [](double lat) { return earth::earth_rate_n(lat); });
  me.def("transport_rate_n",
         [](double lat, double h, const Vec3<double>& v) { return earth::transport_rate_n(lat, h, v); });
  me.def("geodetic_rates",
         [](double lat, double h, const Vec3<double>& v) { return earth::geodetic_rates(lat, h, v); });
  me.def("ned_to_geodetic", [](const Vec3<double>& p, double lat0, double lon0, double h0) {
    return earth::ned_to_geodetic(p, lat0, lon0, h0);
  });
  me.def("geodetic_to_ned", [](double lat, double lon, double h, double lat0, double lon0, double h0) {
    return earth::geodetic_to_ned(lat, lon, h, lat0, lon0, h0);
  });
  me.def("geodetic_to_ecef", [](double lat, double lon, double h) { return earth::geodetic_to_ecef(lat, lon, h); });
  me.attr("G0") = earth::kG0;
  me.attr("G1") = earth::kG1;
  me.attr("G2") = earth::kG2;
  me.attr("G3") = earth::kG3;
  me.attr("OMEGA_IE") = earth::kOmegaIe;

  auto ms = m.def_submodule("strapdown", "NED strapdown mechanization (see quatnav/nav/strapdown.hpp)");
  bind_strapdown_scalar<double>(ms);
  bind_strapdown_scalar<float>(ms);
}

}  // namespace quatnav_py
