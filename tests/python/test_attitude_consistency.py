"""The attitude filters' consistency: the mean NEES of [dtheta, db] (6 dof) of QuaternionEKF (the
paper's 7-state form and the default error-state form without its robustness parts), EulerEKF and
the smoothed QuaternionEKF (its normalized errors squared against the marginal sigmas), on
simulated rotations with the true noise, in a two-sided 99 %
chi-square interval sized to reject a filter 1.5x over- or under-confident (_consistency.py).

The data: ``quatnav.demo.rotation_scenario`` (gyro white noise 0.005 rad/s per sample, accelerometer
0.05 m/s^2, magnetometer 0.5 uT of 50 uT) plus a gyro-bias random walk of the density the filter is
told; initial errors drawn from the filter's P0. The statistic: the mean over RUNS runs and the
checked samples (every 100th after 5 s of 20 s) of NEES / 6. A run's samples are correlated (the
bias error persists), so each run counts as M_EFF independent samples, 80 % of the measured
(``python -c "import test_attitude_consistency as T; T.measure_meff()"`` in tests/python: the
per-run means of 200 runs vary as 2.4 independent 6-dof samples would for each forward filter,
their means 1.048, 1.048 and 1.083 (EulerEKF's Euler step, above), and as 1.5 for the smoother,
mean 1.079): RUNS * 6 * M_EFF >= 296 dof (30 runs x 1.9, 45 x 1.2), whose 99 % interval rejects
1.5x either way with probability >= 99 %. With QUATNAV_TEST_VARIANCE_SCALE = 1/1.5 or 1.5 (the
filter told Q, R and P0 scaled) every check fails (docs/DEVELOPING.md, "Mutations"). About 6 s.

EulerEKF integrates paper 004's Euler-rate equation with one Euler step, whose error grows with
(rate dt)^2 and is not in its covariance: it is checked at 0.5 rad/s (the quaternion filters at
2 rad/s).
"""
from __future__ import annotations

import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q
from quatnav.demo import rotation_scenario

from _consistency import check_mean_nees, scaled

pytest.importorskip("scipy")

N = 2000              #: samples per run (20 s at 100 Hz)
CHECK = np.arange(500, N, 100)  #: checked samples (after 5 s)
GYRO_BIAS_WALK = 1e-5  #: rad/s^2/sqrt(Hz), the truth's and the filter's
#: The robustness parts off: the paper's model, which the simulation follows exactly (an exact
#: gyro scale: no rate-proportional tilt noise).
PLAIN = dict(gyro_rate_noise=0.0, mag_heading_only=False, acc_lp_tau=0.0, acc_lp_bias_sigma=0.0, mag_norm_tol=0.0, mag_dip_tol=0.0,
             mag_gate=0.0, mag_ref_tau=0.0, rest_detection=False)
#: name -> (filter class, its parameters, max rate of the rotation [rad/s], runs, independent samples per run)
CASES = {
    "qekf-paper": (quatnav.QuaternionEKF, dict(paper=True, gyro_rate_noise=0.0), 2.0, 30, 1.9),
    "qekf": (quatnav.QuaternionEKF, PLAIN, 2.0, 30, 1.9),
    "euler-paper": (quatnav.EulerEKF, dict(paper=True), 0.5, 30, 1.9),
}
SMOOTHED_RUNS, SMOOTHED_MEFF = 45, 1.2


def _data(seed, max_rate):
    d = rotation_scenario(n=N, seed=100 + seed, max_rate=max_rate)
    rng = np.random.default_rng([100 + seed, 7])
    walk = np.cumsum(GYRO_BIAS_WALK * np.sqrt(d.dt) * rng.standard_normal((N, 3)), axis=0)
    return d, d.gyr + walk, d.gyro_bias + walk  # the data, the gyro readings, the true bias


def _params(name, d):
    cls, extra, _, _, _ = CASES[name] if name in CASES else CASES["qekf"]
    return cls, scaled(cls.__name__, **extra, gyro_noise=0.005 * np.sqrt(d.dt), gyro_bias_noise=GYRO_BIAS_WALK,
                       acc_sigma=0.05 / 9.80665, mag_sigma=0.5 / 50.0)


