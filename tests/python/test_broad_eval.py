"""BROAD evaluation: metrics against hand-computed cases, ENU->NED, loader, evaluate, tuning."""
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import quatnav
import quatnav.cli
import quatnav.evaluation.evaluate
import quatnav.evaluation.tuning
from quatnav.evaluation import metrics as M
from quatnav.core import quaternion as Q
from quatnav.datasets import broad

from conftest import DATA

BROAD = DATA / "broad"
needs_data = pytest.mark.skipif(not any(BROAD.glob("*.mat")) if BROAD.is_dir() else True,
                                reason=f"BROAD data not found in {BROAD} (set QUATNAV_DATA)")


def rot(axis, deg):
    a = np.radians(deg) * np.asarray(axis, float) / np.linalg.norm(axis)
    return Q.from_rotvec(a)


# --- metrics -----------------------------------------------------------------------------
def test_pure_heading_error():
    q_ref = rot([1, 0, 0], 30)
    q_est = Q.mul(rot([0, 0, 1], 10), q_ref)  # earth-frame rotation about the vertical
    e = M.error_quat(q_est, q_ref)
    assert np.degrees(M.total_error(e)) == pytest.approx(10)
    assert np.degrees(M.heading_error(e)) == pytest.approx(10)
    assert np.degrees(M.inclination_error(e)) == pytest.approx(0, abs=1e-6)


def test_pure_inclination_error():
    q_ref = rot([0, 0, 1], 70)
    q_est = Q.mul(rot([1, 1, 0], 4), q_ref)  # earth-frame rotation about a horizontal axis
    e = M.error_quat(q_est, q_ref)
    assert np.degrees(M.total_error(e)) == pytest.approx(4)
    assert np.degrees(M.heading_error(e)) == pytest.approx(0, abs=1e-6)
    assert np.degrees(M.inclination_error(e)) == pytest.approx(4)


def test_combined_error_hand_computed():
    # e = exp(z 2a) * exp(x 2b) in the earth frame: w = cos a cos b, z = sin a cos b:
    # heading 2 atan(tan a) = 2a, inclination 2 acos(cos b) = 2b, total 2 acos(cos a cos b).
    a, b = np.radians(3.0), np.radians(2.0)
    e_true = Q.mul(Q.from_rotvec([0, 0, 2 * a]), Q.from_rotvec([2 * b, 0, 0]))
    q_ref = rot([0.2, -0.5, 1.0], 40)
    q_est = Q.mul(e_true, q_ref)
    e = M.error_quat(q_est, q_ref)
    assert M.heading_error(e) == pytest.approx(2 * a)
    assert M.inclination_error(e) == pytest.approx(2 * b)
    assert M.total_error(e) == pytest.approx(2 * np.arccos(np.cos(a) * np.cos(b)))


def test_errors_same_in_ned_and_enu():
    rng = np.random.default_rng(0)
    qe = Q.normalize(rng.normal(size=(20, 4)))
    qr = Q.normalize(rng.normal(size=(20, 4)))
    e1 = M.error_quat(qe, qr)
    e2 = M.error_quat(Q.enu_to_ned(qe), Q.enu_to_ned(qr))
    for f in (M.total_error, M.heading_error, M.inclination_error):
        np.testing.assert_allclose(f(e1), f(e2), atol=1e-9)


def test_rmse_mask_and_nan():
    x = np.array([3.0, 4.0, np.nan, 100.0])
    mask = np.array([True, True, True, False])
    assert M.rmse(x, mask) == pytest.approx(np.sqrt((9 + 16) / 2))
    assert np.isnan(M.rmse(x, np.zeros(4, bool)))


def test_attitude_rmse_deg_ignores_nan_reference_and_sign():
    q_ref = np.tile(rot([0, 0, 1], 20), (4, 1))
    q_est = np.array([Q.mul(rot([0, 0, 1], 2), q_ref[0]), -Q.mul(rot([0, 0, 1], 4), q_ref[1]),
                      q_ref[2], q_ref[3]])
    q_ref[2] = np.nan
    out = M.attitude_rmse_deg(q_est, q_ref, mask=[True, True, True, False])
    assert out["total"] == pytest.approx(np.sqrt((4 + 16) / 2))
    assert out["heading"] == pytest.approx(np.sqrt((4 + 16) / 2))
    assert out["inclination"] == pytest.approx(0, abs=1e-5)


