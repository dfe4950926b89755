// GpsInsFilter's aids (nav/gps_ins/aids.hpp): every piece's H against central finite differences
// of its innovation, perturbing the nominal state through the filter's own injection (the error
// state is estimate minus truth: an error +e is the injection of -e), at a state with a lever
// arm, a rotation rate, a specific force, an age and an altimeter offset; and each piece's H
// zero outside the columns it declares; the rest constraints' R against their documented values.
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

template <class Aid> void check(const Aid& aid, double tol, const GpsInsParams<double>& p = params()) {
  const GpsInsState<double> s = a_state();
  AidMeasurement<double, Aid::M> m;
  aid.measure(s, p, m);
  // Steps large enough that the position, carried as latitude and longitude in double (one ulp
  // of longitude ~1.4e-9 m), moves by many ulps: with 1e-6 rad of attitude the lever arm's
  // displacement (~1e-6 m) was resolved to ~1e-3 and the difference quotient was that far off.
  // The rows are linear in the velocity and bias errors (any step) and smooth in the attitude
  // (the central difference's error is O(eps^2)).
  const double eps[gpsins::kN] = {1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2, 1e-4, 1e-4, 1e-4,
                                  1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2, 1e-3};
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
  // A field with a dip of about 60 deg: the tilt terms of the heading row are large. The full row
  // (mag_heading_only = false) is the exact Jacobian.
  GpsInsParams<double> p = params();
  p.mag_heading_only = false;
  check(gpsins_aid::MagHeading<double>{Vec3<double>(18.0, -9.0, 40.0)}, 1e-5, p);
}

TEST(GpsInsAids, MagnetometerHeadingOnlyMovesItsTiltTermsIntoR) {
  // The default: H has the heading column only; the tilt columns of the exact row, with the
  // tilt covariance, are added to R (so the innovation variance H P H^T + R is the full row's
  // whenever the tilt errors are uncorrelated with the rest).
  GpsInsState<double> s = a_state();
  s.P.setIdentity();
  s.P.block<2, 2>(gpsins::kAtt, gpsins::kAtt) << 1e-4, 2e-5, 2e-5, 3e-4;
  GpsInsParams<double> full = params();
  full.mag_heading_only = false;
  const GpsInsParams<double> p = params();
  ASSERT_TRUE(p.mag_heading_only);
  const gpsins_aid::MagHeading<double> aid{Vec3<double>(18.0, -9.0, 40.0)};
  AidMeasurement<double, 1> mf, mh;
  aid.measure(s, full, mf);
  aid.measure(s, p, mh);
  EXPECT_EQ(mh.y[0], mf.y[0]);
  EXPECT_EQ(mh.H(0, gpsins::kAtt), 0.0);
  EXPECT_EQ(mh.H(0, gpsins::kAtt + 1), 0.0);
  EXPECT_EQ(mh.H(0, gpsins::kAtt + 2), 1.0);
  EXPECT_GT(std::abs(mf.H(0, gpsins::kAtt)) + std::abs(mf.H(0, gpsins::kAtt + 1)), 0.5);  // tan(dip) ~ 1.8
  const Vec2<double> ht = mf.H.block<1, 2>(0, gpsins::kAtt).transpose();
  const double tilt = ht.dot(s.P.block<2, 2>(gpsins::kAtt, gpsins::kAtt) * ht);
  EXPECT_GT(tilt, 0.0);
  EXPECT_NEAR(mh.R(0, 0), mf.R(0, 0) + tilt, 1e-15);
}

TEST(GpsInsAids, ConstraintsMatchFiniteDifferences) {
  check(gpsins_aid::ZeroVelocity<double>{}, 1e-6);
  check(gpsins_aid::ZeroRate<double>{}, 1e-6);
  check(gpsins_aid::NonHolonomic<double>{}, 1e-5);
  check(gpsins_aid::NonHolonomic<double>{0.0, 0.02, -0.015}, 1e-5);  // with a learned mounting
  check(gpsins_aid::OdometerSpeed<double>{12.5}, 1e-5);
}

