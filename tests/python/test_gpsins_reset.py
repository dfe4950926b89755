"""GpsInsFilter's one gated path for the GNSS aids: C++ against the numpy reference through an
outlier, an inflation and a reset; a jump of the fixes followed by a reset and accepted fixes; the
plain gate (``inflate_after=0``) locking out; an over-confident configuration (noise densities ten
times too small) recovering through the adaptation instead of rejecting its fixes."""
import numpy as np
import pytest

import quatnav
from quatnav import reference as R
from quatnav.sim.scenarios import make_scenario

from _aids import as_aids

LEVER = (0.1, 0.0, -0.1)


def _kw(s, lat):
    return dict(gps_t=s.gps.t_valid, gps_llh=np.column_stack([lat, s.gps.lon, s.gps.h]), gps_vel=s.gps.v_n,
                baro_t=s.baro.t, baro_h=s.baro.h, compass_t=s.compass.t, compass_yaw=s.compass.yaw)


@pytest.fixture(scope="module")
def walk():
    return make_scenario("paper004_walk", seed=0)


@pytest.fixture(scope="module")
def jumped(walk):
    """paper-004 walk, first 1500 IMU samples; one outlier fix (50 m) at 14 s, and from 20 s on
    the GPS positions jump 200 m north."""
    s, n = walk, 1500
    lat = s.gps.lat.copy()
    t = s.gps.t_valid - s.imu.t[0]
    outlier = int(np.argmax(t >= 14.0))
    lat[outlier] += 50.0 / 6.36e6
    jump = t >= 20.0
    lat[jump] += 200.0 / 6.36e6
    return s, n, _kw(s, lat), jump, outlier


