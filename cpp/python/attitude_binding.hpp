// A binding template shared by the attitude filters (QuaternionEKF, EulerEKF, ...): the step
// methods, state get/set as dicts of arrays, and the batch run with the GIL released.
#pragma once

#include <quatnav/attitude/attitude.hpp>
#include <quatnav/attitude/batch.hpp>
#include <quatnav/attitude/smoother.hpp>

#include <cstring>
#include <type_traits>

#include "common.hpp"
#include "smoother_binding.hpp"

namespace quatnav_py {

/// The magnetic field reference of a state dict (get_state / set_state).
template <class S> void put_mag_ref(py::dict& d, const quatnav::MagRef<S>& m) {
  d["mag_ref"] = quatnav::Vec3<S>(m.ref);
  d["mag_sin_dip_sum"] = m.sin_dip_sum;
  d["mag_ref_count"] = m.count;
  d["mag_ref_fixed"] = m.fixed;
}

template <class S> quatnav::MagRef<S> get_mag_ref(const py::dict& d) {
  quatnav::MagRef<S> m;
  m.ref = d["mag_ref"].cast<quatnav::Vec3<S>>();
  m.sin_dip_sum = d["mag_sin_dip_sum"].cast<S>();
  m.count = d["mag_ref_count"].cast<std::uint32_t>();
  m.fixed = d["mag_ref_fixed"].cast<bool>();
  return m;
}

template <class F> struct AttitudeRun {
  static py::tuple run(F& f, const carray<typename F::Scalar>& gyr, const carray<typename F::Scalar>& acc,
                       const py::object& mag_obj, const carray<typename F::Scalar>& dt, bool smooth,
                       std::size_t segment) {
    using S = typename F::Scalar;
    constexpr int N = F::kStates;
    const py::ssize_t n = gyr.ndim() == 2 ? gyr.shape(0) : -1;
    if (n < 0) throw py::value_error("gyr: expected shape (N, 3)");
    require_shape<S>(gyr, "gyr", n, 3);
    require_shape<S>(acc, "acc", n, 3);
    require_shape<S>(dt, "dt", n, -1);
    carray<S> mag;
    const bool has_mag = !mag_obj.is_none();
    if (has_mag) {
      mag = carray<S>::ensure(mag_obj);
      if (!mag) throw py::type_error("mag: expected a numeric array of shape (N, 3)");
      require_shape<S>(mag, "mag", n, 3);
    }
    auto quat = empty<S>(n, 4), bias = empty<S>(n, 3), sigma = empty<S>(n, N), att_sigma = empty<S>(n, 3);
    py::array_t<std::uint32_t> fl({n});
    const S* pg = gyr.data();
    const S* pa = acc.data();
    const S* pm = has_mag ? mag.data() : nullptr;
    const S* pd = dt.data();
    S *pq = quat.mutable_data(), *pb = bias.mutable_data(), *ps = sigma.mutable_data(), *pas = att_sigma.mutable_data();
    std::uint32_t* pf = fl.mutable_data();
    auto forward = [&](auto&& obs) { quatnav::run_attitude_batch(f, pg, pa, pm, pd, std::size_t(n), pq, pb, ps, pas, pf, obs); };
    if (!smooth) {
      {
        py::gil_scoped_release release;
        forward(quatnav::NoBatchObserver{});
      }
      return py::make_tuple(quat, bias, sigma, att_sigma, fl);
    }
    using Model = typename quatnav::AttitudeRtsModelOf<F>::type;
    if constexpr (std::is_void_v<Model>) {
      throw py::value_error("smooth: this filter has no smoother (QuaternionEKF's error-state default and EulerEKF have)");
    } else {
      auto qs = empty<S>(n, 4), bs = empty<S>(n, 3), ss = empty<S>(n, N), as = empty<S>(n, 3);
      quatnav::AttitudeSmoothedOutput<Model> out{qs.mutable_data(), bs.mutable_data(), ss.mutable_data(),
                                                 as.mutable_data()};
      Model model(f, pg, pd);
      // Every sample updates with the accelerometer: every sample may be a record. The smoothed
      // arrays start as the forward ones (samples before the initialization keep them).
      const py::dict info = run_smoothed(model, std::size_t(n), std::size_t(n), segment, [&](auto&& obs) {
        forward(obs);
        std::memcpy(out.quat, pq, sizeof(S) * 4 * std::size_t(n));
        std::memcpy(out.bias, pb, sizeof(S) * 3 * std::size_t(n));
        std::memcpy(out.sigma, ps, sizeof(S) * N * std::size_t(n));
        std::memcpy(out.att_sigma, pas, sizeof(S) * 3 * std::size_t(n));
      }, out);
      py::dict sd;
      sd["quat"] = qs;
      sd["bias"] = bs;
      sd["sigma"] = ss;
      sd["att_sigma"] = as;
      sd["info"] = info;
      return py::make_tuple(quat, bias, sigma, att_sigma, fl, sd);
    }
  }
};

/// Methods common to every attitude filter class `cls` of type F.
template <class F, class Cls> void def_attitude_common(Cls& cls) {
  using S = typename F::Scalar;
  using V3 = quatnav::Vec3<S>;
  cls.def_property_readonly("params", &F::params)
      .def_property_readonly("quat", [](const F& f) { return quatnav::Quat<S>(f.quat()); },
                             "q_nb [w, x, y, z]")
      .def_property_readonly("bias", [](const F& f) { return V3(f.bias()); }, "gyro bias [rad/s]")
      .def_property_readonly("covariance", [](const F& f) { return f.covariance(); })
      .def_property_readonly("attitude_covariance", [](const F& f) { return quatnav::Mat3<S>(f.attitude_covariance()); })
      .def_property_readonly("initialized", &F::initialized)
      .def("initialize", [](F& f, const V3& acc, const std::optional<V3>& mag) {
            return status_str(mag ? f.initialize(acc, *mag) : f.initialize(acc));
          }, py::arg("acc"), py::arg("mag") = py::none())
      .def("set_mag_dip", &F::set_mag_dip, py::arg("dip"))
      .def("predict", [](F& f, const V3& gyr, S dt) { return status_str(f.predict(gyr, dt)); },
           py::arg("gyr"), py::arg("dt"))
      .def("update_acc", [](F& f, const V3& acc, S gate) { return f.update_acc(acc, gate); },
           py::arg("acc"), py::arg("gate") = S(0))
      .def("update_mag", [](F& f, const V3& mag, S gate) { return f.update_mag(mag, gate); },
           py::arg("mag"), py::arg("gate") = S(0))
      .def("run", &AttitudeRun<F>::run, py::arg("gyr"), py::arg("acc"), py::arg("mag"), py::arg("dt"),
           py::arg("smooth") = false, py::arg("segment") = std::size_t(256),
           "Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth "
           "item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.");
}

}  // namespace quatnav_py
