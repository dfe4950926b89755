"""The attitude filters' Rauch-Tung-Striebel smoothers (attitude/smoother.hpp, docs/SMOOTHING.md):
the C++ smoothed run against the numpy twin step by step (QuaternionEKF's error-state default and
EulerEKF), smoothed sigmas never above the forward ones, the NEES of the smoothed attitude and bias
within chi-square bounds, the forward pass's rejections and rest detection kept, float32, the API."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

import quatnav
from quatnav import reference
from quatnav.core import quaternion as Q
from quatnav.demo import rotation_scenario
from quatnav.reference.attitude_smoother import run_smoothed

FILTERS = [("QuaternionEKF", quatnav.QuaternionEKF, reference.QuaternionEKF),
           ("EulerEKF", quatnav.EulerEKF, reference.EulerEKF)]
#: QuaternionEKF with the paper's model and none of the robustness parts (a consistent covariance
#: on the simulated rotation, as test_attitude's NEES test), in its error-state default form.
PLAIN = dict(gyro_bias_noise=1e-6, init_gyro_bias_sigma=0.03, init_att_sigma=0.05, mag_heading_only=False,
             acc_lp_tau=0.0, acc_lp_bias_sigma=0.0, mag_norm_tol=0.0, mag_dip_tol=0.0, mag_gate=0.0, mag_ref_tau=0.0,
             rest_detection=False)


@pytest.fixture(scope="module")
def rot():
    return rotation_scenario(n=1500, rate=100.0, seed=3)


@pytest.mark.parametrize("name,cls,ref", FILTERS)
def test_cpp_smoother_matches_reference_step_by_step(name, cls, ref, rot):
    d = rot
    r = cls().run(d.gyr, d.acc, d.mag, dt=d.dt, smooth=True)
    t = run_smoothed(ref(), d.gyr, d.acc, d.mag, dt=d.dt)
    dq = np.max(np.abs(Q.canonical(r.quat) - Q.canonical(t.smoothed.quat)))
    db = np.max(np.abs(r.bias - t.smoothed.bias))
    ds = np.max(np.abs(r.sigma - t.smoothed.sigma))
    da = np.max(np.abs(r.att_sigma - t.smoothed.att_sigma))
    assert dq < 1e-9 and db < 1e-9 and ds < 1e-9 and da < 1e-9, (dq, db, ds, da)
    # The forward result is the plain run's; the smoother changed the estimates.
    f = cls().run(d.gyr, d.acc, d.mag, dt=d.dt)
    np.testing.assert_array_equal(r.forward.quat, f.quat)
    np.testing.assert_array_equal(r.quat[-1], f.quat[-1])
    assert np.max(Q.angle_between(r.quat, f.quat)) > 1e-3
    # Smoothed sigmas at most the forward ones: every state of both (their covariances are in the
    # coordinates the smoother corrects in), and the body-frame attitude one-sigma of the
    # error-state filter.
    assert np.all(r.sigma <= f.sigma * (1 + 1e-9) + 1e-15)
    if name == "QuaternionEKF":
        assert np.all(r.att_sigma <= f.att_sigma * (1 + 1e-9) + 1e-15)


def _twin_params(**kw):
    """The numpy twin's (C++) names of QuaternionEKF's Python parameters."""
    from quatnav.filters.tables import QEKF_PARAMS
    names = {p.name: p.core_name for p in QEKF_PARAMS}
    return {names[k]: v for k, v in kw.items()}


def test_forward_decisions_are_kept():
    """Rejected accelerometer updates (|a| far from g) and rest detection happen in the forward
    pass only: the smoother keeps the forward flags and matches the twin fed the same samples
    (whose forward pass makes the same decisions). A saturated gyro sample skips its time update:
    the smoothed state does not move over it."""
    d = rotation_scenario(n=1200, rate=100.0, seed=5)
    acc, gyr = d.acc.copy(), d.gyr.copy()
    acc[300:340] *= 1.8                    # a shock: rejected by acc_reject
    gyr[600:1000] = d.gyro_bias            # at rest (the gyro reads its bias): zero-rate updates
    acc[600:1000] = acc[599]
    # acc_lp_dev=0: the low-pass stays short while the bias is uncertain (3 s in), so the shock
    # reaches the norm test (with the default the low-pass lengthens under it and averages it)
    p = dict(acc_reject=2.0, acc_lp_dev=0.0)
    r = quatnav.QuaternionEKF(**p).run(gyr, acc, d.mag, dt=d.dt, smooth=True)
    assert r.flag("acc_rejected")[300:345].sum() >= 30 and r.flag("at_rest")[900:1000].sum() >= 40
    np.testing.assert_array_equal(r.flags, r.forward.flags)
    t = run_smoothed(reference.QuaternionEKF(**p), gyr, acc, d.mag, dt=d.dt)
    bits = quatnav.FLAGS["acc_rejected"] | quatnav.FLAGS["at_rest"]
    np.testing.assert_array_equal(t.flags & bits, r.flags & bits)
    np.testing.assert_allclose(Q.canonical(r.quat), Q.canonical(t.smoothed.quat), atol=1e-9)
    np.testing.assert_allclose(r.bias, t.smoothed.bias, atol=1e-9)
    gyr[500] = [0.0, 0.0, 9.0]             # saturated: the predict of sample 500 is skipped
    r = quatnav.QuaternionEKF(gyro_range=8.0).run(gyr, acc, d.mag, dt=d.dt, smooth=True)
    assert r.flag("saturated")[500]
    np.testing.assert_array_equal(r.quat[499], r.quat[500])
    np.testing.assert_array_equal(r.sigma[499], r.sigma[500])


def test_float32_tracks_float64(rot):
    d = rot
    r64 = quatnav.QuaternionEKF().run(d.gyr, d.acc, d.mag, dt=d.dt, smooth=True)
    r32 = quatnav.QuaternionEKF(dtype=np.float32).run(d.gyr, d.acc, d.mag, dt=d.dt, smooth=True)
    assert r32.quat.dtype == np.float32 and r32.forward.quat.dtype == np.float32
    assert np.max(Q.angle_between(r32.quat.astype(float), r64.quat)) < 1e-4
    np.testing.assert_allclose(r32.att_sigma, r64.att_sigma, rtol=1e-3)


def test_result_api_and_paper_filter_refused(rot):
    d = rot
    r = quatnav.EulerEKF().run(d.gyr, d.acc, d.mag, dt=d.dt, smooth=True)
    assert r.smoothed and isinstance(r.forward, quatnav.AttitudeResult) and not r.forward.smoothed
    assert "smoothed" in repr(r)
    assert r.smoother["status"] == "ok" and r.smoother["records"] == len(d.gyr)  # every sample updates
    assert r.smoother["bytes"] >= r.smoother["records"] * r.smoother["record_bytes"]
    with pytest.raises(ValueError, match="smooth"):
        quatnav.QuaternionEKF(paper=True).run(d.gyr, d.acc, d.mag, dt=d.dt, smooth=True)
    # Rows that cannot initialize the filter: those samples keep the forward (NaN-free) output.
    acc = d.acc.copy()
    acc[:5] = np.nan
    r = quatnav.QuaternionEKF().run(d.gyr, acc, d.mag, dt=d.dt, smooth=True, on_invalid="skip")
    np.testing.assert_array_equal(r.quat[:5], r.forward.quat[:5])


@pytest.mark.slow
def test_smoothed_nees_within_chi_square_bounds():
    """The error-state QuaternionEKF without the robustness parts (PLAIN) on simulated rotations
    (8 seeds, up to 2 rad/s): the Monte Carlo average NEES of the smoothed [dtheta, db] (6 dof)
    within the two-sided 99% chi-square bounds at most instants and on average. The estimates are
    the C++ smoother's; the full smoothed covariance (the C++ run returns its diagonal) is the
    numpy twin's, which equals the C++ one (test_cpp_smoother_matches_reference_step_by_step;
    checked again here on the estimates and sigmas)."""
    runs, n = 8, 1000
    nees = []
    for seed in range(runs):
        d = rotation_scenario(n=n, seed=100 + seed, max_rate=2.0)
        kw = dict(gyro_noise=0.005 * np.sqrt(d.dt), acc_sigma=0.05 / 9.80665, mag_sigma=0.5 / 50.0, **PLAIN)
        r = quatnav.QuaternionEKF(**kw).run(d.gyr, d.acc, d.mag, dt=d.dt, smooth=True)
        t = run_smoothed(reference.QuaternionEKF(**_twin_params(**kw)), d.gyr, d.acc, d.mag, dt=d.dt).smoothed
        assert np.max(np.abs(r.sigma - t.sigma)) < 1e-9 and np.max(np.abs(Q.canonical(r.quat) - Q.canonical(t.quat))) < 1e-9
        k = np.arange(500, n, 25)  # after 5 s
        dth = Q.to_rotvec(Q.mul(Q.conj(r.quat[k]), d.q_nb[k]))  # q_true = q * exp(dtheta)
        e = np.hstack([dth, d.gyro_bias - r.bias[k]])
        nees.append(np.einsum("ki,ki->k", e, np.linalg.solve(t.P[k], e[..., None])[..., 0]))
    nees = np.array(nees)
    avg = nees.mean(axis=0)
    lo, hi = stats.chi2.ppf([0.005, 0.995], 6 * runs) / runs
    inside = np.mean((avg > lo) & (avg < hi))
    assert inside >= 0.8, (inside, lo, hi, avg)
    assert lo < nees.mean() < hi, nees.mean()


def test_broad_smoothed_below_causal_and_vqf_offline(data_dir):
    """On a BROAD trial with a magnet attached to the sensor (33), the smoothed QuaternionEKF's
    total RMSE is below the causal one and below VQF's offline mode (measured: 1.27 against 3.89
    and 1.81 deg; all eight trials: docs/SMOOTHING.md)."""
    from quatnav.datasets import broad
    from quatnav.evaluation.evaluate import available, evaluate_trial
    trial = broad.load_trial(data_dir / "broad" / "33_disturbed_attached_magnet_2cm.mat")
    smoothed = evaluate_trial(trial, "qekf-smoothed")["total"]
    assert smoothed < evaluate_trial(trial, "qekf")["total"]
    if available("vqf-offline")[0]:
        assert smoothed < evaluate_trial(trial, "vqf-offline")["total"]


def test_ahrs_run_smooth(rot, tmp_path, capsys):
    """``quatnav ahrs run --smooth`` writes the smoothed attitude of the API's run(smooth=True)
    (closer to the truth than without); with marg it is a one-line usage error."""
    pd = pytest.importorskip("pandas")
    from quatnav import cli
    d = rot
    t = np.arange(len(d.gyr)) * d.dt
    cols = {"time": t, **{f"gyro_{c}": d.gyr[:, i] for i, c in enumerate("xyz")},
            **{f"accel_{c}": d.acc[:, i] for i, c in enumerate("xyz")},
            **{f"mag_{c}": d.mag[:, i] for i, c in enumerate("xyz")}}
    pd.DataFrame(cols).to_csv(tmp_path / "imu.csv", index=False, float_format="%.17g")
    out = tmp_path / "s.csv"
    assert cli.main(["ahrs", "run", "--imu", str(tmp_path / "imu.csv"), "--smooth", "--out", str(out)]) == 0
    q = pd.read_csv(out)[["q_w", "q_x", "q_y", "q_z"]].to_numpy()
    r = quatnav.QuaternionEKF().run(d.gyr, d.acc, d.mag, t=t, on_invalid="skip", smooth=True)
    np.testing.assert_allclose(q, r.quat, atol=1e-9)
    assert np.mean(Q.angle_between(q, d.q_nb) ** 2) < np.mean(Q.angle_between(r.forward.quat, d.q_nb) ** 2)
    capsys.readouterr()
    assert cli.main(["ahrs", "run", "--imu", str(tmp_path / "imu.csv"), "--filter", "marg", "--smooth",
                     "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "--smooth" in err and len(err.splitlines()) == 1
