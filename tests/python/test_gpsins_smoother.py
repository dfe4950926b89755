"""GpsInsFilter.run(..., smooth=True): the Rauch-Tung-Striebel backward pass of the 16-state
feedback filter (nav/gps_ins/smoother.hpp).

On the paper-004 walk simulated with sensors that match the filter's model (the setting of
test_gpsins_consistency.py), with a 10 s and a 30 s GNSS outage: the smoothed position, velocity
and attitude errors are consistent with the smoothed sigmas (chi-square bounds over the run),
the worst smoothed error inside each outage is a fraction of the forward drift, the smoothed
sigmas never exceed the forward ones, the forward decisions are kept.

The rest detector is off in these runs: the simulated walk at constant speed has a quiet IMU, and
with the velocity uncertain after 25 s without GNSS the forward filter takes it for rest (measured:
seed 7, zero-velocity updates at 72 s while walking at 1.4 m/s, the forward error 20 m against a
sigma of 2 m). The smoother keeps the forward decisions, that one too, and spreads it over the
outage (smoothed error 14 m, sigma 0.4 m): the consistency of the smoother is tested here, on
forward decisions that are right.
"""
import numpy as np
import pytest

import quatnav
from quatnav.core import earth
from quatnav.core import quaternion as Q
from quatnav.sim.scenarios import make_scenario

from test_gpsins_consistency import _filter_params, _matched

OUTAGES = ((20.0, 30.0), (45.0, 75.0))  # s: 10 s, then 30 s without GNSS (the walk lasts ~100 s)
SEEDS = tuple(range(20))


def _errors(r, traj, imu, k):
    """Estimate minus truth (the filter's error coordinates) of position (m, NED), velocity and
    attitude (the nav-frame phi-angle) at the IMU samples k."""
    ti = imu.index[k]
    lt, ht = traj.lat[ti], traj.h[ti]
    R_M, R_N = earth.radii(lt)
    p = r.position[k]
    dp = np.column_stack([(p[:, 0] - lt) * (R_M + ht), (p[:, 1] - traj.lon[ti]) * (R_N + ht) * np.cos(lt),
                          -(p[:, 2] - ht)])
    dv = r.velocity[k] - traj.v_n[ti]
    psi = Q.to_rotvec(Q.mul(r.quat[k], Q.conj(traj.q_nb[ti])))
    return np.column_stack([dp, dv, psi])


@pytest.fixture(scope="module")
def runs():
    traj = make_scenario("paper004_walk", seed=0).truth
    out = []
    for seed in SEEDS:
        imu, gps, baro, cmp_ = _matched(traj, seed)
        aids = dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
                    gps_vel=quatnav.Aid(gps.t_valid, gps.v_n), compass=quatnav.Aid(cmp_.t, cmp_.yaw),
                    baro=quatnav.Aid(baro.t, baro.h))
        f = quatnav.GpsInsFilter(**_filter_params(), zupt=False)
        r = f.run(imu.gyro, imu.accel, t=imu.t, outages=OUTAGES, smooth=True, **aids)
        plain = None
        if seed < 3:
            plain = quatnav.GpsInsFilter(**_filter_params(), zupt=False).run(imu.gyro, imu.accel, t=imu.t,
                                                                             outages=OUTAGES, **aids)
        out.append((traj, imu, r, plain))
    return out


def test_forward_part_is_the_plain_run_and_its_decisions_are_kept(runs):
    for _, _, r, plain in runs[:3]:
        assert r.smoothed and r.smoother["status"] == "ok"
        np.testing.assert_array_equal(r.forward.position, plain.position)
        np.testing.assert_array_equal(r.forward.sigma, plain.sigma)
        np.testing.assert_array_equal(r.flags, plain.flags)
        assert r.counters == plain.counters
        for name, a in plain.aids.items():
            np.testing.assert_array_equal(r.aids[name].decision, a.decision)
        # the record: aid epochs and checkpoints, far fewer than the samples
        assert r.smoother["records"] < len(r.t)


