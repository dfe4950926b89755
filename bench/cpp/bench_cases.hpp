// The cases and the harness of quatnav_bench_filters (bench_filters.cpp: main and the options).
// Each bench_cases_*.cpp instantiates the cases of one family of filters, so that no unit holds
// every filter's fixed-size Eigen code (one unit of all of them took 13 minutes to compile).
#pragma once
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "flop_counter.hpp"

#include <quatnav/quatnav.hpp>

// Heap allocations during the timed loop (the global operator new of bench_filters.cpp counts them).
extern std::atomic<std::uint64_t> g_allocs;

namespace qb {

using quatnav::Quat;
using quatnav::Vec3;
using quatnav_bench::Counted;

// ------------------------------------------------------------------------------------------
// Simulated MARG samples: smooth rotation (rates up to ~1 rad/s), gravity and an Earth field
// seen in the body frame, white noise and a constant gyro bias. Deterministic (fixed seed).
// ------------------------------------------------------------------------------------------
template <class S> struct Sample {
  Vec3<S> gyr, acc, mag;
  S dt;
};

struct SampleD {
  Vec3<double> gyr, acc, mag;
  double dt;
};

inline const std::vector<SampleD>& marg_samples() {
  static const std::vector<SampleD> data = [] {
    const std::size_t n = 4000;
    const double dt = 0.005;  // 200 Hz
    std::mt19937_64 rng(7);
    std::normal_distribution<double> N01(0.0, 1.0);
    const Vec3<double> g_n(0, 0, 9.80665), m_n(20e-6, 0.0, 45e-6), bias(0.01, -0.02, 0.005);
    Quat<double> q = quatnav::quat::from_euler(0.1, -0.2, 0.5);
    std::vector<SampleD> out(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double t = k * dt;
      const Vec3<double> w(0.8 * std::sin(0.9 * t), 0.6 * std::cos(0.7 * t), 1.0 * std::sin(0.3 * t + 1));
      q = quatnav::quat::normalized(quatnav::quat::mul(q, quatnav::quat::from_rotvec<double>(w * dt)));
      SampleD s;
      s.dt = dt;
      for (int i = 0; i < 3; ++i) {
        s.gyr[i] = w[i] + bias[i] + 0.002 * N01(rng);
      }
      s.acc = quatnav::quat::rotate_inv(q, Vec3<double>(-g_n));
      s.mag = quatnav::quat::rotate_inv(q, m_n);
      for (int i = 0; i < 3; ++i) {
        s.acc[i] += 0.02 * N01(rng);
        s.mag[i] += 0.3e-6 * N01(rng);
      }
      out[k] = s;
    }
    return out;
  }();
  return data;
}

template <class S> std::vector<Sample<S>> samples_as() {
  std::vector<Sample<S>> out;
  for (const SampleD& d : marg_samples())
    out.push_back({d.gyr.cast<S>(), d.acc.cast<S>(), d.mag.cast<S>(), S(d.dt)});
  return out;
}

// ------------------------------------------------------------------------------------------
// Cases: one struct per filter (and time-update policy).
// ------------------------------------------------------------------------------------------
template <class S> struct QEKFCase {
  static constexpr const char* name = "QuaternionEKFPaper";
  static constexpr bool countable = true;
  static constexpr const char* policy = "ekf";
  static constexpr const char* step_desc = "predict+acc+mag";
  quatnav::QuaternionEKFPaper<S> f;
  void init(const Sample<S>& s) { f.initialize(s.acc, s.mag); }
  void step(const Sample<S>& s) {
    f.predict(s.gyr, s.dt);
    f.update_acc(s.acc);
    f.update_mag(s.mag);
  }
};

template <class S> struct QEKFJointCase : QEKFCase<S> {
  static constexpr const char* policy = "ekf, joint 6-row update";
  static constexpr const char* step_desc = "predict+acc_mag";
  void step(const Sample<S>& s) {
    this->f.predict(s.gyr, s.dt);
    this->f.update_acc_mag(s.acc, s.mag);
  }
};

// Where a QuaternionEKFPaper step goes: the time update alone, with the accelerometer update, the
// covariance floor off (cov_floor = 0: no error-state test after each part), and the plain filter
// of the paper (QuaternionEKFParams::paper(): no low-pass, rest, disturbance tests; 3-row
// magnetometer update). Differences between these rows split the full step's cost.
template <class S> struct QEKFPredictCase : QEKFCase<S> {
  static constexpr const char* policy = "ekf, predict only";
  static constexpr const char* step_desc = "predict";
  void step(const Sample<S>& s) { this->f.predict(s.gyr, s.dt); }
};

template <class S> struct QEKFPredictAccCase : QEKFCase<S> {
  static constexpr const char* policy = "ekf, predict+acc only";
  static constexpr const char* step_desc = "predict+acc";
  void step(const Sample<S>& s) {
    this->f.predict(s.gyr, s.dt);
    this->f.update_acc(s.acc);
  }
};

template <class S> struct QEKFNoFloorCase : QEKFCase<S> {
  static constexpr const char* policy = "ekf, cov_floor 0";
  void init(const Sample<S>& s) {
    quatnav::QuaternionEKFParams<S> p;
    p.cov_floor = S(0);
    this->f = quatnav::QuaternionEKFPaper<S>(p);
    this->f.initialize(s.acc, s.mag);
  }
};

template <class S> struct QEKFPaperCase : QEKFCase<S> {
  static constexpr const char* policy = "ekf, paper() parameters";
  void init(const Sample<S>& s) {
    this->f = quatnav::QuaternionEKFPaper<S>(quatnav::QuaternionEKFParams<S>::paper());
    this->f.initialize(s.acc, s.mag);
  }
};

// The default QuaternionEKF of the Python package: the 6-state error-state filter
// (quaternion_ekf.hpp) with the robustness parts, and the same split as above.
template <class S> struct ESKFCase {
  static constexpr const char* name = "QuaternionEKF";
  static constexpr bool countable = true;
  static constexpr const char* policy = "error state";
  static constexpr const char* step_desc = "predict+acc+mag";
  quatnav::QuaternionEKF<S> f;
  void init(const Sample<S>& s) { f.initialize(s.acc, s.mag); }
  void step(const Sample<S>& s) {
    f.predict(s.gyr, s.dt);
    f.update_acc(s.acc);
    f.update_mag(s.mag);
  }
};

template <class S> struct ESKFPredictCase : ESKFCase<S> {
  static constexpr const char* policy = "error state, predict only";
  static constexpr const char* step_desc = "predict";
  void step(const Sample<S>& s) { this->f.predict(s.gyr, s.dt); }
};

template <class S> struct ESKFPredictAccCase : ESKFCase<S> {
  static constexpr const char* policy = "error state, predict+acc only";
  static constexpr const char* step_desc = "predict+acc";
  void step(const Sample<S>& s) {
    this->f.predict(s.gyr, s.dt);
    this->f.update_acc(s.acc);
  }
};

template <class S> struct ESKFPaperCase : ESKFCase<S> {
  static constexpr const char* policy = "error state, paper() parameters";
  void init(const Sample<S>& s) {
    this->f = quatnav::QuaternionEKF<S>(quatnav::QuaternionEKFParams<S>::paper());
    this->f.initialize(s.acc, s.mag);
  }
};

template <class S> struct EulerEKFCase {
  static constexpr const char* name = "EulerEKF";
  static constexpr bool countable = true;
  static constexpr const char* policy = "ekf";
  static constexpr const char* step_desc = "predict+acc+mag";
  quatnav::EulerEKF<S> f;
  void init(const Sample<S>& s) { f.initialize(s.acc, s.mag); }
  void step(const Sample<S>& s) {
    f.predict(s.gyr, s.dt);
    f.update_acc(s.acc);
    f.update_mag(s.mag);
  }
};

// The Gauss-Newton MARG filter (marg_filter.hpp): gyro integration, then the accelerometer and
// magnetometer pair by Gauss-Newton. The iterations of its updates are summed (the flop count of
// a step depends on them; printed with --iterations).
template <class S> struct MargCase {
  static constexpr const char* name = "MargFilter";
  static constexpr bool countable = true;
  static constexpr const char* policy = "gauss-newton";
  static constexpr const char* step_desc = "predict+acc_mag";
  static inline std::uint64_t updates = 0, iterations = 0;
  quatnav::MargFilter<S> f;
  void init(const Sample<S>& s) { f.initialize(s.acc, s.mag); }
  void step(const Sample<S>& s) {
    f.predict(s.gyr, s.dt);
    const auto r = f.update_acc_mag(s.acc, s.mag);
    ++updates;
    iterations += std::uint64_t(r.iterations);
  }
};

// The 16-state GPS/INS filter (gps_ins.hpp), navigating from a given state: the time update of one
// IMU sample (strapdown and covariance propagation) with a GNSS epoch every 200th sample (1 Hz at
// 200 Hz, so that the unaided vertical channel and P stay bounded over the repeats: the step is
// the time update plus 1/200 of an epoch), and the time update with an epoch at every sample
// (position and velocity, 3 + 3 rows). The fixes are the filter's own position and velocity (the
// rows' cost does not depend on the innovation). The flop count leaves out what the filter computes
// in double whatever S is (the geodetic position, the Earth terms of F).
template <class S, bool SF = false> struct GpsInsCaseT {
  static constexpr const char* name = SF ? "GpsInsFilter [scale factors]" : "GpsInsFilter";
  static constexpr bool countable = true;
  static constexpr const char* policy = "time update, gnss 1/200";
  static constexpr const char* step_desc = "predict";
  static constexpr int kGnssEvery = 200;
  quatnav::GpsInsFilter<S, SF> f;
  int n = 0;
  void init(const Sample<S>&) {
    const Quat<S> q = quatnav::quat::from_euler<S>(S(0.1), S(-0.2), S(0.5));
    const auto P = f.initial_covariance(Vec3<S>(S(2), S(2), S(4)), S(0.2));
    f.reset(q, Vec3<S>(S(10), S(2), S(0)), 0.8, 0.2, 100.0, Vec3<S>::Zero(), Vec3<S>::Zero(), P);
  }
  void gnss() {
    const Vec3<double> llh = f.llh();
    f.update_gps(llh[0], llh[1], llh[2], Vec3<S>(f.v_n()), Vec3<S>(S(2), S(2), S(4)), Vec3<S>::Constant(S(0.2)));
  }
  void step(const Sample<S>& s) {
    f.predict(s.gyr, s.acc, s.dt);
    if (++n == kGnssEvery) {
      n = 0;
      gnss();
    }
  }
};
template <class S> using GpsInsCase = GpsInsCaseT<S, false>;
/// With the gyro and accelerometer scale-factor states (22 error states).
template <class S> using GpsInsScaleCase = GpsInsCaseT<S, true>;
template <class S, bool SF = false> struct GpsInsGnssCaseT : GpsInsCaseT<S, SF> {
  static constexpr const char* policy = "time update + gnss pos+vel";
  static constexpr const char* step_desc = "predict+gnss";
  void step(const Sample<S>& s) {
    this->f.predict(s.gyr, s.acc, s.dt);
    this->gnss();
  }
};
template <class S> using GpsInsGnssCase = GpsInsGnssCaseT<S, false>;
template <class S> using GpsInsScaleGnssCase = GpsInsGnssCaseT<S, true>;

// The 13-state GPS-aided navigation filter (nav_filter13.hpp): its time update alone, one row per
// policy (EKF, second order, UKF), from a representative state and covariance. The measurement
// updates are the same for the three policies. The flop count leaves out the geodetic position,
// which the filter carries in double whatever S is.
template <class S, quatnav::TimeUpdate TU> struct Nav13CaseT {
  static constexpr const char* name = "NavFilter13";
  static constexpr const char* step_desc = "predict";
  static constexpr bool countable = true;
  quatnav::NavFilter13<S, TU> f;
  void init(const Sample<S>&) {
    const Quat<S> q = quatnav::quat::from_euler<S>(S(0.1), S(-0.1), S(0.5));
    quatnav::Mat<S, 13, 13> P = quatnav::Mat<S, 13, 13>::Zero();
    P.template block<3, 3>(0, 0).diagonal().setConstant(S(0.09));
    const quatnav::Mat43<S> X = quatnav::quat::xi(q);
    P.template block<4, 4>(3, 3) = S(0.25 * 0.03) * X * X.transpose();
    P.template block<3, 3>(7, 7).diagonal().setConstant(S(4e-4));
    P.template block<3, 3>(10, 10).diagonal().setConstant(S(1e-10));
    f.reset(Vec3<S>(S(1), S(1), S(0)), q, Vec3<S>::Zero(), Vec3<S>::Zero(), P, 0.63, 2.2, 50.0);
  }
  void step(const Sample<S>& s) { f.predict(s.gyr, s.acc, s.dt); }
};
template <class S> struct Nav13EkfCase : Nav13CaseT<S, quatnav::TimeUpdate::Ekf> {
  static constexpr const char* policy = "time update: ekf";
};
template <class S> struct Nav13SecondOrderCase : Nav13CaseT<S, quatnav::TimeUpdate::SecondOrder> {
  static constexpr const char* policy = "time update: second order";
};
template <class S> struct Nav13UkfCase : Nav13CaseT<S, quatnav::TimeUpdate::Ukf> {
  static constexpr const char* policy = "time update: ukf";
};

// ------------------------------------------------------------------------------------------
// Harness
// ------------------------------------------------------------------------------------------
struct Options {
  int reps = 21;
  std::size_t steps = 4000;  // steps per repeat
  std::string filter;
  bool csv = false;
  bool list = false;     // --list: print the case labels and exit
  bool flops = true;     // --no-flops: skip the counting run (callgrind.sh)
  std::string scalar;    // --scalar float|double: time only that one
  bool iterations = false;  // --iterations: MargFilter's mean Gauss-Newton iterations per update
};

// Not inlined, so that `valgrind --tool=callgrind --toggle-collect='*timed_steps*'` counts
// exactly the steps (bench/cpp/callgrind.sh).
template <class C, class S>
__attribute__((noinline)) void timed_steps(C& c, const std::vector<Sample<S>>& data, std::size_t& k,
                                           std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    c.step(data[k]);
    if (++k == data.size()) k = 1;
  }
}

