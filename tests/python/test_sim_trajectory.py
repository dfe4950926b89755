"""Trajectory truth and the simulator/strapdown round trip."""
import numpy as np
import pytest

from quatnav.core import earth
from quatnav.core import quaternion as quat
from quatnav.sim import (Accelerate, Climb, CoordinatedTurn, Cruise, RandomMotion, Rest, Rotate,
                         Turn, WaypointPath, make_trajectory, trajectory_from_waypoints)
from quatnav.core.strapdown import StrapdownState, strapdown_run, strapdown_step


def att_err_deg(a, b):
    return np.degrees(np.linalg.norm(quat.to_rotvec(quat.mul(quat.conj(a), b)), axis=-1))


def round_trip(tr, earth_rotation=None):
    er = tr.earth_rate if earth_rotation is None else earth_rotation
    s = StrapdownState(tr.q_nb[0], tr.v_n[0], tr.lat[0], tr.lon[0], tr.h[0])
    out = strapdown_run(s, tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt, er)
    pos = earth.geodetic_to_ned(out["lat"], out["lon"], out["h"], tr.lat[0], tr.lon[0], tr.h[0])
    return (np.linalg.norm(pos - tr.pos_n[1:], axis=1).max(),
            att_err_deg(out["q_nb"], tr.q_nb[1:]).max(), out)


@pytest.fixture(scope="module")
def straight_circle():
    return make_trajectory([Cruise(100.0), Turn(100.0, rate=0.1, ramp=1.0)], 100.0, speed0=2.0,
                           rpy0=(0.0, 0.0, 0.5))


def test_round_trip_200s_100hz(straight_circle):
    """Noise-free IMU integrated by the strapdown returns the trajectory (200 s, 100 Hz)."""
    pos, att, out = round_trip(straight_circle)
    assert np.all(out["status"] == "ok")
    assert pos < 0.5 and att < 0.01
    assert pos < 1e-3 and att < 1e-5  # what the scheme actually achieves


def test_round_trip_aircraft_and_turntable():
    tr = make_trajectory([Cruise(10), CoordinatedTurn(30, rate=0.1, ramp=3), Climb(30, 0.15),
                          Accelerate(10, delta_speed=5), CoordinatedTurn(30, angle=-2.0, ramp=3),
                          Cruise(90)], 100.0, speed0=30.0)
    assert tr.t[-1] == pytest.approx(200.0)
    pos, att, _ = round_trip(tr)
    assert pos < 0.5 and att < 0.01
    tt = make_trajectory([Rest(5), Rotate("roll", 10, rate=0.5), Rotate("pitch", 10, angle=-1.0),
                          Rotate([1, 1, 1], 10, angle=2.0), Rest(5)], 100.0, earth_rate=False)
    pos, att, _ = round_trip(tt)
    assert pos < 0.01 and att < 1e-4


def test_truth_consistency(straight_circle):
    tr = straight_circle
    # circle of radius speed/rate
    k = (tr.t > 110) & (tr.t < 198.5)
    assert np.allclose(np.linalg.norm(tr.v_n[k], axis=1), 2.0, atol=1e-9)
    assert np.allclose(tr.omega_nb_b[k, 2], 0.1, atol=1e-9)
    # specific force of a level vehicle: about -g along body z plus the centripetal term
    g = earth.gravity(tr.lat, tr.h)
    assert np.allclose(tr.f_ib_b[k, 2], -g[k], atol=1e-3)
    assert np.allclose(tr.f_ib_b[k, 1], 0.2, atol=1e-3)  # v * r
    # Earth rate is seen by the gyros at rest/cruise
    assert np.linalg.norm(tr.omega_ib_b[10]) == pytest.approx(earth.OMEGA_IE, rel=1e-2)
    # increments are the integrals of the instantaneous values
    assert np.allclose(tr.dtheta_b[1:] / tr.dt, 0.5 * (tr.omega_ib_b[1:] + tr.omega_ib_b[:-1]),
                       atol=1e-5)  # trapezoid vs Simpson: dt^2/12 * max |omega''|
    assert np.allclose(quat.to_euler(tr.q_nb), tr.rpy)
    # local NED position follows the velocity
    assert np.allclose(np.gradient(tr.pos_n[:, 0], tr.dt)[5:-5], tr.v_n[5:-5, 0], atol=1e-3)


def test_angular_acceleration():
    tr = make_trajectory([Rest(1.0), Rotate("yaw", 4.0, rate=1.0, ramp=1.0)], 200.0,
                         earth_rate=False)
    num = np.gradient(tr.omega_nb_b[:, 2], tr.dt)
    assert np.allclose(tr.alpha_nb_b[5:-5, 2], num[5:-5], atol=2e-2)
    assert np.max(np.abs(tr.alpha_nb_b[:, 2])) == pytest.approx(np.pi / 2, rel=1e-3)