TEST(GpsInsAids, RestConstraintsNoiseIsTheDocumentedOne) {
  // The finite differences above check H and y, not R: the rest constraints' R against their
  // documented values (aids.hpp): ZUPT zupt_sigma^2 I; ZARU (gyro_noise^2 / dt + zaru_sigma^2) I,
  // dt the last interval. A mis-scaled R (a ZUPT twice as confident, say) fails here.
  const GpsInsState<double> s = a_state();
  GpsInsParams<double> p = params();
  p.zupt_sigma = 0.03;
  p.zaru_sigma = 0.004;
  AidMeasurement<double, 3> z, w;
  gpsins_aid::ZeroVelocity<double>{}.measure(s, p, z);
  gpsins_aid::ZeroRate<double>{}.measure(s, p, w);
  EXPECT_EQ(z.R, Mat3<double>(Mat3<double>::Identity() * (0.03 * 0.03)));
  const double rw = p.gyro_noise * p.gyro_noise / s.dt_last + 0.004 * 0.004;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(w.R(i, j), i == j ? rw : 0.0, 1e-15 * rw) << i << "," << j;
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

// The evidence of a wheeled vehicle (detail::gpsins_nhc_evidence): it accumulates while GNSS-aided
// and fast with no lateral or vertical body velocity, is held while unaided or slow, and is lost
// when the body moves sideways; the constraint's R is then no smaller than what was seen.
TEST(GpsInsAids, NonHolonomicEvidence) {
  GpsInsParams<double> p = params();
  p.nhc_mount_tau_yaw = p.nhc_mount_tau_pitch = 0.0;  // the mounting is not learned (NonHolonomicMounting)
  GpsInsState<double> s = a_state();
  const Vec3<double> fwd_b(10.0, 0.05, -0.02);  // 0.054 m/s across: within the 0.3 m/s limit
  s.nav.v_n = quat::rotate(s.nav.q_nb, fwd_b);
  s.t = 100.0;
  s.gnss_t = 99.5;  // aided
  const double dt = 0.01;
  for (int k = 0; k < 1000; ++k) detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_NEAR(s.nhc_t, 10.0, 1e-9);
  EXPECT_NEAR(s.nhc_ms, 0.05 * 0.05 + 0.02 * 0.02, 1e-12);  // started at the first sample
  s.gnss_t = 90.0;  // unaided (an outage): held
  for (int k = 0; k < 1000; ++k) detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_NEAR(s.nhc_t, 10.0, 1e-9);
  s.gnss_t = 99.5;
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(2.0, 0.0, 0.0));  // slower than nhc_auto_speed: held
  for (int k = 0; k < 1000; ++k) detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_NEAR(s.nhc_t, 10.0, 1e-9);
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(10.0, 0.45, 0.0));  // 0.45 m/s across (a turn): held
  for (int k = 0; k < 3000; ++k) detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_NEAR(s.nhc_ms, 0.45 * 0.45, 1e-3);  // six time constants
  // It accrued until the mean square passed 0.09: (1 - a)^k = (0.2025 - 0.09) / (0.2025 - 0.0029),
  // a = dt / (5 + dt): k = 287 samples, 2.87 s.
  EXPECT_NEAR(s.nhc_t, 12.87, 0.02);
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(8.0, 6.0, 0.0));  // sideways at 6 m/s: lost
  int lost_after = -1;
  for (int k = 0; k < 1000 && lost_after < 0; ++k) {
    detail::gpsins_nhc_evidence(s, p, dt);
    if (s.nhc_t == 0.0) lost_after = k;
  }
  EXPECT_GE(lost_after, 0);
  EXPECT_LT(lost_after, 10);  // the mean square passes 4 x 0.09 m^2/s^2 within a few samples of 36
  p.nhc_auto = false;  // off: nothing moves
  const GpsInsState<double> before = s;
  detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_EQ(s.nhc_t, before.nhc_t);
  EXPECT_EQ(s.nhc_ms, before.nhc_ms);
  // The constraint's R: the larger of nhc_sigma^2 and the evidence's mean square.
  AidMeasurement<double, 2, 16> m;
  gpsins_aid::NonHolonomic<double>{0.25}.measure(s, p, m);
  EXPECT_EQ(m.R(0, 0), 0.25);
  gpsins_aid::NonHolonomic<double>{}.measure(s, p, m);
  EXPECT_EQ(m.R(1, 1), p.nhc_sigma * p.nhc_sigma);
}