template <class C, class S> C* make_case(const std::vector<Sample<S>>& data) {
  C* c = new C();
  c->init(data[0]);
  return c;
}

template <class S> const char* scalar_name() { return sizeof(S) == 4 ? "float" : "double"; }

template <class S, template <class> class CaseT>
double time_case(const Options& opt, std::uint64_t& allocs) {
  const std::vector<Sample<S>> data = samples_as<S>();
  CaseT<S>* c = make_case<CaseT<S>>(data);
  std::size_t k = 1;
  timed_steps(*c, data, k, opt.steps);  // warm-up
  std::vector<double> ns;
  ns.reserve(std::size_t(opt.reps));
  const std::uint64_t a0 = g_allocs.load();
  for (int r = 0; r < opt.reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    timed_steps(*c, data, k, opt.steps);
    const auto t1 = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(opt.steps));
  }
  allocs = g_allocs.load() - a0;
  delete c;
  std::nth_element(ns.begin(), ns.begin() + ns.size() / 2, ns.end());
  return ns[ns.size() / 2];
}

template <template <class> class CaseT> double count_flops() {
  const std::vector<Sample<Counted>> data = samples_as<Counted>();
  CaseT<Counted>* c = make_case<CaseT<Counted>>(data);
  std::size_t k = 1;
  const std::size_t n = 1000;
  timed_steps(*c, data, k, n);
  const std::uint64_t f0 = quatnav_bench::flop_count();
  timed_steps(*c, data, k, n);
  const double per_step = double(quatnav_bench::flop_count() - f0) / double(n);
  delete c;
  return per_step;
}

