"""GpsInsFilter.run(..., smooth=True): the Rauch-Tung-Striebel backward pass of the 16-state
feedback filter (nav/gps_ins/smoother.hpp).

On the paper-004 walk simulated with sensors that match the filter's model (the setting of
test_gpsins_consistency.py), with a 10 s and a 30 s GNSS outage: the smoothed position, velocity
and attitude errors are consistent with the smoothed sigmas (chi-square bounds over the run),
the worst smoothed error inside each outage is a fraction of the forward drift, the smoothed
sigmas never exceed the forward ones, the forward decisions are kept.

The smoothed normalized errors are checked as every consistency test is (_consistency.py): the
filter told Q, R and P0 times QUATNAV_TEST_VARIANCE_SCALE, the mean over the runs of a block's
squared normalized errors per dof in the two-sided 99 % interval of runs x M_EFF x 3 dof >= 296,
which rejects a covariance off by 1.5x either way with probability >= 99 %. Measured (2026-12-05,
200 runs with the defaults, rest detection on; the per-run means' variance; ``python -c "import
test_gpsins_smoother as T; T.measure_meff()"`` in tests/python): m = 2.8, 6.8 and 1.9 for
position, velocity and attitude (M_EFF at most 80 % of it), means 0.98, 0.91 and 1.03 at truth.
Over the runs checked (48, 24, 80): 0.94, 1.01 and 1.00 at truth, 1.39, 1.42 and 1.44 with the
variances times 1/1.5, 0.64, 0.68 and 0.67 times 1.5 (each of these fails its check).

The runs use the filter's default rest detection: the zero-velocity updates of the stands at the
start and the end of the walk go through the smoother. They ran without it until the rest test
stopped trusting a drifted INS speed in an outage
(``test_no_zero_velocity_update_while_walking_in_an_outage``): the simulated walk at constant
speed has a quiet IMU, and after 20 to 25 s without GNSS the INS speed had drifted (its one-sigma
about 1.9 m/s) below the rest test's limit (0.6 m/s), so the zero-velocity updates pinned the
velocity at zero while the walker moved at 1.4 m/s (seed 7 from 71.8 s: forward error 20 m
against a sigma of 2 m; 12 of 200 runs of a 20 s outage, smoothed velocity errors of 100 to 300
sigma). With a 20 s outage (45-65 s) none of 200 runs now flags rest while walking (the only
samples flagged above 0.5 m/s are the first 1-3 as the walker sets off at 11.6 s, in 14 runs).
"""
import numpy as np
import pytest

import quatnav
from quatnav.core import earth
from quatnav.core import quaternion as Q
from quatnav.sim.scenarios import make_scenario

from _consistency import check_mean_nees, scaled
from test_gpsins_consistency import _filter_params, _matched

OUTAGES = ((20.0, 30.0), (45.0, 75.0))  # s: 10 s, then 30 s without GNSS (the walk lasts ~100 s)
#: block: (columns, runs, M_EFF); the fixture runs as many as the largest needs
NEES_BLOCKS = {"position": ([0, 1, 2], 48, 2.2), "velocity": ([3, 4, 5], 24, 4.9), "attitude": ([6, 7, 8], 80, 1.3)}
SEEDS = tuple(range(max(r for _, r, _ in NEES_BLOCKS.values())))


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


def _aids(gps, baro, cmp_):
    return dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
                gps_vel=quatnav.Aid(gps.t_valid, gps.v_n), compass=quatnav.Aid(cmp_.t, cmp_.yaw),
                baro=quatnav.Aid(baro.t, baro.h))


def _runs(seeds, **params):
    traj = make_scenario("paper004_walk", seed=0).truth
    out = []
    for seed in seeds:
        imu, gps, baro, cmp_ = _matched(traj, seed)
        aids = _aids(gps, baro, cmp_)
        kw = scaled("GpsInsFilter", **_filter_params(), **params)
        r = quatnav.GpsInsFilter(**kw).run(imu.gyro, imu.accel, t=imu.t, outages=OUTAGES, smooth=True, **aids)
        plain = None
        if seed < 3:
            plain = quatnav.GpsInsFilter(**kw).run(imu.gyro, imu.accel, t=imu.t, outages=OUTAGES, **aids)
        out.append((traj, imu, r, plain))
    return out


@pytest.fixture(scope="module")
def runs():
    return _runs(SEEDS)


def _smoothed_nees(runs):
    """Squared normalized errors of position, velocity, attitude (runs x samples x 9), every 10 s
    after the first 20 s (the prior forgotten)."""
    out = []
    for traj, imu, r, _ in runs:
        idx = np.searchsorted(r.t, np.arange(20.0, r.t[-1] - 1.0, 10.0))
        out.append((_errors(r, traj, imu, idx) / r.sigma[idx][:, :9]) ** 2)
    return np.array(out)


def measure_meff(runs=200, **params):
    """The measured m of each block: the per-run means of NEES / dof vary as 2 / (3 m)."""
    z2 = _smoothed_nees(_runs(range(runs), **params))
    for name, (cols, _, _) in NEES_BLOCKS.items():
        per_run = z2[:, :, cols].sum(axis=2).mean(axis=1) / 3
        print(f"{name:9s} mean {per_run.mean():.3f}, m = {2.0 / (3 * per_run.var(ddof=1)):.2f}")


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


@pytest.mark.parametrize("block", list(NEES_BLOCKS))
def test_smoothed_nees_within_chi2_bounds(runs, block):
    """The block's squared normalized errors over its first ``runs`` runs against the interval of
    check_mean_nees. The smoother returns sigmas, so each component is normalized by its own
    variance (the block's cross-covariances left out; the mean is the same)."""
    cols, n, m_eff = NEES_BLOCKS[block]
    nees = _smoothed_nees(runs[:n])[:, :, cols].sum(axis=2)
    check_mean_nees(nees, 3, m_eff=m_eff, what=f"smoothed {block} NEES")


