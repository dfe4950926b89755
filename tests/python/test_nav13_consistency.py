"""NavFilter13's consistency on paper 002's simulation (straight, then a circle from 100 s), with
the true sensor noise and the filter's defaults: the mean NEES of the 12-dimensional error state
[dv, dtheta, db_a, db_g] of the forward filter and of the smoother, for every time update, lies in
a two-sided 99 % chi-square interval sized to reject a filter 1.5x over- or under-confident.

The Monte Carlo (shared by the forward and the smoothed checks): RUNS seeds of
``paper002_straight_then_circle``, initial errors drawn from the filter's P0, the paper's initial
one-sigma values (roll, pitch 10 deg, yaw 20 deg, velocity 1 ft/s, gyro bias 2 deg/h) except the
accelerometer bias: 200 ug instead of 2000 ug. Why (docs/NAV13.md, "Consistency"): in straight
motion a horizontal accelerometer-bias error db_h is compensated by a tilt error and stays
unobservable, and the second-order term of C(q) (f - b_a) puts |db_h|^2 / (2 g) into the vertical
channel, where it is taken for the vertical bias; with 2000 ug per axis that is 4 ug on average
(up to 12 ug) against a vertical-bias one-sigma of 2-3 ug, a nonlinearity no Gaussian filter
(EKF, second-order mean, UKF) represents. With 200 ug it is 0.04 ug.

The statistic: the mean over runs and checked times (every 10 s from 20 s) of NEES / 12, per time
update, in two windows (before 100 s: straight; from 100 s: the circle). The samples of one run
are correlated (a bias error persists over the whole run), so each run counts as one sample of 12
degrees of freedom (m_eff = 1, the conservative count): RUNS = 25 gives 300 dof, the 99 %
interval [0.81, 1.22], which contains 1.5 x the NEES with probability < 1 % and 1/1.5 x with
probability < 1 % (_consistency.power). Measured (2026-12-05): the means lie within 0.8-1.1;
with QUATNAV_TEST_VARIANCE_SCALE = 1/1.5 and 1.5 (Q, R and P0 scaled) every check fails
(docs/DEVELOPING.md, "Mutations"). About 20 s (the 25 simulations, 0.5 s each, and 75 runs with
their smoothers).
"""
from __future__ import annotations

import numpy as np
import pytest

from _consistency import check_mean_nees, scaled, scaled_covariance

pytest.importorskip("scipy")
pytest.importorskip("quatnav.sim")

from quatnav.core import quaternion as Q  # noqa: E402
from quatnav.experiments import nav13 as X  # noqa: E402
from quatnav.filters.nav13 import initial_covariance  # noqa: E402
from quatnav.sim import scenarios  # noqa: E402

POLICIES = ("ekf", "second_order", "ukf")
RUNS = 25
ACCEL_BIAS_SIGMA = 200e-6 * 9.80665  #: m/s^2, the initial accelerometer-bias one-sigma (see above)
CHECK_EVERY = 1000  #: samples (10 s)
FIRST_CHECK_S = 20.0


def _start(scn, rng):
    """(v_n, q_nb, b_a, b_g, P0): the truth at t[0] plus errors drawn from P0."""
    s = X.initial_sigmas(scn)
    tr = scn.truth
    d_rpy = s["euler"] * rng.standard_normal(3)
    v = tr.v_n[0] + s["vel"] * rng.standard_normal(3)
    ba = scn.imu.accel_bias[0] + ACCEL_BIAS_SIGMA * rng.standard_normal(3)
    bg = scn.imu.gyro_bias[0] + s["gyro_bias"] * rng.standard_normal(3)
    q0 = Q.from_euler(tr.rpy[0] + d_rpy)
    return v, q0, ba, bg, initial_covariance(q0, s["vel"], s["euler"], ACCEL_BIAS_SIGMA, s["gyro_bias"])


