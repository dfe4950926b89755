// NavFilter13Ekf_f64, NavFilter13SecondOrder_f64, NavFilter13Ukf_f64 and their parameter and
// result classes (nav13_binding.hpp; the _f32 ones are in bind_nav13_f32.cpp), and the timing
// helper nav13_time_update_cost_ns, which times the three float64 filters instantiated here.
#include "nav13_binding.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace quatnav_py {
namespace {

/// Median over `repeats` of the mean time (ns) of `iterations` consecutive time updates, the three
/// policies interleaved within every repeat (double precision, a representative state and P).
template <quatnav::TimeUpdate TU>
double time_block(quatnav::NavFilter13<double, TU>& f, const quatnav::NavFilter13State<double>& s0, int iterations) {
  f.set_state(s0);
  const quatnav::Vec3<double> fb(0.05, -0.02, -9.79), wb(0.001, -0.002, 0.1);
  const auto a = std::chrono::steady_clock::now();
  for (int k = 0; k < iterations; ++k) f.predict(wb, fb, 0.01);
  const auto b = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::nano>(b - a).count() / iterations;
}

py::dict time_update_cost_ns(int repeats, int iterations) {
  using namespace quatnav;
  if (repeats < 1 || iterations < 1) throw py::value_error("repeats, iterations: expected positive integers");
  NavFilter13<double, TimeUpdate::Ekf> fe;
  NavFilter13<double, TimeUpdate::SecondOrder> fs;
  NavFilter13<double, TimeUpdate::Ukf> fu;
  const Quat<double> q = quat::from_euler(0.1, -0.1, 0.5);
  Mat<double, 13, 13> P = Mat<double, 13, 13>::Zero();
  P.block<3, 3>(0, 0).diagonal().setConstant(0.09);
  const Mat43<double> X = quat::xi(q);
  P.block<4, 4>(3, 3) = 0.25 * 0.03 * X * X.transpose();
  P.block<3, 3>(7, 7).diagonal().setConstant(4e-4);
  P.block<3, 3>(10, 10).diagonal().setConstant(1e-10);
  fe.reset(Vec3<double>(1, 1, 0), q, Vec3<double>::Zero(), Vec3<double>::Zero(), P, 0.63, 2.2, 50);
  const NavFilter13State<double> s0 = fe.state();
  std::vector<double> te, ts, tu;
  {
    py::gil_scoped_release release;
    for (int r = 0; r < repeats; ++r) {
      te.push_back(time_block(fe, s0, iterations));
      ts.push_back(time_block(fs, s0, iterations));
      tu.push_back(time_block(fu, s0, iterations));
    }
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t k = v.size() / 2;
    return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
  };
  py::dict d;
  d["ekf"] = median(te);
  d["second_order"] = median(ts);
  d["ukf"] = median(tu);
  d["repeats"] = repeats;
  d["iterations"] = iterations;
  return d;
}

}  // namespace

void bind_nav13_f64(py::module_& m) { bind_all<double>(m); }

void bind_nav13_timing(py::module_& m) {
  m.def("nav13_time_update_cost_ns", &time_update_cost_ns, py::arg("repeats") = 21, py::arg("iterations") = 2000,
        "Cost of one NavFilter13 time update per policy (ns, float64): the median over `repeats` of the mean "
        "over `iterations` consecutive predicts, the three policies interleaved in each repeat.");
}

}  // namespace quatnav_py