// The IMU's mounting (detail::gpsins_nhc_evidence): the mean lateral and vertical body velocity
// per forward speed, learned with nhc_mount_tau_yaw and _pitch while driving straight and held in turns; the
// constraint then measures the velocity across the mounting's direction, not across the IMU's.
TEST(GpsInsAids, NonHolonomicMounting) {
  GpsInsParams<double> p = params();
  p.nhc_mount_tau_yaw = p.nhc_mount_tau_pitch = 10.0;
  GpsInsState<double> s = a_state();
  s.omega_b.setZero();  // straight
  // 0.86 deg in yaw, 1.15 deg in pitch: 0.3 and 0.4 m/s at 20 m/s
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(20.0, 0.3, -0.4));
  s.t = 100.0;
  s.gnss_t = 99.5;  // aided
  const double dt = 0.01;
  for (int k = 0; k < 10000; ++k) detail::gpsins_nhc_evidence(s, p, dt);  // ten time constants
  EXPECT_NEAR(s.nhc_ky, 0.015, 2e-6);
  EXPECT_NEAR(s.nhc_kz, -0.02, 2e-6);
  EXPECT_LT(s.nhc_ms, 1e-3);  // what is left about the mounting: its start from zero, decayed
  EXPECT_GT(s.nhc_t, 80.0);  // a mounting off by a degree is still a wheeled vehicle
  AidMeasurement<double, 2, 16> m;
  gpsins_aid::NonHolonomic<double>{0.0, s.nhc_ky, s.nhc_kz}.measure(s, p, m);
  EXPECT_NEAR(m.y[0], 0.0, 1e-4);
  EXPECT_NEAR(m.y[1], 0.0, 1e-4);
  gpsins_aid::NonHolonomic<double>{}.measure(s, p, m);  // the IMU's own axes: 0.3 and -0.4 m/s
  EXPECT_NEAR(m.y[0], 0.3, 1e-12);
  EXPECT_NEAR(m.y[1], -0.4, 1e-12);
  // In a turn the IMU ahead of the rear axle moves sideways: the mounting is held.
  s.omega_b << 0.0, 0.0, 0.2;
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(20.0, 0.54, -0.4));
  const GpsInsState<double> before = s;
  for (int k = 0; k < 1000; ++k) detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_EQ(s.nhc_ky, before.nhc_ky);
  EXPECT_EQ(s.nhc_kz, before.nhc_kz);
  // Unaided (an outage): held, whatever the INS velocity does.
  s.omega_b.setZero();
  s.gnss_t = 80.0;
  detail::gpsins_nhc_evidence(s, p, dt);
  EXPECT_EQ(s.nhc_ky, before.nhc_ky);
}

// Without `lateral` the constraint's lateral row carries nothing (zero residual and H); the
// vertical row is the full constraint's.
TEST(GpsInsAids, NonHolonomicWithoutTheLateralRow) {
  const GpsInsParams<double> p = params();
  const GpsInsState<double> s = a_state();
  AidMeasurement<double, 2, 16> full, vert;
  gpsins_aid::NonHolonomic<double>{0.0, 0.02, -0.015}.measure(s, p, full);
  gpsins_aid::NonHolonomic<double>{0.0, 0.02, -0.015, false}.measure(s, p, vert);
  EXPECT_NE(full.y[0], 0.0);
  EXPECT_EQ(vert.y[0], 0.0);
  EXPECT_TRUE(vert.H.row(0).isZero(0.0));
  EXPECT_EQ(vert.y[1], full.y[1]);
  EXPECT_TRUE(vert.H.row(1) == full.H.row(1));
  EXPECT_TRUE(vert.R == full.R);
}

// nhc_arm: in a turn the IMU a distance L from the non-slipping axle moves sideways at w_z L, so
// the lateral row's variance gains (w_z L)^2 (here 0.25 rad/s and 1.5 m: 0.14 m^2/s^2 against
// nhc_sigma^2's 0.01); the vertical row, the residual and H stay as they are, and 0 is off.
TEST(GpsInsAids, NonHolonomicLateralVarianceGrowsWithTheYawRate) {
  GpsInsParams<double> p = params();
  GpsInsState<double> s = a_state();
  s.omega_b << 0.03, -0.02, 0.25;
  AidMeasurement<double, 2, 16> off, arm;
  gpsins_aid::NonHolonomic<double>{}.measure(s, p, off);
  EXPECT_EQ(off.R(0, 0), p.nhc_sigma * p.nhc_sigma);  // the default: off
  p.nhc_arm = 1.5;
  gpsins_aid::NonHolonomic<double>{}.measure(s, p, arm);
  EXPECT_NEAR(arm.R(0, 0), 0.01 + 0.375 * 0.375, 1e-15);
  EXPECT_EQ(arm.R(1, 1), off.R(1, 1));
  EXPECT_EQ(arm.R(0, 1), 0.0);
  EXPECT_TRUE(arm.y == off.y);
  EXPECT_TRUE(arm.H == off.H);
  s.omega_b[2] = -0.25;  // either way round
  gpsins_aid::NonHolonomic<double>{0.02}.measure(s, p, arm);
  EXPECT_NEAR(arm.R(0, 0), 0.02 + 0.375 * 0.375, 1e-15);
  EXPECT_EQ(arm.R(1, 1), 0.02);
}

