// GpsInsFilter_f64, GpsInsParams_f64 (gpsins_binding.hpp; the _f32 classes are in
// bind_gpsins_f32.cpp).
#include "gpsins_binding.hpp"

namespace quatnav_py {

void bind_gpsins_f64(py::module_& m) {
  bind_gpsins_scalar<double>(m);
  m.def(
      "gpsins_decision_names",
      [] {
        py::list names;
        for (int k = 0; k < quatnav::kGpsInsDecisions; ++k) names.append(quatnav::to_string(quatnav::GpsInsDecision(k)));
        return names;
      },
      "Names of quatnav::GpsInsDecision by code (what GpsInsFilter did with an aiding sample).");
  m.def(
      "gnss_solution_names",
      [] {
        py::list names;
        for (int k = 0; k < quatnav::kGnssSolutions; ++k) names.append(quatnav::to_string(quatnav::GnssSolution(k)));
        return names;
      },
      "Names of quatnav::GnssSolution by code (the receiver's solution kind of a GNSS fix).");
}

}  // namespace quatnav_py