def test_last_sample_is_the_forward_one_and_sigmas_never_above(runs):
    for _, _, r, _ in runs:
        np.testing.assert_array_equal(r.position[-1], r.forward.position[-1])
        np.testing.assert_array_equal(r.quat[-1], r.forward.quat[-1])
        np.testing.assert_array_equal(r.sigma[-1], r.forward.sigma[-1])
        nav = r.navigating
        assert np.all(r.sigma[nav] <= r.forward.sigma[nav] * (1 + 1e-9) + 1e-15)
        # ... and well below them inside the outages (the position sigma at the middle of each)
        for a, b in OUTAGES:
            k = np.searchsorted(r.t, 0.5 * (a + b))
            assert r.sigma[k, 0] < 0.5 * r.forward.sigma[k, 0]


@pytest.mark.parametrize("block,cols", [("position", [0, 1, 2]), ("velocity", [3, 4, 5]), ("attitude", [6, 7, 8])])
def test_smoothed_nees_within_chi2_bounds(runs, block, cols):
    """The normalized squared errors of the block, every 10 s after the first 20 s (the prior
    forgotten; the smoothed errors are correlated over seconds), over the 20 runs: the mean within
    the two-sided 99.9 % chi-square bounds. The
    smoother returns sigmas, so each component is normalized by its own variance (the block's
    cross-covariances left out; a block's NEES with them is the same mean, chi-square distributed)."""
    from scipy.stats import chi2
    vals = []
    for traj, imu, r, _ in runs:
        idx = np.searchsorted(r.t, np.arange(20.0, r.t[-1] - 1.0, 10.0))
        e = _errors(r, traj, imu, idx)[:, cols]
        vals.append(((e / r.sigma[idx][:, cols]) ** 2).sum(axis=1))
    nees = np.concatenate(vals)
    m, d = len(nees), len(cols)
    lo, hi = chi2.ppf([0.0005, 0.9995], d * m) / m
    assert m >= 60
    assert lo < nees.mean() < hi, (block, lo, nees.mean(), hi)


def test_outage_error_is_a_fraction_of_the_forward_drift(runs):
    """The worst horizontal position error inside each outage, smoothed against forward: over the
    runs, the median ratio below 0.5 and the ratio below 1 in every run, where the forward
    solution drifts by more than 1 m in the median run."""
    for a, b in OUTAGES:
        ef, es = [], []
        for traj, imu, r, _ in runs:
            idx = np.flatnonzero((r.t >= a) & (r.t < b))
            ef.append(np.hypot(*_errors(r.forward, traj, imu, idx)[:, :2].T).max())
            es.append(np.hypot(*_errors(r, traj, imu, idx)[:, :2].T).max())
        ratio = np.array(es) / np.array(ef)
        assert np.median(ef) > 1.0, (a, b, ef)
        assert np.median(ratio) < 0.5 and ratio.max() < 1.0, (a, b, ratio)


def test_cpp_matches_the_numpy_twin_backward_pass():
    """The C++ smoother against ``quatnav.reference.gpsins.run_smoothed`` on the paper-004 walk
    (its own sensor errors, every aid) with a GNSS outage: alignment, levelling and ~25 s of
    navigation, sample by sample."""
    from quatnav import reference as R
    from quatnav.reference.gpsins import run_smoothed

    from _aids import as_aids
    from test_gpsins import LEVER, _aids
    s, n = make_scenario("paper004_walk", seed=0), 1500
    kw = _aids(s)
    kw["gps_llh"] = kw["gps_llh"].copy()
    kw["gps_llh"][(kw["gps_t"] >= 15.0) & (kw["gps_t"] < 22.0)] = np.nan  # a 7 s outage
    r = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], smooth=True,
                                                   **as_aids(kw))
    fwd, ref = run_smoothed(R.GpsInsFilter(lever_arm_b=LEVER), s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n],
                            **as_aids(kw))
    nav = r.navigating
    assert nav.sum() > 1000
    d = np.abs(r.position[nav] - r.forward.position[nav]).max(axis=0)
    assert d[0] > 1e-8  # the smoother moved the position (radians: ~0.1 m)
    np.testing.assert_allclose(r.position[nav, :2], ref["llh"][nav, :2], rtol=0, atol=1e-12)  # rad: 6 um
    np.testing.assert_allclose(r.h[nav], ref["llh"][nav, 2], rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.velocity[nav], ref["v_n"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.quat[nav], ref["q_nb"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.bias[nav], ref["gyro_bias"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.acc_bias[nav], ref["acc_bias"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.sigma[nav], ref["sigma"][nav], rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(r.baro_offset, ref["baro_offset"], rtol=0, atol=1e-7)