// nhc_lever_b: the constraint holds the velocity at the non-slipping point. An IMU 1.2 m ahead of
// the rear axle turning at 0.25 rad/s moves sideways at 0.3 m/s while the axle does not: the
// residual is zero there (0.3 m/s at the IMU), H is unchanged (the bias term is left out).
TEST(GpsInsAids, NonHolonomicAtTheAxle) {
  GpsInsParams<double> p = params();
  GpsInsState<double> s = a_state();
  s.omega_b << 0.0, 0.0, 0.25;
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(10.0, 0.3, 0.0));
  AidMeasurement<double, 2, 16> imu, axle;
  gpsins_aid::NonHolonomic<double>{}.measure(s, p, imu);
  EXPECT_NEAR(imu.y[0], 0.3, 1e-12);
  p.nhc_lever_b << -1.2, 0.0, 0.0;
  gpsins_aid::NonHolonomic<double>{}.measure(s, p, axle);
  EXPECT_NEAR(axle.y[0], 0.0, 1e-12);
  EXPECT_NEAR(axle.y[1], imu.y[1], 1e-12);
  EXPECT_TRUE(axle.H == imu.H);
  // the evidence of a wheeled vehicle is taken at the axle too: no lateral mean square in the turn
  s.t = 100.0;
  s.gnss_t = 99.5;
  detail::gpsins_nhc_evidence(s, p, 0.01);
  EXPECT_NEAR(s.nhc_ms, 0.0, 1e-20);
  p.nhc_lever_b.setZero();
  s.nhc_ms = -1.0;
  detail::gpsins_nhc_evidence(s, p, 0.01);
  EXPECT_NEAR(s.nhc_ms, 0.09, 1e-12);
}

// The learned constraint (nhc_auto) leaves its lateral row out while GNSS-aided (an accepted fix
// within 2.5 s: the heading is the GNSS's, and the mounting's yaw is learned from it) and applies
// it in an outage; nhc_lateral_aided and the forced constraint (nhc) apply it always.
TEST(GpsInsAids, LearnedNonHolonomicLateralRowOnlyInAnOutage) {
  GpsInsState<double> s = a_state();
  s.nav.v_n = quat::rotate(s.nav.q_nb, Vec3<double>(20.0, 0.05, 0.02));
  s.P = decltype(s.P)::Identity() * 1e-4;
  s.t = 100.0;
  s.pseudo_t = 0.0;
  s.nhc_t = 100.0;  // the evidence of a wheeled vehicle is in
  s.rest_v = s.nav.v_n;
  auto lateral_innovation = [&](const GpsInsParams<double>& p, double gnss_t) {
    GpsInsState<double> st = s;
    st.gnss_t = gnss_t;
    GpsInsFilter<double> f(p);
    EXPECT_EQ(f.set_state(st), Status::Ok);
    const auto r = f.update_constraints();
    EXPECT_EQ(r.nhc.status, Status::Ok);
    return r.nhc.innovation[0];
  };
  GpsInsParams<double> p = params();
  EXPECT_EQ(lateral_innovation(p, 98.0), 0.0);  // aided 2 s ago: left out
  EXPECT_NEAR(lateral_innovation(p, 97.0), 0.05, 1e-9);  // 3 s without GNSS: applied (the lateral 0.05 m/s)
  p.nhc_lateral_aided = true;
  EXPECT_NEAR(lateral_innovation(p, 98.0), 0.05, 1e-9);
  p.nhc_lateral_aided = false;
  p.nhc = true;
  EXPECT_NEAR(lateral_innovation(p, 98.0), 0.05, 1e-9);
}
