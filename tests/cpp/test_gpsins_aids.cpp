// GpsInsFilter's aids (nav/gps_ins/aids.hpp): every piece's H against central finite differences
// of its innovation, perturbing the nominal state through the filter's own injection (the error
// state is estimate minus truth: an error +e is the injection of -e), at a state with a lever
// arm, a rotation rate, a specific force, an age and an altimeter offset; and each piece's H
// zero outside the columns it declares.
#include <gtest/gtest.h>

#include <cmath>
#include <quatnav/nav/gps_ins.hpp>

using namespace quatnav;

namespace {

GpsInsState<double> a_state() {
  GpsInsState<double> s;
  s.nav.q_nb = quat::from_euler(0.2, -0.3, 1.1);
  s.nav.v_n = Vec3<double>(12.0, -5.0, 0.8);
  s.nav.lat = 0.7;
  s.nav.lon = -1.2;
  s.nav.h = 350.0;
  s.acc_bias = Vec3<double>(0.05, -0.02, 0.03);
  s.gyro_bias = Vec3<double>(1e-3, -2e-3, 5e-4);
  s.omega_b = Vec3<double>(0.3, -0.2, 0.5);
  s.f_b = Vec3<double>(1.2, 0.4, -9.7);
  s.baro_offset = 3.5;
  s.baro_offset_valid = true;
  s.phase = GpsInsPhase::Navigating;
  s.dt_last = 0.01;
  return s;
}

GpsInsParams<double> params() {
  GpsInsParams<double> p;
  p.lever_arm_b = Vec3<double>(0.8, -0.3, -1.1);
  return p;
}

// The state with error e added: the injection of -e (and the last rate and specific force,
// which are the measured ones less the bias estimates, moved with the bias errors).
GpsInsState<double> with_error(const GpsInsState<double>& s, const Vec<double, gpsins::kN>& e) {
  GpsInsState<double> t = s;
  detail::gpsins_inject(t, Vec<double, gpsins::kN>(-e));
  t.f_b = s.f_b - e.segment<3>(gpsins::kBa);
  t.omega_b = s.omega_b - e.segment<3>(gpsins::kBg);
  return t;
}

template <class Aid> void check(const Aid& aid, double tol) {
  const GpsInsState<double> s = a_state();
  const GpsInsParams<double> p = params();
  AidMeasurement<double, Aid::M> m;
  aid.measure(s, p, m);
  const double eps[gpsins::kN] = {1e-3, 1e-3, 1e-3, 1e-4, 1e-4, 1e-4, 1e-6, 1e-6, 1e-6,
                                  1e-5, 1e-5, 1e-5, 1e-6, 1e-6, 1e-6, 1e-3};
  for (int i = 0; i < gpsins::kN; ++i) {
    Vec<double, gpsins::kN> e = Vec<double, gpsins::kN>::Zero();
    e[i] = eps[i];
    AidMeasurement<double, Aid::M> mp, mm;
    aid.measure(with_error(s, e), p, mp);
    aid.measure(with_error(s, -e), p, mm);
    const Vec<double, Aid::M> fd = (mp.y - mm.y) / (2.0 * eps[i]);
    const double scale = 1.0 + m.H.col(i).cwiseAbs().maxCoeff();
    EXPECT_LE((fd - m.H.col(i)).cwiseAbs().maxCoeff(), tol * scale)
        << "aid kind " << int(Aid::kind) << " column " << i << "\nfd " << fd.transpose() << "\nH  "
        << m.H.col(i).transpose();
    if (i < Aid::C0 || i >= Aid::C0 + Aid::NC) { EXPECT_EQ(m.H.col(i).cwiseAbs().maxCoeff(), 0.0) << i; }
  }
}

}  // namespace

TEST(GpsInsAids, GpsPositionMatchesFiniteDifferences) {
  const GpsInsState<double> s = a_state();
  double lat = s.nav.lat + 3.0 / 6.37e6, lon = s.nav.lon, h = s.nav.h - 2.0;
  check(gpsins_aid::GpsPosition<double>{lat, lon, h, Vec3<double>(0.5, 0.5, 1.0), 0.08}, 1e-5);
}

TEST(GpsInsAids, GpsVelocityMatchesFiniteDifferences) {
  check(gpsins_aid::GpsVelocity<double>{Vec3<double>(11.0, -4.0, 1.0), Vec3<double>(0.1, 0.1, 0.1), 0.08}, 1e-5);
}

TEST(GpsInsAids, AltimeterMatchesFiniteDifferences) {
  check(gpsins_aid::BaroHeight<double>{352.0}, 1e-6);
  check(gpsins_aid::BaroVerticalVelocity<double>{352.0, 351.0, 1.5}, 1e-6);
}

TEST(GpsInsAids, CompassMatchesFiniteDifferences) { check(gpsins_aid::CompassHeading<double>{1.0}, 1e-5); }

TEST(GpsInsAids, MagnetometerMatchesFiniteDifferences) {
  // A field with a dip of about 60 deg: the tilt terms of the heading row are large.
  check(gpsins_aid::MagHeading<double>{Vec3<double>(18.0, -9.0, 40.0)}, 1e-5);
}

TEST(GpsInsAids, ConstraintsMatchFiniteDifferences) {
  check(gpsins_aid::ZeroVelocity<double>{}, 1e-6);
  check(gpsins_aid::ZeroRate<double>{}, 1e-6);
  check(gpsins_aid::NonHolonomic<double>{}, 1e-5);
  check(gpsins_aid::OdometerSpeed<double>{12.5}, 1e-5);
}

TEST(GpsInsAids, TheCheckDetectsAnError) {
  // The finite differences see the age terms of the position row: without them H is wrong.
  const GpsInsState<double> s = a_state();
  const GpsInsParams<double> p = params();
  const gpsins_aid::GpsPosition<double> aid{s.nav.lat, s.nav.lon, s.nav.h, Vec3<double>::Ones(), 0.5};
  AidMeasurement<double, 3> m;
  aid.measure(s, p, m);
  Vec<double, gpsins::kN> e = Vec<double, gpsins::kN>::Zero();
  e[gpsins::kVel] = 1e-4;
  AidMeasurement<double, 3> mp, mm;
  aid.measure(with_error(s, e), p, mp);
  aid.measure(with_error(s, -e), p, mm);
  const Vec3<double> fd = (mp.y - mm.y) / 2e-4;
  EXPECT_NEAR(fd[0], -0.5, 1e-6);
  EXPECT_NEAR(m.H(0, gpsins::kVel), -0.5, 1e-12);
}
