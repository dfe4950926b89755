"""GpsInsFilter gate-lockout recovery (found on the real walk, docs/GPSINS_DATA.md): after
``gps_reset_after`` consecutive gate rejections the next rejected GPS position resets the
position to the fix. C++ against the numpy reference through a reset, and the reset's effect."""
import numpy as np
import pytest

import quatnav
from quatnav import reference as R
from quatnav.sim.scenarios import make_scenario

from _aids import as_aids

LEVER = (0.1, 0.0, -0.1)


@pytest.fixture(scope="module")
def jumped():
    """paper-004 walk, first 1500 IMU samples; the GPS positions jump 200 m north from t = 20 s."""
    s = make_scenario("paper004_walk", seed=0)
    n = 1500
    lat = s.gps.lat.copy()
    jump = s.gps.t_valid >= s.imu.t[0] + 20.0
    lat[jump] += 200.0 / 6.36e6
    kw = dict(gps_t=s.gps.t_valid, gps_llh=np.column_stack([lat, s.gps.lon, s.gps.h]), gps_vel=s.gps.v_n,
              baro_t=s.baro.t, baro_h=s.baro.h, compass_t=s.compass.t, compass_yaw=s.compass.yaw)
    return s, n, kw, jump


def test_cpp_matches_reference_through_a_reset(jumped):
    s, n, kw, _ = jumped
    f = quatnav.GpsInsFilter(lever_arm_b=LEVER)
    r = f.run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    ref_f = R.GpsInsFilter(lever_arm_b=LEVER)
    ref = ref_f.run(s.imu.t[:n], s.imu.gyro[:n], s.imu.accel[:n], **kw)
    assert r.counters["gps_pos"]["resets"] == ref_f.counters["gps_pos"]["resets"] >= 1
    assert r.flag("gps_reset").sum() == r.counters["gps_pos"]["resets"] + r.counters["gps_vel"]["resets"]
    nav = r.navigating
    np.testing.assert_allclose(r.position[nav, :2], ref["llh"][nav, :2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.h[nav], ref["llh"][nav, 2], rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.velocity[nav], ref["v_n"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.quat[nav], ref["q_nb"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.sigma[nav], ref["sigma"][nav], rtol=1e-7, atol=1e-12)
    np.testing.assert_array_equal(r.aids["gps_pos"].status_names, ref["gps_status"][:, 0])
    np.testing.assert_array_equal(r.aids["gps_vel"].status_names, ref["gps_status"][:, 1])


def test_reset_follows_the_jump_and_zero_disables_it(jumped):
    s, n, kw, jump = jumped
    t = s.imu.t[:n]
    r1 = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=t, **as_aids(kw))
    r0 = quatnav.GpsInsFilter(lever_arm_b=LEVER, gps_reset_after=0).run(s.imu.gyro[:n], s.imu.accel[:n], t=t,
                                                                        **as_aids(kw))
    used = s.gps.t_valid <= t[-1]
    after = jump & used
    st1, st0 = r1.aids["gps_pos"].status_names[after], r0.aids["gps_pos"].status_names[after]
    # without the reset every fix after the jump is rejected (lockout)
    assert np.all(st0 == "rejected") and r0.counters["gps_pos"]["resets"] == 0
    # with it: gps_reset_after (5) rejections, then a reset, then fixes accepted again
    assert np.all(st1[:6] == "rejected") and np.mean(st1[6:] == "ok") > 0.9
    # the position follows the (jumped) fixes: north offset ~200 m at the end
    i = np.searchsorted(s.truth.t, t[-1])
    dn = (r1.lat[-1] - s.truth.lat[i]) * 6.36e6
    assert abs(dn - 200.0) < 10.0
    # state round trip keeps the reset counters and the rejection run
    f = quatnav.GpsInsFilter(lever_arm_b=LEVER)
    f.run(s.imu.gyro[:1200], s.imu.accel[:1200], t=t[:1200], **as_aids(kw))
    st = f.get_state()
    g = quatnav.GpsInsFilter(lever_arm_b=LEVER)
    g.set_state(st)
    assert g.get_state()["resets"] == st["resets"] and g.counters == f.counters
    assert g.get_state()["gps_pos_reject_run"] == st["gps_pos_reject_run"]
