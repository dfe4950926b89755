"""The simulated RTK car (``quatnav.sim.car.car_rtk``): each error source is what its spec says
(the solution kinds and their errors, the receiver's optimistic sigma, the multipath jumps, the
vibration while driving, the IMU's late stamps and lost samples), and the trajectory's car
kinematics (the IMU ahead of the rear axle slips sideways in turns)."""
import numpy as np
import pytest

from quatnav.core import quaternion as quat
from quatnav.sim.car import RtkSpec, car_rtk


@pytest.fixture(scope="module")
def car():
    return car_rtk(seed=3)


def test_solution_kinds_and_their_errors(car):
    g, spec = car.gps, RtkSpec()
    q = g.quality
    assert set(np.unique(q)) == {1, 2, 5}
    assert 0.6 < np.mean(q == 1) < 0.97
    fixed = q == 1
    sd = g.error_n[fixed].std(axis=0)
    np.testing.assert_allclose(sd, [spec.fixed_sigma[0]] * 2 + [spec.fixed_sigma[1]], rtol=0.15)
    # the receiver's sigma: half the true one (optimistic), per kind
    np.testing.assert_allclose(np.median(g.sigma[fixed], axis=0) / sd, spec.reported_ratio, rtol=0.2)
    # float errors wander (correlated over seconds) and are far larger; fixed ones are white
    def lag_corr(e, sel, lag=4):  # 1 s at 4 Hz, within runs of the kind
        ok = sel[:-lag] & sel[lag:]
        return np.corrcoef(e[:-lag][ok, 0], e[lag:][ok, 0])[0, 1]
    assert lag_corr(g.error_n, fixed) < 0.2
    assert lag_corr(g.error_n, q == 2) > 0.6
    assert np.abs(g.error_n[q == 2, :2]).mean() > 5 * np.abs(g.error_n[fixed, :2]).mean()


def test_imu_stamps_late_with_lost_samples(car):
    d = car.imu.t - car.imu_t_true
    delay = car.params["sensor_model"]["imu_delay_s"]
    assert 0.002 <= delay <= 0.012
    assert abs(np.mean(d) - delay) < 2e-5 and 2e-4 < np.std(d) < 4e-4  # 0.3 ms jitter
    lost = 1 - len(car.imu.t) / (round(car.truth.t[-1] * 100) + 1)
    assert 0 < lost < 0.003
    assert np.all(np.diff(car.imu.t) > 0)


def test_vibration_while_driving(car):
    """Sample-to-sample differences of the specific force: far above the white noise while
    cruising (road and engine), and with vibration off the same drive shows the noise only."""
    quiet = car_rtk(seed=3, vibration_on=False)
    t = car.imu.t
    cruise = (t > 200) & (t < 220)  # highway, 25 m/s
    parked = (t > 2) & (t < 18)
    rms = lambda s, m: np.sqrt(np.mean(np.diff(s.imu.accel[m], axis=0) ** 2))  # noqa: E731
    assert rms(car, cruise) > 5 * rms(quiet, (quiet.imu.t > 200) & (quiet.imu.t < 220))
    assert rms(car, cruise) > 2 * rms(car, parked)  # the engine idles at rest; the road adds with speed


def test_imu_ahead_of_the_axle_slips_sideways_in_turns(car):
    tr = car.truth
    v_b = quat.rotate_inv(tr.q_nb, tr.v_n)
    w_z = tr.omega_ib_b[:, 2]
    moving = np.linalg.norm(tr.v_n, axis=1) > 3
    slope = np.polyfit(w_z[moving], v_b[moving, 1], 1)[0]
    np.testing.assert_allclose(slope, 1.2, rtol=0.05)  # imu_ahead_m