def test_sigma_consistency_hand_case():
    q_ref = np.tile(Q.identity(), (4, 1))
    q_est = np.array([rot([1, 0, 0], d) for d in (1.0, 2.0, 4.0, 0.0)])
    sig = np.full((4, 3), np.radians(1.0))  # 3 sigma = 3 deg: the 4 deg sample fails on one axis
    assert M.sigma_consistency(q_est, q_ref, sig) == pytest.approx(11 / 12)
    assert M.sigma_consistency(q_est, q_ref, sig, k=5) == 1.0


# --- ENU -> NED ----------------------------------------------------------------------------
def test_enu_to_ned_helper():
    # A body whose x axis points north in ENU: q_enu_b = 90 deg about z (x_b -> y_e).
    q_enu = rot([0, 0, 1], 90)
    np.testing.assert_allclose(Q.rotate(q_enu, [1, 0, 0]), [0, 1, 0], atol=1e-12)
    q_ned = broad.enu_to_ned(q_enu)
    np.testing.assert_allclose(Q.rotate(q_ned, [1, 0, 0]), [1, 0, 0], atol=1e-12)  # north
    # Up in ENU is -z in NED; NaN rows stay NaN; round trip.
    np.testing.assert_allclose(Q.rotate(broad.enu_to_ned(Q.identity()), [0, 0, 1]), [0, 0, -1], atol=1e-12)
    qs = np.array([q_enu, [np.nan] * 4])
    out = broad.enu_to_ned(qs)
    assert np.all(np.isnan(out[1]))
    np.testing.assert_allclose(Q.ned_to_enu(out[0]), q_enu, atol=1e-12)


# --- synthetic BROAD-format trials (no data needed) ---------------------------------------
def write_synthetic_trial(path, n=1500, rate=100.0, seed=0):
    import scipy.io as sio
    rng = np.random.default_rng(seed)
    dt = 1 / rate
    q = Q.identity()
    g_n, m_n = np.array([0, 0, 9.81]), 45.0 * np.array([np.cos(1.1), 0, np.sin(1.1)])  # NED
    gyr, acc, mag, quat = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 4))
    for k in range(n):
        w = 0.4 * np.array([np.sin(0.01 * k), np.cos(0.013 * k), 0.6]) if k > 300 else np.zeros(3)
        if k:
            q = Q.mul(q, Q.from_rotvec(w * dt))
        quat[k] = q
        gyr[k] = w + rng.normal(0, 0.003, 3)
        acc[k] = Q.rotate_inv(q, -g_n) + rng.normal(0, 0.05, 3)
        mag[k] = Q.rotate_inv(q, m_n) + rng.normal(0, 0.3, 3)
    q_enu = Q.ned_to_enu(quat)
    q_enu[400:420] = np.nan
    movement = np.zeros((n, 1), np.uint8)
    movement[300:] = 1
    sio.savemat(path, dict(imu_gyr=gyr, imu_acc=acc, imu_mag=mag, opt_quat=q_enu, opt_pos=np.zeros((n, 3)),
                           sampling_rate=np.array([[rate]]), movement=movement, info=np.array(["synthetic"])))
    return quat


@pytest.fixture
def synthetic_dir(tmp_path):
    truth = {}
    for i in range(2):
        truth[f"0{i}_synthetic"] = write_synthetic_trial(tmp_path / f"0{i}_synthetic.mat", seed=i)
    return tmp_path, truth


def test_loader_on_synthetic(synthetic_dir):
    d, truth = synthetic_dir
    files = broad.list_trials(d)
    assert [f.stem for f in files] == sorted(truth)
    t = broad.load_trial(files[0])
    assert t.gyr.shape == (1500, 3) and t.quat_ref.shape == (1500, 4) and t.rate == 100.0
    assert t.movement.dtype == bool and t.movement.sum() == 1200
    assert np.all(np.isnan(t.quat_ref[400:420]))
    ok = np.isfinite(t.quat_ref[:, 0])
    ang = M.total_error(M.error_quat(t.quat_ref[ok], truth[t.name][ok]))
    assert ang.max() < 1e-9  # the reference came back in NED