template <template <class> class CaseT> void run_case(const Options& opt) {
  const std::string label = std::string(CaseT<double>::name) + " [" + CaseT<double>::policy + "]";
  if (!opt.filter.empty() && label != opt.filter && label.find(opt.filter) == std::string::npos) return;
  if (opt.list) {
    std::printf("%s\t%s\n", label.c_str(), CaseT<double>::name);
    return;
  }
  double flops = 0.0;
  if constexpr (CaseT<double>::countable) {
    if (opt.flops) flops = count_flops<CaseT>();
  }
  std::uint64_t alloc_d = 0, alloc_f = 0;
  const double ns_d = opt.scalar != "float" ? time_case<double, CaseT>(opt, alloc_d) : 0.0;
  const double ns_f = opt.scalar != "double" ? time_case<float, CaseT>(opt, alloc_f) : 0.0;
  if (opt.csv) {
    std::printf("%s,%s,%s,%.0f,%.1f,%.1f,%llu\n", CaseT<double>::name, CaseT<double>::policy,
                CaseT<double>::step_desc, flops, ns_d, ns_f, (unsigned long long)(alloc_d + alloc_f));
  } else {
    std::printf("%-42s %-18s %8.0f %9.1f %7.2f %9.1f %7.2f %6llu\n", label.c_str(), CaseT<double>::step_desc,
                flops, ns_d, flops / ns_d, ns_f, flops / ns_f, (unsigned long long)(alloc_d + alloc_f));
  }
  if constexpr (std::is_same_v<CaseT<double>, MargCase<double>>) {
    if (opt.iterations) {
      const double u = double(MargCase<double>::updates + MargCase<float>::updates);
      std::printf("  MargFilter Gauss-Newton iterations per update (timed runs, f64+f32): %.3f\n",
                  double(MargCase<double>::iterations + MargCase<float>::iterations) / (u > 0 ? u : 1.0));
    }
  }
  std::fflush(stdout);
}

// One per unit (bench_cases_*.cpp), each running its cases in order.
void run_qekf_cases(const Options& opt);
void run_eskf_cases(const Options& opt);
void run_euler_marg_cases(const Options& opt);
void run_gpsins_cases(const Options& opt);
void run_nav13_cases(const Options& opt);
void run_nav13_ukf_cases(const Options& opt);

}  // namespace qb