def test_cpp_matches_reference_through_outlier_and_reset(jumped):
    s, n, kw, _, _ = jumped
    r = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    ref_f = R.GpsInsFilter(lever_arm_b=LEVER)
    ref = ref_f.run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    assert r.counters == ref_f.counters
    assert r.counters["gps_pos"]["resets"] >= 1 and r.counters["gps_pos"]["rejected"] >= 2
    assert r.flag("gps_reset").sum() == r.counters["gps_pos"]["resets"] + r.counters["gps_vel"]["resets"]
    nav = r.navigating
    np.testing.assert_allclose(r.position[nav, :2], ref["llh"][nav, :2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.h[nav], ref["llh"][nav, 2], rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.velocity[nav], ref["v_n"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.quat[nav], ref["q_nb"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.sigma[nav], ref["sigma"][nav], rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(r.q_scale, ref["q_scale"], rtol=1e-9)
    for c, name in enumerate(("gps_pos", "gps_vel")):
        a = r.aids[name]
        np.testing.assert_array_equal(a.status_names, ref["gps"]["status"][:, c])
        np.testing.assert_array_equal(a.decision_names, ref["gps"]["decision"][:, c])
        np.testing.assert_allclose(a.nis, ref["gps"]["nis"][:, c], rtol=1e-7)
        np.testing.assert_allclose(a.inflation, ref["gps"]["inflation"][:, c], rtol=1e-6)


def test_outlier_isolated_jump_reset_and_plain_gate_locks_out(jumped):
    s, n, kw, jump, outlier = jumped
    t = s.imu.t[:n]
    r1 = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=t, **as_aids(kw))
    r0 = quatnav.GpsInsFilter(lever_arm_b=LEVER, inflate_after=0).run(s.imu.gyro[:n], s.imu.accel[:n], t=t,
                                                                      **as_aids(kw))
    d1 = r1.aids["gps_pos"].decision_names
    # the outlier alone is rejected, its neighbours accepted
    assert d1[outlier] == "rejected" and d1[outlier - 1] == "accepted" and d1[outlier + 1] == "accepted"
    used = s.gps.t_valid <= t[-1]
    after = np.flatnonzero(jump & used)
    # the jump: one rejection, then the reset (200 m is beyond inflate_max), then the fixes are used
    assert list(d1[after[:2]]) == ["rejected", "reset"]
    assert np.mean(np.isin(d1[after[2:]], ("accepted", "inflated"))) > 0.9
    i = np.searchsorted(s.truth.t, t[-1])
    assert abs((r1.lat[-1] - s.truth.lat[i]) * 6.36e6 - 200.0) < 10.0
    # the plain gate rejects every fix after the jump (lockout)
    assert np.all(r0.aids["gps_pos"].decision_names[after] == "rejected")


def test_state_round_trip_keeps_the_adaptation_and_the_rejection_run(jumped):
    s, n, kw, _, _ = jumped
    f = quatnav.GpsInsFilter(lever_arm_b=LEVER)
    f.run(s.imu.gyro[:1200], s.imu.accel[:1200], t=s.imu.t[:1200], **as_aids(kw))
    st = f.get_state()
    g = quatnav.GpsInsFilter(lever_arm_b=LEVER)
    g.set_state(st)
    assert g.counters == f.counters and g.q_scale == f.q_scale
    np.testing.assert_array_equal(g.get_state()["reject_run"], st["reject_run"])


@pytest.fixture(scope="module")
def car():
    return make_scenario("paper001_constant_turn", seed=0)


def _car_run(s, factor, **extra):
    g = s.gps
    k = len(g.t_valid)
    aids = dict(gps_pos=quatnav.Aid(g.t_valid, np.column_stack([g.lat, g.lon, g.h]), np.tile((0.01, 0.01, 0.02), (k, 1))),
                gps_vel=quatnav.Aid(g.t_valid, g.v_n, np.full((k, 3), 0.02)))
    # the simulated IMU's noise densities (0.03 deg/s/sqrt(Hz), 150 ug/sqrt(Hz)) times factor
    noise = dict(gyro_noise=np.radians(0.03), acc_noise=150e-6 * 9.81, gyro_bias_noise=1e-5, acc_bias_noise=1e-4)
    f = quatnav.GpsInsFilter(lever_arm_b=tuple(s.params["gps"]["lever_arm_b_m"]),
                             **{k_: v * factor for k_, v in noise.items()}, **extra)
    r = f.run(s.imu.gyro, s.imu.accel, t=s.imu.t, **aids)
    nav = r.navigating
    i = np.searchsorted(s.truth.t, r.t[nav])
    dn = (r.lat[nav] - s.truth.lat[i]) * 6.36e6
    de = (r.lon[nav] - s.truth.lon[i]) * 6.38e6 * np.cos(s.truth.lat[i])
    used = r.aids["gps_pos"].decision != 0
    rejected = max(np.mean(r.aids[a].decision_names[used] == "rejected") for a in ("gps_pos", "gps_vel"))
    return r, rejected, float(np.sqrt(np.mean(dn ** 2 + de ** 2)))


@pytest.mark.parametrize("factor", [1.0, 0.1, 0.01])
def test_over_confident_noise_recovers(car, factor):
    """The simulated car with RTK fixes (1 cm, 20 Hz) and the IMU noise densities given 1, 10 and
    100 times too small: with the adaptation and the inflation no more than a few percent of the
    (correct) fixes are rejected and the error stays at the centimetre level; the plain gate
    (no adaptation, no inflation) locks out of its own fixes at 100 times."""
    r, rejected, rms = _car_run(car, factor)
    assert rejected < 0.03, rejected
    assert rms < 0.05, rms
    if factor == 0.01:
        assert r.q_scale.max() > 10.0
        _, rejected0, rms0 = _car_run(car, factor, adapt_q_max=1.0, inflate_after=0)
        assert rejected0 > 0.3 and rms0 > 1.0, (rejected0, rms0)


@pytest.fixture(scope="module")
def rtk_car():
    from quatnav.sim.car import car_rtk
    return car_rtk(seed=15)


def test_inflation_leaves_the_heading_alone(rtk_car):
    """The simulated RTK car (its receiver reports half the true vertical error, so RTK-fixed fixes
    fail the gate on their height now and then): an inflation opens the position and velocity
    block only. Inflating the attitude with them turned a vertical misfit into a heading sigma of
    tens of degrees on a straight highway, where the fixes then walked the heading through the
    lever arm: 39 deg off at the start of a 30 s outage in a curve, 167 m of drift. Every
    inflated update leaves the attitude sigma where it was, and the heading at the start of
    every outage is within a few degrees. The noise as given and the down floor the north and east
    one (``gps_vertical_floor_ratio = 1``), and the weighting off (``gps_robust_k = 0``): the log's
    accelerometer noise, the default's larger down floor and the weighted gate let nearly every such
    fix through, and this test is about those that fail it."""
    from quatnav.experiments import gpsins_car as gc
    s = rtk_car
    outages = s.params["events"]["outages_30"]
    r = quatnav.GpsInsFilter(**gc.filter_params(s, base=dict(gps_time_sigma=0.02, gps_vertical_floor_ratio=1.0,
                                                                   gps_robust_k=0.0),
                                                 noise_from_log=False)).run(
        s.imu.gyro, s.imu.accel, t=s.imu.t, outages=outages, **gc.aids(s))
    g = r.aids["gps_pos"]
    inflated = np.flatnonzero(g.decision_names == "inflated")
    assert len(inflated) > 5  # the case this test is about
    k = np.searchsorted(r.t, g.t[inflated])
    grown = r.sigma[k, 6:9] / r.sigma[k - 1, 6:9]
    assert grown.max() < 1.01, grown.max()
    e = gc.errors(s, r)
    for a, _ in outages:
        j = int(np.searchsorted(r.t, a))
        assert abs(np.degrees(e["yaw"][j])) < 5.0, (a, np.degrees(e["yaw"][j]))