def test_evaluate_and_table_on_synthetic(synthetic_dir):
    d, _ = synthetic_dir
    res = quatnav.evaluation.evaluate.evaluate(d, filters=("qekf", "euler-ekf"), peers=())
    assert res["algorithms"] == ["qekf", "euler-ekf"]
    for t in res["trials"].values():
        assert t["results"]["qekf"]["total"] < 3.0
        assert 0 <= t["results"]["qekf"]["within_3sigma"] <= 1
    assert res["mean"]["qekf"]["total"] == pytest.approx(
        np.mean([t["results"]["qekf"]["total"] for t in res["trials"].values()]))
    text = quatnav.evaluation.evaluate.format_table(res)
    assert "mean total" in text and "qekf" in text


def test_missing_filter_is_skipped_with_note(synthetic_dir, monkeypatch):
    d, _ = synthetic_dir
    monkeypatch.setitem(quatnav.evaluation.evaluate.FILTERS, "nope", "NoSuchFilter")
    monkeypatch.setitem(quatnav.evaluation.evaluate.PEERS, "nopeer", "no_such_module_xyz")
    res = quatnav.evaluation.evaluate.evaluate(d, filters=("qekf", "nope"), peers=("nopeer",))
    assert res["algorithms"] == ["qekf"]
    assert len(res["notes"]) == 2


def test_cli_eval_broad(synthetic_dir, tmp_path, capsys):
    d, _ = synthetic_dir
    out = tmp_path / "r.json"
    plots = tmp_path / "plots"
    rc = quatnav.cli.main(["eval", "broad", str(d), "--filters", "qekf", "--peers", "", "--json", str(out),
                           "--plot", str(plots), "--quiet"])
    assert rc == 0
    import json
    data = json.loads(out.read_text())
    mean = data["datasets"][d.name]["mean"]
    assert set(mean) == {"qekf 9D", "qekf 6D"} and data["align"] == "both"
    assert mean["qekf 9D"]["total"] == pytest.approx(
        np.mean([t["results"]["qekf 9D"]["total"] for t in data["trials"].values()]))
    assert (plots / "summary.png").exists()
    assert len(list(plots.glob("error_*.png"))) == 2
    assert "mean total" in capsys.readouterr().out


def test_tuning_picks_lowest_mean(synthetic_dir):
    d, _ = synthetic_dir
    sets = quatnav.evaluation.tuning.grid(acc_sigma=[0.05, 5.0], mag_sigma=[0.1])
    assert len(sets) == 2
    with ThreadPoolExecutor(max_workers=2) as ex:
        res = quatnav.evaluation.tuning.tune(sets, directory=d, executor=ex)
    scores = [r[0] for r in res.ranking]
    assert scores == sorted(scores)
    assert res.best_score == scores[0]
    for score, p, per in res.ranking:
        assert score == pytest.approx(np.mean([v["total"] for v in per.values()]))


# --- the real data --------------------------------------------------------------------------
@needs_data
def test_loader_on_broad():
    files = broad.list_trials(BROAD)
    t = broad.load_trial(files[0])
    assert t.rate == pytest.approx(285.714, rel=1e-4)
    assert np.median(np.linalg.norm(t.acc[:200], axis=1)) == pytest.approx(9.81, abs=0.2)
    assert np.median(np.linalg.norm(t.mag, axis=1)) == pytest.approx(44, abs=8)  # uT
    ok = np.isfinite(t.quat_ref[:, 0])
    np.testing.assert_allclose(np.linalg.norm(t.quat_ref[ok], axis=1), 1, atol=1e-6)
    assert t.movement.any() and "all_trials" in t.groups
    # Gravity from the reference agrees with the accelerometer at the start (rest): NED down.
    k = np.flatnonzero(ok)[0]
    f_n = Q.rotate(t.quat_ref[k], t.acc[k])
    assert f_n[2] == pytest.approx(-9.81, abs=0.3)


@needs_data
def test_peer_mappings_on_broad():
    """Each peer's frame mapping puts it within a few degrees of the reference."""
    t = broad.load_trial(broad.list_trials(BROAD)[0])
    for name in ("vqf", "imufusion"):
        ok, _ = quatnav.evaluation.evaluate.available(name)
        if not ok:
            continue
        r = quatnav.evaluation.evaluate.evaluate_trial(t, name)
        assert r["total"] < 5.0, name