def test_waypoints_pass_through_points():
    pts = np.array([[30.0, 0.0], [50.0, 20.0], [50.0, 60.0]])
    tr = trajectory_from_waypoints(pts, 1.5, 50.0, rest=2.0, accel_time=2.0)
    for p in pts:
        assert np.min(np.linalg.norm(tr.pos_n[:, :2] - p, axis=1)) < 0.05
    speed = np.linalg.norm(tr.v_n, axis=1)
    on_path = (tr.t > 4.0) & (tr.t < tr.t[-1] - 4.0)
    assert np.median(speed[on_path]) == pytest.approx(1.5, abs=0.05)
    assert np.max(np.abs(speed[on_path] - 1.5)) < 0.4
    pos, att, _ = round_trip(tr)
    assert pos < 0.01 and att < 1e-3


def test_random_motion_reproducible_and_round_trip():
    seg = RandomMotion(20.0, translation=0.05, seed=7)
    a = make_trajectory([Rest(1.0), seg], 200.0, earth_rate=False)
    b = make_trajectory([Rest(1.0), RandomMotion(20.0, translation=0.05, seed=7)], 200.0,
                        earth_rate=False)
    c = make_trajectory([Rest(1.0), RandomMotion(20.0, translation=0.05, seed=8)], 200.0,
                        earth_rate=False)
    assert np.array_equal(a.q_nb, b.q_nb) and not np.allclose(a.q_nb, c.q_nb)
    assert np.allclose(a.pos_n[-1], 0.0, atol=1e-6)
    pos, att, _ = round_trip(a)
    assert pos < 0.05 and att < 1e-3


@pytest.mark.parametrize("make, name", [
    (lambda: Turn(10.0, rate=0.1, ramp=6.0), "ramp"),
    (lambda: Turn(10.0, rate=0.1, ramp=0.0), "ramp"),
    (lambda: Turn(-1.0, rate=0.1), "duration"),
    (lambda: Turn(10.0), "rate"),
    (lambda: Accelerate(5.0), "to_speed"),
    (lambda: Accelerate(5.0, to_speed=-1.0), "to_speed"),
    (lambda: Climb(10.0, angle=np.radians(85)), "angle"),
    (lambda: Rotate("sideways", 5.0, rate=1.0), "axis"),
    (lambda: Rotate([0, 0, 0], 5.0, rate=1.0), "axis"),
    (lambda: WaypointPath([[1.0, 2.0, 3.0, 4.0]], 1.0), "points_n"),
    (lambda: WaypointPath([[10.0, 0.0]], 0.0), "speed"),
    (lambda: RandomMotion(10.0, amplitude=(1.0, 2.0)), "amplitude"),
])
def test_bad_segment_parameters(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_bad_trajectory_parameters():
    with pytest.raises(ValueError, match="rate_hz"):
        make_trajectory([Rest(1.0)], 0.0)
    with pytest.raises(ValueError, match="lat0"):
        make_trajectory([Rest(1.0)], 10.0, lat0=np.radians(90.0))
    with pytest.raises(ValueError, match="Rest"):
        make_trajectory([Rest(1.0)], 10.0, speed0=1.0)
    with pytest.raises(ValueError, match="CoordinatedTurn"):
        make_trajectory([CoordinatedTurn(5.0, rate=0.1)], 10.0)
    with pytest.raises(ValueError, match="segments"):
        make_trajectory([], 10.0)


def test_strapdown_step_rejects_bad_input():
    s = StrapdownState(quat.identity(), np.zeros(3), 0.6, 2.2, 10.0)
    before = s.copy()
    assert strapdown_step(s, [np.nan, 0, 0], [0, 0, -9.8], 0.01) == "non_finite"
    assert strapdown_step(s, [0, 0, 0], [0, 0, -9.8], 0.0) == "invalid_dt"
    assert strapdown_step(s, [0, 0, 0], [0, 0, -9.8], -0.01) == "invalid_dt"
    assert strapdown_step(s, [0, 0, 0], [0, 0, np.inf], 0.01) == "non_finite"
    for f in ("q_nb", "v_n", "dtheta_prev", "dv_prev"):
        assert np.array_equal(getattr(s, f), getattr(before, f))
    assert (s.lat, s.lon, s.h, s.has_prev) == (before.lat, before.lon, before.h, before.has_prev)
    with pytest.raises(ValueError, match="omega_ib_b"):
        strapdown_run(s, np.zeros((5, 2)), np.zeros((5, 3)), 0.01)