def _error_covariance(f):
    """The 6x6 covariance of [dtheta, db] (dtheta body frame: q_true = q * exp(dtheta))."""
    P = np.zeros((6, 6))
    P[:3, :3] = f.attitude_covariance
    if isinstance(f, quatnav.QuaternionEKF) and f.covariance.shape == (7, 7):
        P[3:, 3:] = f.covariance[4:, 4:]
        P[:3, 3:] = 2 * Q.xi(f.quat).T @ f.covariance[:4, 4:]
    elif isinstance(f, quatnav.QuaternionEKF):
        P[3:, 3:] = f.covariance[3:, 3:]
        P[:3, 3:] = f.covariance[:3, 3:]
    else:
        r, p = f.euler[0], f.euler[1]
        W = np.array([[1, 0, -np.sin(p)], [0, np.cos(r), np.sin(r) * np.cos(p)],
                      [0, -np.sin(r), np.cos(r) * np.cos(p)]])
        P[3:, 3:] = f.covariance[3:, 3:]
        P[:3, 3:] = W @ f.covariance[:3, 3:]
    P[3:, :3] = P[:3, 3:].T
    return P


def nees_per_run(name, runs):
    """(runs, checks) NEES of the forward filter ``name`` (a key of CASES)."""
    cls, _, max_rate, _, _ = CASES[name]
    out = []
    for seed in range(runs):
        d, gyr, bias = _data(seed, max_rate)
        f = cls(**_params(name, d)[1])
        f.run(gyr[:1], d.acc[:1], d.mag[:1], dt=d.dt)  # initialize from the first sample (P0 from the parameters)
        rows = []
        for k in range(1, N):
            f.predict(gyr[k], d.dt)
            f.update_acc(d.acc[k])
            f.update_mag(d.mag[k])
            if k in CHECK_SET:
                e = np.concatenate([Q.to_rotvec(Q.mul(Q.conj(f.quat), d.q_nb[k])), bias[k] - f.bias])
                rows.append(e @ np.linalg.solve(_error_covariance(f), e))
        out.append(rows)
    return np.array(out)


CHECK_SET = set(CHECK.tolist())


def smoothed_nees_per_run(runs):
    """(runs, checks) normalized errors squared of the smoothed QuaternionEKF (PLAIN, its
    error-state form): sum over [dtheta, db] of (error / smoothed one-sigma)^2, each component
    against its marginal variance (the C++ smoother returns the diagonal; the full smoothed
    covariance is the numpy twin's, 30x slower). Its components are correlated, which the
    measured M_EFF accounts for."""
    out = []
    for seed in range(runs):
        d, gyr, bias = _data(seed, 2.0)
        r = quatnav.QuaternionEKF(**_params("qekf", d)[1]).run(gyr, d.acc, d.mag, dt=d.dt, smooth=True)
        assert r.sigma_names[:3] == ("dtheta_x", "dtheta_y", "dtheta_z")
        dth = Q.to_rotvec(Q.mul(Q.conj(r.quat[CHECK]), d.q_nb[CHECK]))
        e = np.hstack([dth, bias[CHECK] - r.bias[CHECK]])
        out.append(np.sum((e / r.sigma[CHECK]) ** 2, axis=1))
    return np.array(out)


@pytest.mark.parametrize("name", list(CASES))
def test_nees_within_chi_square_bounds(name):
    _, _, _, runs, m_eff = CASES[name]
    check_mean_nees(nees_per_run(name, runs), 6, m_eff=m_eff, what=f"{name} NEES")


def test_smoothed_nees_within_chi_square_bounds():
    check_mean_nees(smoothed_nees_per_run(SMOOTHED_RUNS), 6, m_eff=SMOOTHED_MEFF, what="smoothed qekf NEES")


def measure_meff(runs=200):
    """Print, per case, how many independent 6-dof samples a run's mean NEES is worth."""
    for name in CASES:
        e = nees_per_run(name, runs).mean(axis=1) / 6
        print(f"{name}: {2 / (6 * e.var(ddof=1)):.2f} independent samples per run, mean {e.mean():.3f}")
    e = smoothed_nees_per_run(runs).mean(axis=1) / 6
    print(f"smoothed: {2 / (6 * e.var(ddof=1)):.2f}, mean {e.mean():.3f}")