def _run(scn, tu, start):
    """The smoothed run (its .forward the causal one) with the true noise and every other parameter
    at its default, Q, R and P0 scaled by the test's variance scale."""
    import quatnav
    from quatnav.filters._base import Aid
    tr, imu = scn.truth, scn.imu
    params = scaled("NavFilter13", time_update=tu, acc_noise=X._density(scn, "accel"),
                    gyro_noise=X._density(scn, "gyro"), gps_vel_sigma=scn.params["gps"]["vel_sigma_m_s"],
                    yaw_sigma=np.radians(scn.params["compass"]["noise_deg"]))
    flt = quatnav.NavFilter13(**params)
    v, q, ba, bg, P0 = start
    flt.reset(v, q, ba, bg, scaled_covariance(P0), lat=tr.lat[0], lon=tr.lon[0], h=tr.h[0])
    # IMU row 0 is the reading at t[0], where the filter starts; row k >= 1 is the mean over (t[k-1], t[k]].
    return flt.run(imu.gyro[1:], imu.accel[1:], t=imu.t[1:], gps_vel=Aid(scn.gps.t_valid, scn.gps.v_n),
                   yaw=Aid(scn.compass.t, scn.compass.yaw), return_covariance=True, smooth=True)


def monte_carlo(runs=RUNS):
    """(policy -> {"forward"|"smoothed": (runs, checks) NEES, "sigma_ratio": (runs,) the largest
    smoothed / forward one-sigma of the error state}, the checked times)."""
    # Every seed has the same trajectory: compute it once (the sensors differ by seed).
    original, cache = scenarios.make_trajectory, {}

    def make_trajectory(*a, **k):
        key = repr((a, sorted(k.items())))
        if key not in cache:
            cache[key] = original(*a, **k)
        return cache[key]

    mp = pytest.MonkeyPatch()
    mp.setattr(scenarios, "make_trajectory", make_trajectory)
    out = {tu: {"forward": [], "smoothed": [], "sigma_ratio": []} for tu in POLICIES}
    try:
        for r in range(runs):
            scn = scenarios.make_scenario(X.SCENARIO, seed=100 + r)
            start = _start(scn, np.random.default_rng([100 + r, 2]))
            for tu in POLICIES:
                res = _run(scn, tu, start)
                sel = slice(CHECK_EVERY - 1, None, CHECK_EVERY)
                # the largest smoothed / forward one-sigma of the error state (velocity, attitude, biases)
                err_cols = np.r_[0:3, 7:13]
                out[tu]["sigma_ratio"].append(max(np.max(res.sigma[:, err_cols] / res.forward.sigma[:, err_cols]),
                                                  np.max(res.att_sigma / res.forward.att_sigma)))
                for kind, rr in (("smoothed", res), ("forward", res.forward)):
                    err = X.errors(scn, rr)
                    sub = type(rr)(**{**rr.__dict__, "x": rr.x[sel], "P": rr.P[sel], "quat": rr.quat[sel]})
                    out[tu][kind].append(X.nees(sub, {"state": err["state"][sel]}))
    finally:
        mp.undo()
    t = scn.imu.t[1:][CHECK_EVERY - 1::CHECK_EVERY]
    return {tu: {k: np.array(v) for k, v in d.items()} for tu, d in out.items()}, t


@pytest.fixture(scope="module")
def nees():
    return monte_carlo()


@pytest.mark.parametrize("kind", ["forward", "smoothed"])
@pytest.mark.parametrize("tu", POLICIES)
def test_nees_within_chi_square_bounds_on_paper002_scenario(nees, tu, kind):
    table, t = nees
    e = table[tu][kind]
    assert e.shape == (RUNS, len(t)) and np.all(np.isfinite(e))
    for name, window in (("straight, 20-100 s", (t >= FIRST_CHECK_S) & (t < 100.0)), ("circle, 100-200 s", t >= 100.0)):
        check_mean_nees(e[:, window], 12, m_eff=1.0, what=f"{tu} {kind} NEES, {name}")


@pytest.mark.parametrize("tu", POLICIES)
def test_smoothed_sigmas_never_above_the_forward_ones(nees, tu):
    """On every run and sample, the smoother's one-sigma of the error state (velocity, attitude,
    biases) is at most the forward filter's (to rounding)."""
    table, _ = nees
    assert np.max(table[tu]["sigma_ratio"]) <= 1 + 1e-9
