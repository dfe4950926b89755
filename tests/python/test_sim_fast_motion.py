"""Fast-motion segments and scenarios: exact truth (round trip), the physics each one claims."""
import numpy as np
import pytest

from quatnav.core import quaternion as quat
from quatnav.core.strapdown import StrapdownState, strapdown_run
from quatnav.sim import (FAST_MOTION, LimbSwing, Pendulum, Rest, Running, Shaking, Vibration, RandomMotion,
                         list_scenarios, make_scenario, make_trajectory)


def att_err_deg(a, b):
    return np.degrees(np.linalg.norm(quat.to_rotvec(quat.mul(quat.conj(a), b)), axis=-1))


def round_trip(tr):
    s = StrapdownState(tr.q_nb[0], tr.v_n[0], tr.lat[0], tr.lon[0], tr.h[0])
    out = strapdown_run(s, tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt, tr.earth_rate)
    return att_err_deg(out["q_nb"], tr.q_nb[1:]).max(), np.abs(out["v_n"] - tr.v_n[1:]).max()


@pytest.mark.parametrize("seg", [
    Pendulum(12.0, ramp=2.0),
    LimbSwing(12.0, ramp=2.0),
    Running(12.0, ramp=2.0, weave_period=8.0),
    Shaking(12.0, ramp=2.0),
    Vibration(RandomMotion(12.0, seed=1), accel=8.0),
], ids=["pendulum", "limb", "running", "shaking", "vibration"])
def test_segments_round_trip(seg):
    """The noise-free IMU integrated by the strapdown returns the truth: the segments' attitude and
    velocity are consistent, fast as they are."""
    tr = make_trajectory([Rest(1.0), seg, Rest(1.0)], 1000.0, earth_rate=False)
    att, vel = round_trip(tr)
    assert att < 0.01 and vel < 0.01, (att, vel)
    assert np.allclose(tr.v_n[-1], 0, atol=1e-9)  # they end at rest


def test_pendulum_physics():
    """The centripetal acceleration is length * rate^2 along the string: at the bottom of the swing
    the accelerometer reads g plus it, along the string (body z at the start)."""
    L = 0.8
    tr = make_trajectory([Rest(1.0), Pendulum(20.0, length=L, amplitude=0.8, cone=0.0, twist=0.0)], 1000.0,
                         earth_rate=False)
    tilt = np.degrees(np.arccos(np.clip(quat.rotate(tr.q_nb, np.array([0, 0, 1.0]))[:, 2], -1, 1)))
    bottom = (tilt < 0.5) & (tr.t > 8) & (tr.t < 14)
    rate = np.linalg.norm(tr.omega_nb_b[bottom], axis=1)
    f_z = -tr.f_ib_b[bottom, 2]
    np.testing.assert_allclose(f_z, 9.81 + L * rate**2, rtol=0.01)
    assert (L * rate**2).max() > 5.0


def test_running_impacts_and_weave():
    tr = make_trajectory([Rest(1.0), Running(40.0, weave_period=20.0)], 1000.0, earth_rate=False)
    f = np.linalg.norm(tr.f_ib_b, axis=1)
    assert f.max() > 25.0 and f.min() < 7.0  # strikes of 2.5 g and more; less than g between them
    mid = (tr.t > 10) & (tr.t < 30)
    yaw = np.unwrap(tr.rpy[mid, 2])
    assert np.ptp(yaw) > np.radians(100)
    assert np.abs(tr.pos_n[-1, 2]) < 0.2  # the impacts bounce, they do not climb


def test_fast_motion_scenarios():
    assert {n for n, _ in FAST_MOTION} <= set(list_scenarios())
    s = make_scenario("fast_gyro_saturation", seed=0)
    assert s.imu.saturated.any()
    assert np.abs(s.imu.gyro).max() <= np.radians(500.0 + 0.061)  # clipped, then quantized
    s = make_scenario("fast_limb_run", seed=1)
    assert np.degrees(np.linalg.norm(s.truth.omega_ib_b, axis=1)).max() > 400
    assert s.imu.rate_hz == 200.0 and s.params["scoring"]["from_s"] == 5.0
    assert np.array_equal(make_scenario("fast_shaking", seed=0).imu.gyro, make_scenario("fast_shaking", seed=0).imu.gyro)
