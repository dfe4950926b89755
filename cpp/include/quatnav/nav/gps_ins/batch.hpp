// quatnav: the batch run of GpsInsFilter (gps_ins/filter.hpp) over an IMU record and aiding
// records, each at its own times: the per-sample outputs, the per-sample report of every aid and
// the flags; the loop the Python binding runs with the GIL released and the smoother records.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "../../core/checks.hpp"
#include "../../core/flags.hpp"
#include "../../core/types.hpp"
#include "filter.hpp"

namespace quatnav {

/// Where the batch run writes the per-sample report of one aiding record (any pointer may be
/// null): each row (aiding sample) holds `cols` updates (a GPS fix: position, velocity; an
/// altimeter sample: height, vertical velocity; others one) of `m` rows each.
template <class S> struct GpsInsAidOut {
  S* innovation = nullptr;           ///< (rows, cols * m): INS minus aid; NaN where no update was made
  S* nis = nullptr;                  ///< (rows, cols): NIS the gate saw; NaN where no update was made
  std::uint8_t* status = nullptr;    ///< (rows, cols): quatnav::Status
  std::uint8_t* decision = nullptr;  ///< (rows, cols): GpsInsDecision
  S* inflation = nullptr;            ///< (rows, cols): covariance inflation (1 unless Inflated)
};

/// Batch run over an IMU record and aiding records, each with its own times (s, strictly
/// increasing). IMU sample k holds the mean rate and specific force over (t[k-1], t[k]] (or, with
/// `increments`, the angle and velocity increments over it); sample 0 only fixes the start time.
/// An interval longer than max_dt but at most max_coast is coasted: propagated in equal steps of
/// at most max_dt with sample k (flags::kCoasted). After the time update of sample k: the
/// pseudo-measurements (update_constraints), the magnetometer sample of row k (NaN: none), then
/// the aiding samples with times in (t[k-1], t[k]], in the order compass, odometer, altimeter,
/// GPS; aids at or before t[0] are skipped. GNSS times are put on the IMU clock with the
/// parameter gps_time_offset, and each fix is applied with its age t[k] - (gps_t + offset) (the
/// filter takes the INS back by it). A GPS row whose position is NaN is skipped as absent; a NaN
/// velocity means "no velocity".
///
/// Inputs (row-major; aiding pointers may be null with count 0):
///   t (n), gyro (n x 3, rad/s or rad), accel (n x 3, m/s^2 or m/s), mag (n x 3, any unit, or null);
///   gps_t (ng), gps_llh (ng x 3: lat, lon rad, h m; double), gps_vel (ng x 3, m/s or NaN),
///   gps_pos_sigma (ng x 3, m, NaN: parameters), gps_vel_sigma (ng x 3, m/s, NaN: parameters),
///   gps_solution (ng, GnssSolution codes, or null: all Unknown; a code out of range: Unknown);
///   baro_t (nb), baro_h (nb, m); compass_t (nc), compass_yaw (nc, rad); odo_t (no), odo_speed (no, m/s).
/// Outputs (any may be null): llh (n x 3, double), v_n (n x 3), q_nb (n x 4), acc_bias,
///   gyro_bias (n x 3), acc_scale, gyro_scale (n x 3; scale-factor states only), sigma (n x 16, or
///   n x 22 with the scale-factor states), baro_offset (n), q_scale (n), flags (n); the reports of
///   the aids: gps (2 updates of 3 rows: position, velocity), baro (2 of 1: height, vertical
///   velocity), compass, odometer (1 of 1), and per IMU sample mag (1 of 1), zupt, zaru (1 of 3),
///   nhc (1 of 2). Statuses are quatnav::Status as uint8.
template <class S> struct GpsInsBatchIo {
  const double* t = nullptr;
  const S* gyro = nullptr;
  const S* accel = nullptr;
  const S* mag = nullptr;
  std::size_t n = 0;
  bool increments = false;
  const double* gps_t = nullptr;
  const double* gps_llh = nullptr;
  const S* gps_vel = nullptr;
  const S* gps_pos_sigma = nullptr;
  const S* gps_vel_sigma = nullptr;
  const std::uint8_t* gps_solution = nullptr;
  std::size_t ng = 0;
  const double* baro_t = nullptr;
  const double* baro_h = nullptr;
  std::size_t nb = 0;
  const double* compass_t = nullptr;
  const S* compass_yaw = nullptr;
  std::size_t nc = 0;
  const double* odo_t = nullptr;
  const S* odo_speed = nullptr;
  std::size_t no = 0;
  double* llh = nullptr;
  S* v_n = nullptr;
  S* q_nb = nullptr;
  S* acc_bias = nullptr;
  S* gyro_bias = nullptr;
  S* acc_scale = nullptr;
  S* gyro_scale = nullptr;
  S* sigma = nullptr;
  double* baro_offset = nullptr;
  S* q_scale = nullptr;
  std::uint32_t* flags = nullptr;
  /// The reports of the aids.
  struct Reports {
    GpsInsAidOut<S> gps, baro, compass, odometer, mag, zupt, zaru, nhc;
  } report;
};

namespace detail {
template <class S, int M>
std::uint32_t gpsins_aid_flag(const UpdateResult<S, M>& r, std::uint32_t used, std::uint32_t rejected) {
  switch (r.status) {
    case Status::Ok: return used;
    case Status::Rejected: return rejected;
    case Status::NotInitialized: return 0u;
    default: return flags::kAidSkipped;
  }
}

/// The flags of one aid update: used / rejected / skipped, and the adaptation's.
template <class S, int M>
std::uint32_t gpsins_update_flags(const GpsInsUpdate<S, M>& r, std::uint32_t used, std::uint32_t rejected) {
  std::uint32_t fl = gpsins_aid_flag(r, used, rejected);
  if (r.decision == GpsInsDecision::Inflated) fl |= flags::kAdapted;
  if (r.decision == GpsInsDecision::Reset) fl |= flags::kGpsReset;
  return fl;
}

/// The time update of batch sample k >= 1: the mean rate w and specific force a over
/// (t[k-1], t[k]] (increments divided by the interval), in m equal steps of dt; a gap longer than
/// max_dt (up to max_coast) is coasted in steps of at most max_dt (m > 1).
template <class S> struct GpsInsSampleStep {
  Vec3<S> w, a;
  long m;
  S dt;
};
template <class S>
GpsInsSampleStep<S> gpsins_sample_step(const GpsInsParams<S>& p, const double* t, const S* gyro, const S* accel,
                                       bool increments, std::size_t k) {
  GpsInsSampleStep<S> u;
  const double step = t[k] - t[k - 1];
  u.w = Eigen::Map<const Vec3<S>>(gyro + 3 * k);
  u.a = Eigen::Map<const Vec3<S>>(accel + 3 * k);
  if (increments) {  // angle and velocity increments over the interval: their means
    u.w /= S(step);
    u.a /= S(step);
  }
  const double max_dt = double(p.max_dt);
  u.m = 1;
  if (step > max_dt && step <= double(p.max_coast) && max_dt > 0.0) u.m = long(std::ceil(step / (max_dt * (1.0 - 1e-9))));
  u.dt = S(step / double(u.m));
  return u;
}

/// Prefill an aid's report: NaN innovations and NIS, NotInitialized, decision None, inflation 1.
template <class S> void gpsins_out_init(const GpsInsAidOut<S>& o, std::size_t rows, int cols, int m) {
  const S nan = std::numeric_limits<S>::quiet_NaN();
  for (std::size_t j = 0; j < rows * std::size_t(cols); ++j) {
    for (int i = 0; i < m && o.innovation; ++i) o.innovation[j * std::size_t(m) + std::size_t(i)] = nan;
    if (o.nis) o.nis[j] = nan;
    if (o.status) o.status[j] = std::uint8_t(Status::NotInitialized);
    if (o.decision) o.decision[j] = std::uint8_t(GpsInsDecision::None);
    if (o.inflation) o.inflation[j] = S(1);
  }
}

/// Write update r as column `col` of row `row` of an aid's report (`cols` updates per row).
template <class S, int M>
void gpsins_out_write(const GpsInsAidOut<S>& o, std::size_t row, int cols, int col, const GpsInsUpdate<S, M>& r) {
  const std::size_t j = row * std::size_t(cols) + std::size_t(col);
  const bool done = r.status == Status::Ok || r.status == Status::Rejected;
  if (o.innovation && done)
    for (int i = 0; i < M; ++i) o.innovation[j * M + std::size_t(i)] = r.innovation[i];
  if (o.nis && done) o.nis[j] = r.nis;
  if (o.status) o.status[j] = std::uint8_t(r.status);
  if (o.decision) o.decision[j] = std::uint8_t(r.decision);
  if (o.inflation) o.inflation[j] = r.inflation;
}
}  // namespace detail

/// Run the filter over the records of `io` (see GpsInsBatchIo). Allocates nothing. Every sample
/// is reported to `obs` (core/checks.hpp's NoBatchObserver; the smoother's record): after the
/// time update of sample k (all its coasting steps), and after all its steps.
template <class S, bool SF, class Observer = NoBatchObserver>
void gpsins_batch(GpsInsFilter<S, SF>& f, const GpsInsBatchIo<S>& io, Observer&& obs = Observer{}) {
  namespace gf = flags;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  detail::gpsins_out_init(io.report.gps, io.ng, 2, 3);
  detail::gpsins_out_init(io.report.baro, io.nb, 2, 1);
  detail::gpsins_out_init(io.report.compass, io.nc, 1, 1);
  detail::gpsins_out_init(io.report.odometer, io.no, 1, 1);
  detail::gpsins_out_init(io.report.mag, io.n, 1, 1);
  detail::gpsins_out_init(io.report.zupt, io.n, 1, 3);
  detail::gpsins_out_init(io.report.zaru, io.n, 1, 3);
  detail::gpsins_out_init(io.report.nhc, io.n, 1, 2);
  if (io.n == 0) return;
  const double t0 = io.t[0];
  const double gps_offset = double(f.params().gps_time_offset);
  auto gps_time = [&](std::size_t i) { return io.gps_t[i] + gps_offset; };
  std::size_t ig = 0, ib = 0, ic = 0, io_ = 0;
  while (ig < io.ng && gps_time(ig) <= t0) ++ig;
  while (ib < io.nb && io.baro_t[ib] <= t0) ++ib;
  while (ic < io.nc && io.compass_t[ic] <= t0) ++ic;
  while (io_ < io.no && io.odo_t[io_] <= t0) ++io_;

  for (std::size_t k = 0; k < io.n; ++k) {
    std::uint32_t fl = 0;
    const bool was_nav = f.navigating();
    const S q_scale0 = f.q_scale();
    if (k > 0) {
      const detail::GpsInsSampleStep<S> u = detail::gpsins_sample_step(f.params(), io.t, io.gyro, io.accel, io.increments, k);
      if (u.m > 1) fl |= gf::kCoasted;
      Status s = Status::Ok;
      for (long j = 0; j < u.m && s == Status::Ok; ++j) s = f.predict(u.w, u.a, u.dt);
      if (s != Status::Ok) fl |= gf::kPredictSkipped | (s == Status::Saturated ? gf::kSaturated : 0u);
      obs.after_predict(k, f);
      const ConstraintResult<S> cr = f.update_constraints();
      detail::gpsins_out_write(io.report.zupt, k, 1, 0, cr.zupt);
      detail::gpsins_out_write(io.report.zaru, k, 1, 0, cr.zaru);
      detail::gpsins_out_write(io.report.nhc, k, 1, 0, cr.nhc);
      if (cr.zupt.status == Status::Ok || cr.zaru.status == Status::Ok || cr.nhc.status == Status::Ok)
        fl |= gf::kConstraintUsed;
      if (io.mag) {
        const Vec3<S> mk = Eigen::Map<const Vec3<S>>(io.mag + 3 * k);
        if (!(std::isnan(mk[0]) && std::isnan(mk[1]) && std::isnan(mk[2]))) {
          const GpsInsUpdate<S, 1> r = f.update_mag(mk);
          detail::gpsins_out_write(io.report.mag, k, 1, 0, r);
          fl |= detail::gpsins_update_flags(r, gf::kHeadingUsed, gf::kMagRejected);
          if (fl & gf::kAidSkipped) fl |= gf::kMagSkipped;
        }
      }
      const double tk = io.t[k];
      for (; ic < io.nc && io.compass_t[ic] <= tk; ++ic) {
        const GpsInsUpdate<S, 1> r = f.update_compass(io.compass_yaw[ic]);
        detail::gpsins_out_write(io.report.compass, ic, 1, 0, r);
        fl |= detail::gpsins_update_flags(r, gf::kHeadingUsed, gf::kHeadingRejected);
      }
      for (; io_ < io.no && io.odo_t[io_] <= tk; ++io_) {
        const GpsInsUpdate<S, 1> r = f.update_odometer(io.odo_speed[io_]);
        detail::gpsins_out_write(io.report.odometer, io_, 1, 0, r);
        fl |= detail::gpsins_update_flags(r, gf::kConstraintUsed, 0u);
      }
      for (; ib < io.nb && io.baro_t[ib] <= tk; ++ib) {
        const BaroResult<S> r = f.update_baro(io.baro_h[ib]);
        detail::gpsins_out_write(io.report.baro, ib, 2, 0, r.height);
        detail::gpsins_out_write(io.report.baro, ib, 2, 1, r.vd);
        fl |= detail::gpsins_update_flags(r.height, gf::kBaroUsed, gf::kBaroRejected);
        fl |= detail::gpsins_update_flags(r.vd, gf::kBaroVdUsed, gf::kBaroVdRejected);
      }
      for (; ig < io.ng && gps_time(ig) <= tk; ++ig) {
        const double* llh = io.gps_llh + 3 * ig;
        if (std::isnan(llh[0]) && std::isnan(llh[1]) && std::isnan(llh[2])) {
          GpsInsUpdate<S, 3> absent;
          absent.status = Status::NonFinite;
          absent.decision = GpsInsDecision::Skipped;
          detail::gpsins_out_write(io.report.gps, ig, 2, 0, absent);
          continue;
        }
        const Vec3<S> vel = io.gps_vel ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_vel + 3 * ig)) : Vec3<S>::Constant(nan);
        const Vec3<S> ps = io.gps_pos_sigma ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_pos_sigma + 3 * ig))
                                            : Vec3<S>::Constant(nan);
        const Vec3<S> vs = io.gps_vel_sigma ? Vec3<S>(Eigen::Map<const Vec3<S>>(io.gps_vel_sigma + 3 * ig))
                                            : Vec3<S>::Constant(nan);
        const GnssSolution kind = io.gps_solution && io.gps_solution[ig] < kGnssSolutions
                                      ? GnssSolution(io.gps_solution[ig])
                                      : GnssSolution::Unknown;
        const GpsResult<S> r = f.update_gps(llh[0], llh[1], llh[2], vel, ps, vs, S(tk - gps_time(ig)), kind);
        detail::gpsins_out_write(io.report.gps, ig, 2, 0, r.pos);
        detail::gpsins_out_write(io.report.gps, ig, 2, 1, r.vel);
        fl |= detail::gpsins_update_flags(r.pos, gf::kGpsPosUsed, gf::kGpsPosRejected);
        fl |= detail::gpsins_update_flags(r.vel, gf::kGpsVelUsed, gf::kGpsVelRejected);
      }
    }
    if (f.at_rest()) fl |= gf::kAtRest;
    switch (f.phase()) {
      case GpsInsPhase::Aligning: fl |= gf::kAligning; break;
      case GpsInsPhase::Levelled: fl |= gf::kLevelled; break;
      case GpsInsPhase::Navigating: fl |= gf::kNavigating; break;
    }
    if (!was_nav && f.navigating()) fl |= gf::kInitialized;
    if (f.q_scale() != q_scale0) fl |= gf::kAdapted;
    const bool nav = f.navigating();
    if (io.llh) {
      const Vec3<double> l = f.llh();
      for (int c = 0; c < 3; ++c) io.llh[3 * k + c] = nav ? l[c] : std::numeric_limits<double>::quiet_NaN();
    }
    if (io.v_n) Eigen::Map<Vec3<S>>(io.v_n + 3 * k) = nav ? f.v_n() : Vec3<S>::Constant(nan);
    if (io.q_nb)
      Eigen::Map<Vec4<S>>(io.q_nb + 4 * k) = f.levelled() ? f.q_nb() : Vec4<S>(Vec4<S>::Constant(nan));
    if (io.acc_bias) Eigen::Map<Vec3<S>>(io.acc_bias + 3 * k) = f.acc_bias();
    if (io.gyro_bias) Eigen::Map<Vec3<S>>(io.gyro_bias + 3 * k) = f.gyro_bias();
    if (io.acc_scale) Eigen::Map<Vec3<S>>(io.acc_scale + 3 * k) = f.acc_scale();
    if (io.gyro_scale) Eigen::Map<Vec3<S>>(io.gyro_scale + 3 * k) = f.gyro_scale();
    constexpr int N = GpsInsFilter<S, SF>::kStates;
    if (io.sigma)
      Eigen::Map<Vec<S, N>>(io.sigma + N * k) =
          nav ? Vec<S, N>(f.covariance().diagonal().cwiseMax(S(0)).cwiseSqrt()) : Vec<S, N>::Constant(nan);
    if (io.baro_offset)
      io.baro_offset[k] = nav && f.state().baro_offset_valid ? f.baro_offset() : std::numeric_limits<double>::quiet_NaN();
    if (io.q_scale) io.q_scale[k] = f.q_scale();
    if (io.flags) io.flags[k] = fl;
    obs.after_sample(k, f);
  }
}

}  // namespace quatnav
