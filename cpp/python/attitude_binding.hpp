// The binding of the attitude filters, one template for all of them (QuaternionEKFPaper,
// QuaternionEKF, EulerEKF, MargFilter): parameters and state from their field declarations
// (fields_binding.hpp), the step methods every attitude filter has, and the batch runs with the
// GIL released. A filter's own binding (bind_attitude.cpp, bind_eskf.cpp, bind_euler.cpp,
// bind_marg_f64.cpp, bind_marg_f32.cpp) is a few lines on top.
#pragma once

#include <quatnav/attitude/attitude.hpp>
#include <quatnav/attitude/batch.hpp>
#include <quatnav/attitude/marg_filter.hpp>
#include <quatnav/attitude/smoother.hpp>

#include <cstring>
#include <optional>
#include <string>
#include <type_traits>

#include "common.hpp"
#include "fields_binding.hpp"
#include "smoother_binding.hpp"

namespace quatnav_py {

/// A member function returning Status, bound under `name` with the status as its string.
template <class F, class Cls, class... Args, class... Extra>
void def_status(Cls& cls, const char* name, quatnav::Status (F::*fn)(Args...), const Extra&... extra) {
  cls.def(name, [fn](F& f, Args... a) { return status_str((f.*fn)(a...)); }, extra...);
}

/// The magnetometer argument of a batch run: None (a null pointer) or an (n, 3) array of S, kept in `a`.
template <class S> const S* optional_rows(const py::object& obj, const char* name, py::ssize_t n, carray<S>& a) {
  if (obj.is_none()) return nullptr;
  a = carray<S>::ensure(obj);
  if (!a) throw py::type_error(std::string(name) + ": expected a numeric array of shape (N, 3)");
  require_shape<S>(a, name, n, 3);
  return a.data();
}

/// The batch run of a Kalman attitude filter (run_attitude_batch): (quat, bias, sigma, att_sigma, flags);
/// with smooth, a sixth item: the Rauch-Tung-Striebel estimates and the smoother's report.
template <class F>
py::tuple attitude_run(F& f, const carray<typename F::Scalar>& gyr, const carray<typename F::Scalar>& acc,
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
  const S* pm = optional_rows<S>(mag_obj, "mag", n, mag);
  auto quat = empty<S>(n, 4), bias = empty<S>(n, 3), sigma = empty<S>(n, N), att_sigma = empty<S>(n, 3);
  py::array_t<std::uint32_t> fl({n});
  const S *pg = gyr.data(), *pa = acc.data(), *pd = dt.data();
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
    throw py::value_error("smooth: this filter has no smoother (QuaternionEKF and EulerEKF have)");
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

/// The batch run of MargFilter with GPS velocity fixes (run_marg_batch): (quat, bias, gps_acc_n, residual, flags).
template <class S>
py::tuple marg_run(quatnav::MargFilter<S>& f, const carray<double>& t, const carray<S>& dt, const carray<S>& gyr,
                   const carray<S>& acc, const py::object& mag_obj, const carray<double>& gps_t,
                   const carray<S>& gps_vel) {
  const py::ssize_t n = gyr.ndim() == 2 ? gyr.shape(0) : -1;
  if (n < 0) throw py::value_error("gyr: expected shape (N, 3)");
  require_shape<S>(gyr, "gyr", n, 3);
  require_shape<S>(acc, "acc", n, 3);
  require_shape<double>(t, "t", n, -1);
  require_shape<S>(dt, "dt", n, -1);
  const py::ssize_t m = gps_t.ndim() == 1 ? gps_t.shape(0) : -1;
  if (m < 0) throw py::value_error("gps_t: expected shape (M,)");
  require_shape<S>(gps_vel, "gps_vel_n", m, 3);
  carray<S> mag;
  const S* pm = optional_rows<S>(mag_obj, "mag", n, mag);
  auto quat = empty<S>(n, 4), bias = empty<S>(n, 3), gps_acc = empty<S>(n, 3), resid = empty<S>(n, -1);
  py::array_t<std::uint32_t> fl({n});
  {
    const S *pd = dt.data(), *pg = gyr.data(), *pa = acc.data(), *pgv = gps_vel.data();
    const double *pt = t.data(), *pgt = gps_t.data();  // times in double for every S
    S *pq = quat.mutable_data(), *pb = bias.mutable_data(), *pga = gps_acc.mutable_data(), *pr = resid.mutable_data();
    std::uint32_t* pf = fl.mutable_data();
    py::gil_scoped_release release;
    quatnav::run_marg_batch(f, pt, pd, pg, pa, pm, std::size_t(n), pgt, m > 0 ? pgv : nullptr, std::size_t(m), pq, pb,
                            pga, pr, pf);
  }
  return py::make_tuple(quat, bias, gps_acc, resid, fl);
}

/// The class of an attitude filter F with what every attitude filter has: the constructor from
/// its Params, params, quat, bias, initialized, initialize(acc, mag=None), set_mag_dip, predict,
/// get_state / set_state / state_fields (from F::State's declaration). Params must be bound.
template <class F> py::class_<F> bind_attitude_class(py::module_& m, const char* base) {
  using S = typename F::Scalar;
  using V3 = quatnav::Vec3<S>;
  py::class_<F> cls(m, cls_name<S>(base).c_str());
  cls.def(py::init<const typename F::Params&>(), py::arg("params"))
      .def_property_readonly("params", &F::params)
      .def_property_readonly("quat", [](const F& f) { return quatnav::Quat<S>(f.quat()); }, "q_nb [w, x, y, z]")
      .def_property_readonly("bias", [](const F& f) { return V3(f.bias()); }, "gyro bias [rad/s]")
      .def_property_readonly("initialized", &F::initialized)
      .def("initialize", [](F& f, const V3& acc, const std::optional<V3>& mag) {
            return status_str(mag ? f.initialize(acc, *mag) : f.initialize(acc));
          }, py::arg("acc"), py::arg("mag") = py::none())
      .def("set_mag_dip", &F::set_mag_dip, py::arg("dip"));
  def_status<F>(cls, "predict", &F::predict, py::arg("gyr"), py::arg("dt"));
  def_state_dict<F>(cls);
  return cls;
}

/// A Kalman attitude filter (run_attitude_batch): bind_attitude_class and the covariance, the
/// updates of the accelerometer and magnetometer, reset(attitude, gyro_bias, P) and the batch run.
template <class F> py::class_<F> bind_attitude_kf(py::module_& m, const char* base, const char* attitude_name) {
  using S = typename F::Scalar;
  using V3 = quatnav::Vec3<S>;
  auto cls = bind_attitude_class<F>(m, base);
  cls.def_property_readonly("covariance", [](const F& f) { return quatnav::Mat<S, F::kStates, F::kStates>(f.covariance()); })
      .def_property_readonly("attitude_covariance", [](const F& f) { return quatnav::Mat3<S>(f.attitude_covariance()); })
      .def_property_readonly("extra_flags", &F::extra_flags)
      .def("update_acc", [](F& f, const V3& acc, S gate) { return f.update_acc(acc, gate); }, py::arg("acc"),
           py::arg("gate") = S(0))
      .def("update_mag", [](F& f, const V3& mag, S gate) { return f.update_mag(mag, gate); }, py::arg("mag"),
           py::arg("gate") = S(0))
      .def("run", &attitude_run<F>, py::arg("gyr"), py::arg("acc"), py::arg("mag"), py::arg("dt"),
           py::arg("smooth") = false, py::arg("segment") = std::size_t(256),
           "Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth "
           "item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.");
  def_status<F>(cls, "reset", &F::reset, py::arg(attitude_name), py::arg("gyro_bias"), py::arg("P"));
  return cls;
}

/// QuaternionEKFPaper (7 states) and QuaternionEKF (6 states): bind_attitude_kf and the joint update.
template <class F> void bind_quaternion_kf(py::module_& m, const char* base) {
  using S = typename F::Scalar;
  using V3 = quatnav::Vec3<S>;
  bind_attitude_kf<F>(m, base, "q_nb")
      .def("update_acc_mag", [](F& f, const V3& a, const V3& mg, S gate) { return f.update_acc_mag(a, mg, gate); },
           py::arg("acc"), py::arg("mag"), py::arg("gate") = S(0))
      .def_property_readonly("at_rest", &F::at_rest);
}

/// MargFilter for one S: its update result, parameters and class.
template <class S> void bind_marg(py::module_& m) {
  using F = quatnav::MargFilter<S>;
  using R = typename F::Result;
  using V3 = quatnav::Vec3<S>;
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
  bind_fields_struct<typename F::Params>(m, cls_name<S>("MargFilterParams"), "Parameters of MargFilter (marg_filter.hpp).")
      .def_property_readonly("valid", [](const typename F::Params& p) { return F::valid_params(p); })
      .def_static("paper", &F::Params::paper, "Parameters of the plain paper-001 filter (robustness parts off).");
  auto cls = bind_attitude_class<F>(m, "MargFilter");
  cls.def_property_readonly("gps_acc_available", &F::gps_acc_available)
      .def_property_readonly("at_rest", &F::at_rest)
      .def_property_readonly("gps_acc_n", [](const F& f) { return V3(f.gps_acc_n()); })
      .def("update_acc", &F::update_acc, py::arg("acc"))
      .def("update_acc_mag", &F::update_acc_mag, py::arg("acc"), py::arg("mag"))
      .def("run", &marg_run<S>, py::arg("t"), py::arg("dt"), py::arg("gyr"), py::arg("acc"), py::arg("mag"),
           py::arg("gps_t"), py::arg("gps_vel_n"),
           "Batch run (GIL released). Returns (quat, bias, gps_acc_n, residual, flags).");
  def_status<F>(cls, "reset", &F::reset, py::arg("q_nb"), py::arg("gyro_bias"));
  def_status<F>(cls, "update_gps_velocity", &F::update_gps_velocity, py::arg("v_n"), py::arg("t"));
}

}  // namespace quatnav_py
