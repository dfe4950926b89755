"""Times on a GPS or Unix clock (about 1.4e9 s, as ROS bags and GNSS receivers give them) in the
float32 filters: the aid timing must be that of the same record on a clock starting at 0. A
float32 time resolves 128 s there, so the times are carried in double whatever the dtype."""
from __future__ import annotations

import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q

EPOCH = 1.4e9  # s: 2014-05-13 on the Unix clock


def _marg(dtype, offset):
    from quatnav.experiments import marg_turn
    from quatnav.sim import make_scenario
    d = marg_turn._inputs(make_scenario("paper001_constant_turn", seed=5))
    f = quatnav.MargFilter(declination=d["declination"], lever_arm_b=d["lever"], gps_acc_tau=0.05, dtype=dtype)
    r = f.run(d["gyr"], d["acc"], d["mag"], t=d["t"] + offset,
              gps_vel=quatnav.Aid(d["gps_t"] + offset, d["gps_vel_n"]))
    return r, d


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_marg_gps_correction_on_an_epoch_clock(dtype):
    r0, d = _marg(dtype, 0.0)
    r1, _ = _marg(dtype, EPOCH)
    used0, used1 = r0.flag("gps_corrected"), r1.flag("gps_corrected")
    assert used0.sum() > 0.5 * len(used0)
    np.testing.assert_array_equal(used1, used0)
    # The antenna acceleration differenced from the fixes: the same within the rounding of
    # 1.4e9 s times in double (2.4e-7 s over 0.05 s fix intervals; measured 5.5e-6 m/s^2 in both
    # dtypes); the attitude within float32 rounding (measured 0.0034 deg).
    both = used0.astype(bool)
    np.testing.assert_allclose(r1.gps_acc_n[both], r0.gps_acc_n[both], atol=1e-4, rtol=0)
    ang = np.degrees(Q.angle_between(r1.quat.astype(float), r0.quat.astype(float)))
    assert ang.max() < 0.01


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("tu", ["ekf", "ukf"])
def test_nav13_aids_on_an_epoch_clock(dtype, tu):
    from quatnav.sim.scenarios import make_scenario
    s = make_scenario("paper002_straight_then_circle", seed=1)
    tr, n = s.truth, 4001  # the first 40 s
    res = {}
    for off in (0.0, EPOCH):
        f = quatnav.NavFilter13(time_update=tu, dtype=dtype)
        f.reset(tr.v_n[0], tr.q_nb[0], lat=tr.lat[0], lon=tr.lon[0], h=tr.h[0])
        res[off] = f.run(s.imu.gyro[1:n], s.imu.accel[1:n], t=s.imu.t[1:n] + off,
                         gps_vel=quatnav.Aid(s.gps.t_valid + off, s.gps.v_n),
                         yaw=quatnav.Aid(s.compass.t + off, s.compass.yaw))
    a, b = res[0.0], res[EPOCH]
    for name in ("gps_vel_used", "heading_used"):
        assert a.flag(name).sum() > 100
        np.testing.assert_array_equal(b.flag(name), a.flag(name))
    np.testing.assert_array_equal(b.aids["gps_vel"].status, a.aids["gps_vel"].status)
    assert np.abs(b.velocity.astype(float) - a.velocity).max() < 1e-3
    assert np.degrees(Q.angle_between(b.quat.astype(float), a.quat.astype(float))).max() < 0.01