def test_outage_error_is_a_fraction_of_the_forward_drift(runs):
    """The worst horizontal position error inside each outage, smoothed against forward: over the
    runs, the median ratio below 0.5, where the forward solution drifts by more than 1 m in the
    median run, and the ratio below 1 in every run whose forward drift exceeds 1 m. (Below that
    the forward error is at the level of the aided error with 2.5 m fixes, and the smoothed one
    can be a little larger: 0.30 against 0.25 m in one of 80 runs, three of 80 above 1.)"""
    for a, b in OUTAGES:
        ef, es = [], []
        for traj, imu, r, _ in runs:
            idx = np.flatnonzero((r.t >= a) & (r.t < b))
            ef.append(np.hypot(*_errors(r.forward, traj, imu, idx)[:, :2].T).max())
            es.append(np.hypot(*_errors(r, traj, imu, idx)[:, :2].T).max())
        ef = np.array(ef)
        ratio = np.array(es) / ef
        assert np.median(ef) > 1.0, (a, b, ef)
        assert np.median(ratio) < 0.5 and ratio[ef > 1.0].max() < 1.0, (a, b, ratio)


def _false_rest(seed, outages, **params):
    """Samples flagged at rest while the truth moves faster than 0.5 m/s, and the run."""
    traj = make_scenario("paper004_walk", seed=0).truth
    imu, gps, baro, cmp_ = _matched(traj, seed)
    r = quatnav.GpsInsFilter(**_filter_params(), **params).run(imu.gyro, imu.accel, t=imu.t, outages=outages,
                                                               smooth=True, **_aids(gps, baro, cmp_))
    speed = np.linalg.norm(traj.v_n[imu.index], axis=1)
    return int(np.sum(r.flag("at_rest") & (speed > 0.5))), r, traj, imu


def test_smoother_with_the_default_rest_detection():
    """The defaults (rest detection on): the zero-velocity updates of the first 10 s and the last
    10 s of the walk (the walker standing) go through the smoother; a 10 s outage. The smoothed
    velocity at the final stand is zero to within its sigma, the smoothed sigmas never exceed the
    forward ones and the outage's smoothed error is a fraction of the forward drift."""
    n, r, traj, imu = _false_rest(0, ((45.0, 55.0),))
    assert n == 0
    assert r.smoothed and r.smoother["status"] == "ok" and r.flag("at_rest").sum() > 500
    nav = r.navigating
    assert np.all(r.sigma[nav] <= r.forward.sigma[nav] * (1 + 1e-9) + 1e-15)
    stand = nav & (r.t > 90.0)
    assert stand.sum() > 100 and r.flag("at_rest")[stand].all()
    assert np.all(np.abs(r.velocity[stand]) < 4 * r.sigma[stand, 3:6] + 1e-12)
    idx = np.flatnonzero((r.t >= 45.0) & (r.t < 55.0))
    ef = np.hypot(*_errors(r.forward, traj, imu, idx)[:, :2].T).max()
    es = np.hypot(*_errors(r, traj, imu, idx)[:, :2].T).max()
    assert es < 0.5 * ef, (es, ef)


def test_no_zero_velocity_update_while_walking_in_an_outage():
    """With the defaults, seed 7 of the walk and the 30 s outage: no sample may be flagged at
    rest while the walker moves at 1.4 m/s. After 25 s without GNSS the INS speed has drifted
    below 0.6 m/s (its one-sigma 1.9 m/s) and the IMU of a constant-speed walk is as quiet as at
    rest; a rest test that trusted that speed took the walk for rest from 71.8 s (215 samples) and
    its zero-velocity updates pinned the velocity at zero. Seed 153: a rest test whose velocity
    followed the other aids' corrections (compass, altimeter) in the outage still fell below the
    limit from 69.8 s."""
    for seed in (7, 153):
        n, r, _, _ = _false_rest(seed, OUTAGES)
        assert n == 0, (seed, n)
        # the stands at the start and the end of the walk are still detected
        assert r.flag("at_rest")[r.t < 10.0].mean() > 0.8 and r.flag("at_rest")[r.t > 90.0].all()


def test_rest_velocity_in_an_outage_matches_the_numpy_twin():
    """The rest test's velocity (state ``rest_v``) 24 s into the 30 s outage of seed 7, C++
    against the numpy twin: the INS velocity has drifted away from it while it keeps the
    walker's speed (no acceleration stood out of the drift)."""
    from quatnav import reference as R
    traj = make_scenario("paper004_walk", seed=0).truth
    imu, gps, baro, cmp_ = _matched(traj, 7)
    n = int(np.searchsorted(imu.t, 69.0))
    args = (imu.gyro[:n], imu.accel[:n])
    kw = dict(t=imu.t[:n], outages=OUTAGES, **_aids(gps, baro, cmp_))
    f = quatnav.GpsInsFilter(**_filter_params())
    f.run(*args, **kw)
    ref = R.GpsInsFilter(**_filter_params())
    ref.run(*args, **kw)
    st = f.get_state()
    np.testing.assert_allclose(st["v_n"], ref.s.nav.v_n, rtol=0, atol=1e-9)
    np.testing.assert_allclose(st["rest_v"], ref.s.rest_v, rtol=0, atol=1e-9)
    speed = np.linalg.norm(traj.v_n[imu.index[n - 1]])
    assert abs(speed - 1.4) < 0.1
    assert abs(np.linalg.norm(st["rest_v"]) - speed) < 0.2 and np.linalg.norm(st["rest_v"] - st["v_n"]) > 0.5


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
