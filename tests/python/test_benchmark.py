"""The attitude benchmark: alignment fit, the generic trial format, runs over sources, the CLI."""
import json
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import quatnav
import quatnav.cli
from quatnav.core import quaternion as Q
from quatnav.datasets import trials as T
from quatnav.evaluation import metrics as M
from quatnav.evaluation.benchmark import benchmark, evaluate_run, resolve_sources

from conftest import DATA


def rotvec_deg(v):
    return Q.from_rotvec(np.radians(np.asarray(v, float)))


# --- alignment ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def random_refs():
    rng = np.random.default_rng(4)
    return Q.normalize(rng.standard_normal((3000, 4))), rng


def test_fit_alignment_recovers_both_rotations(random_refs):
    ref, rng = random_refs
    q_e, q_b = rotvec_deg([0, 0, 37]), rotvec_deg([12, -30, 50])
    est = Q.mul(Q.mul(q_e, ref), q_b)
    fe, fb = M.fit_alignment(est, ref)
    assert abs(abs(fe @ q_e) - 1) < 1e-12 and abs(abs(fb @ q_b) - 1) < 1e-12
    noisy = Q.mul(est, Q.from_rotvec(0.01 * rng.standard_normal((len(est), 3))))
    out = M.aligned_errors_deg(noisy, ref)
    # 0.01 rad per axis: total RMSE sqrt(3) * 0.573 deg; the fit takes nothing more away
    assert out["total"] == pytest.approx(np.sqrt(3) * np.degrees(0.01), rel=0.05)
    assert out["align_heading_deg"] == pytest.approx(37, abs=0.1)
    assert out["align_body_deg"] == pytest.approx(np.degrees(np.linalg.norm(np.radians([12, -30, 50]))), abs=0.1)


def test_fit_alignment_options(random_refs):
    ref, _ = random_refs
    est = Q.mul(Q.mul(rotvec_deg([0, 0, 20]), ref), rotvec_deg([3, 0, 0]))
    none = M.aligned_errors_deg(est, ref, align="none")
    heading = M.aligned_errors_deg(est, ref, align="heading")
    both = M.aligned_errors_deg(est, ref, align="both")
    assert none["total"] > 15 and none["align_heading_deg"] == 0
    assert 1 < heading["total"] < 5  # the body rotation is left
    assert both["total"] < 1e-5
    # a tilt of the earth frame is not an alignment: it stays an inclination error
    tilted = Q.mul(rotvec_deg([2, 0, 0]), ref)
    assert M.aligned_errors_deg(tilted, ref)["inclination"] > 1.0
    with pytest.raises(ValueError, match="align"):
        M.fit_alignment(est, ref, align="full")


def test_fit_alignment_ignores_nan_and_mask(random_refs):
    ref, _ = random_refs
    est = Q.mul(rotvec_deg([0, 0, -50]), ref)
    ref2 = ref.copy()
    ref2[:100] = np.nan
    mask = np.ones(len(ref), bool)
    mask[-200:] = False
    bad = est.copy()
    bad[-200:] = Q.identity()  # outside the mask: must not move the fit
    out = M.aligned_errors_deg(bad, ref2, mask)
    assert out["total"] < 1e-5 and out["align_heading_deg"] == pytest.approx(-50)


# --- trials: format, round trip, frames -----------------------------------------------------
def make_trial(n=2400, rate=100.0, seed=0, mag=True, name="t"):
    """A rotating, noisy IMU with its exact reference (NED)."""
    rng = np.random.default_rng(seed)
    dt = 1 / rate
    t = np.arange(n) * dt
    w = np.column_stack([0.5 * np.sin(0.3 * t + seed), 0.4 * np.cos(0.23 * t), 0.3 * np.sin(0.17 * t + 1)])
    w[t < 3] = 0.0
    q = np.empty((n, 4))
    q[0] = rotvec_deg([5, -3, 40])
    for k in range(1, n):
        q[k] = Q.mul(q[k - 1], Q.from_rotvec(w[k] * dt))
    g_n, m_n = np.array([0, 0, 9.81]), 48 * np.array([np.cos(1.1), 0, np.sin(1.1)])
    gyr = w + np.array([0.01, -0.02, 0.015]) + rng.normal(0, 0.003, (n, 3))
    acc = Q.rotate_inv(q, -g_n) + rng.normal(0, 0.05, (n, 3))
    m = Q.rotate_inv(q, np.broadcast_to(m_n, (n, 3))) + rng.normal(0, 0.3, (n, 3)) if mag else None
    mov = t >= 3.0
    return T.Trial(name, gyr, acc, m, t, q, mov, ["g"], "synthetic", "")


@pytest.mark.parametrize("suffix", [".csv", ".h5", ".mat"])
@pytest.mark.parametrize("frame", ["NED", "ENU"])
def test_trial_round_trip(tmp_path, suffix, frame):
    tr = make_trial(n=600)
    tr.quat_ref[50:60] = np.nan
    p = T.save_trial(tr, tmp_path / f"x{suffix}", ref_frame=frame)
    back = T.load_trial(p)
    assert back.name == "x" and back.dataset == tmp_path.name
    for f in ("gyr", "acc", "mag", "t"):
        np.testing.assert_allclose(getattr(back, f), getattr(tr, f), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(back.movement, tr.movement)
    ok = np.isfinite(tr.quat_ref[:, 0])
    assert np.all(np.isnan(back.quat_ref[~ok]))
    assert M.total_error(M.error_quat(back.quat_ref[ok], tr.quat_ref[ok])).max() < 1e-9


def test_trial_csv_with_rate_and_without_mag(tmp_path):
    tr = make_trial(n=300, mag=False)
    p = tmp_path / "r.csv"
    data = np.hstack([tr.gyr, tr.acc, tr.quat_ref])
    p.write_text("# ref_frame: NED\n# rate: 100\ngyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,q_w,q_x,q_y,q_z\n" +
                 "\n".join(",".join(f"{x:.17g}" for x in row) for row in data) + "\n")
    back = T.load_trial(p)
    assert back.mag is None and not back.has_mag and back.movement.all()
    np.testing.assert_allclose(back.t, tr.t, atol=1e-12)


def test_trial_errors(tmp_path):
    tr = make_trial(n=300)
    p = T.save_trial(tr, tmp_path / "a.h5")
    import h5py
    with h5py.File(p, "a") as f:
        del f.attrs["ref_frame"]
    with pytest.raises(ValueError, match="ref_frame NED or ENU"):
        T.load_trial(p)
    assert T.load_trial(p, ref_frame="ned").quat_ref.shape == (300, 4)
    q = tmp_path / "b.csv"
    q.write_text("# ref_frame: NED\ntime,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,q_w,q_x,q_y\n0,0,0,0,0,0,9,1,0,0\n"
                 "1,0,0,0,0,0,9,1,0,0\n")
    with pytest.raises(ValueError, match="q_z"):
        T.load_trial(q)
    with pytest.raises(ValueError, match="expected NED or ENU"):
        T.load_trial(tmp_path / "a.h5", ref_frame="XYZ")
    with pytest.raises(ValueError, match="unsupported"):
        T.load_trial(_touch(tmp_path / "c.json"))
    with pytest.raises(FileNotFoundError):
        T.load_trial(tmp_path / "none.csv")


def _touch(p):
    p.write_text("{}")
    return p


def test_wrong_reference_frame_is_told(tmp_path):
    tr = make_trial(n=1200)
    p = T.save_trial(tr, tmp_path / "enu.csv", ref_frame="ENU")
    text = p.read_text().replace("# ref_frame: ENU", "# ref_frame: NED")  # the file lies
    p.write_text(text)
    with pytest.warns(T.ReferenceWarning, match="other earth frame"):
        T.load_trial(p)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        good = T.load_trial(p, ref_frame="ENU")  # the option overrides the file
    # a rotated marker frame is not a wrong earth frame
    good.quat_ref = Q.mul(good.quat_ref, rotvec_deg([0, 90, 30]))
    chk = T.check_reference(good)
    assert chk["residual_deg"] < 2 and chk["other_frame_residual_deg"] > 15


# --- the benchmark --------------------------------------------------------------------------
def test_benchmark_on_trials(tmp_path):
    t1, t2 = make_trial(seed=1, name="a"), make_trial(seed=2, name="b", mag=False)
    res = benchmark([t1, t2], ["qekf", "qekf-smoothed", "marg"], ("9D", "6D"))
    assert res.runs == ["qekf 9D", "qekf-smoothed 9D", "marg 9D", "qekf 6D", "qekf-smoothed 6D", "marg 6D"]
    assert set(res.trials["synthetic/b"]["results"]) == {"qekf 6D", "qekf-smoothed 6D", "marg 6D"}
    assert any("without a magnetometer" in n for n in res.notes)
    for r, figs in res.trials["synthetic/a"]["results"].items():
        assert figs["total"] < 2.0, r
        assert figs["total"] ** 2 == pytest.approx(figs["heading"] ** 2 + figs["inclination"] ** 2, rel=0.3)
    m = res.mean("synthetic")
    assert m["qekf 6D"]["total"] == pytest.approx(np.mean([res.trials[k]["results"]["qekf 6D"]["total"]
                                                           for k in res.trials]))
    assert m["qekf 9D"]["trials"] == 1 and "within_3sigma" in m["qekf 9D"]
    assert res.groups("synthetic")["g"]["trials"] == ["synthetic/a", "synthetic/b"]
    assert res.score("qekf 6D") == pytest.approx(m["qekf 6D"]["total"])
    text = res.table()
    assert "9D: total RMSE" in text and "6D: total RMSE" in text and "synthetic mean heading" in text
    d = json.loads(json.dumps(res.to_dict()))
    assert d["datasets"]["synthetic"]["mean"]["marg 6D"]["total"] == pytest.approx(m["marg 6D"]["total"])


def test_benchmark_executor_and_params_give_the_same(tmp_path):
    t1 = make_trial(seed=3, name="c")
    serial = benchmark([t1], ["qekf"], ("6D",), params={"qekf": {"acc_sigma": 0.2}})
    with ThreadPoolExecutor(2) as ex:
        par = benchmark([t1], ["qekf"], ("6D",), params={"qekf": {"acc_sigma": 0.2}}, executor=ex)
    assert serial.to_dict()["trials"] == par.to_dict()["trials"]
    default = benchmark([t1], ["qekf"], ("6D",))
    assert default.trials["synthetic/c"]["results"]["qekf 6D"]["total"] != \
        serial.trials["synthetic/c"]["results"]["qekf 6D"]["total"]
    with pytest.raises(ValueError, match="params"):
        benchmark([t1], ["qekf"], params={"vqf": {}})
    with pytest.raises(ValueError, match="modes"):
        benchmark([t1], ["qekf"], ("3D",))


def test_peer_cache(tmp_path):
    pytest.importorskip("vqf")
    t1 = make_trial(seed=5, name="d")
    a = evaluate_run(t1, "vqf", "6D", cache_dir=tmp_path)
    files = list(tmp_path.glob("vqf_6D_*.npy"))
    assert len(files) == 1
    b = evaluate_run(t1, "vqf", "6D", cache_dir=tmp_path)
    assert a == b
    np.save(files[0], Q.identity(len(t1)))  # a planted estimate: the second run reads the file
    c = evaluate_run(t1, "vqf", "6D", cache_dir=tmp_path)
    assert c["total"] > 5 * a["total"]
    assert evaluate_run(t1, "vqf", "9D", cache_dir=tmp_path) != c and len(list(tmp_path.glob("*.npy"))) == 2


def test_resolve_sources(tmp_path):
    T.save_trial(make_trial(n=300), tmp_path / "x.csv")
    T.save_trial(make_trial(n=300), tmp_path / "y.h5")
    specs = resolve_sources([str(tmp_path), "sim:fast_pendulum:2"])
    assert [s[0] for s in specs] == ["file", "file", "sim"] and specs[2][1:] == ("fast_pendulum", 2, "rest")
    with pytest.raises(ValueError, match="unknown scenario"):
        resolve_sources(["sim:nope"])
    with pytest.raises(FileNotFoundError):
        resolve_sources([str(tmp_path / "missing")])
    specs = resolve_sources(["sim"])
    from quatnav.sim import FAST_MOTION
    assert [(s[1], s[2]) for s in specs] == list(FAST_MOTION) and {s[3] for s in specs} == {"rest"}
    specs = resolve_sources(["sim-moving", "sim-moving:fast_shaking:3"])
    assert [(s[1], s[2]) for s in specs] == [*FAST_MOTION, ("fast_shaking", 3)]
    assert {s[3] for s in specs} == {"moving"}
    with pytest.raises(ValueError, match="unknown scenario"):
        resolve_sources(["sim-moving:nope"])


def test_cli_eval_on_own_trials(tmp_path, capsys):
    T.save_trial(make_trial(n=1500, seed=6), tmp_path / "mine.csv", ref_frame="ENU")
    out = tmp_path / "r.json"
    rc = quatnav.cli.main(["eval", str(tmp_path / "mine.csv"), "--filters", "qekf", "--peers", "none",
                           "--modes", "6d", "--json", str(out), "--quiet"])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["runs"] == ["qekf 6D"] and data["trials"][f"{tmp_path.name}/mine"]["results"]["qekf 6D"]["total"] < 2
    assert "6D: total RMSE" in capsys.readouterr().out


def test_cli_eval_checks_a_trial_file_once(tmp_path, capsys):
    """A user's trial in deg/s and g: one warning line each, named by the file (not one per run);
    the run goes on."""
    tr = make_trial(n=1500, seed=7)
    tr.gyr, tr.acc = np.degrees(tr.gyr), tr.acc / 9.80665
    T.save_trial(tr, tmp_path / "units.csv")
    with pytest.warns(quatnav.UnitWarning) as w:
        T.load_trial(tmp_path / "units.csv")
    assert sorted(str(x.message).split(": ", 1)[1][:14] for x in w) == ["accel looks li", "gyro looks lik"]
    rc = quatnav.cli.main(["eval", str(tmp_path / "units.csv"), "--filters", "qekf,marg", "--peers", "none",
                           "--quiet"])
    assert rc == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ": warning: " in ln]
    assert len(lines) == 2 and all("units.csv" in ln for ln in lines), lines
    assert "gyro looks like deg/s" in lines[0] and "accel looks like g" in lines[1], lines
    good = make_trial(n=600, seed=8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert T.check_trial(good) == []


@pytest.mark.parametrize("args, expect", [
    ((), "give a source"),
    (("nowhere",), "nowhere: no such file or folder"),
    (("sim:nope",), "unknown scenario 'nope'"),
    (("sim-moving:fast_pendulum:x",), "the seed must be"),
    (("broad", "--modes", "7d"), "--modes 7d"),
])
def test_cli_eval_errors(args, expect, capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("QUATNAV_DATA", str(DATA))
    rc = quatnav.cli.main(["eval", *args, "--peers", "none", "--quiet"])
    assert rc == 2
    assert expect in capsys.readouterr().err


# --- simulated trials -----------------------------------------------------------------------
def test_scenario_trial_reference_is_the_imu_frame():
    from quatnav.datasets.simulated import scenario_trial
    tr = scenario_trial("car_city", 0)  # an IMU mounted rotated: the reference is the IMU's attitude
    from quatnav.sim import make_scenario
    s = make_scenario("car_city", seed=0)
    k = 100
    f_n = Q.rotate(tr.quat_ref[k], s.imu.accel[k] - s.imu.accel_bias[k])
    assert f_n[2] == pytest.approx(-9.8, abs=0.3)
    assert tr.has_mag and np.isnan(tr.mag).all(axis=1).any()  # 50 Hz field on a 200 Hz IMU
    assert not tr.movement[tr.t < 4.9].any() and tr.movement[-1]


def test_scenario_trial_started_in_the_motion():
    """``start="moving"``: the first rest is cut off (the first sample is already in the swing) and
    every remaining sample is scored; the samples are those of the trial started at rest."""
    from quatnav.datasets.simulated import scenario_trial
    rest = scenario_trial("fast_pendulum", 1)
    moving = scenario_trial("fast_pendulum", 1, start="moving")
    cut = int(np.argmax(rest.movement))
    assert cut > 0 and len(moving.t) == len(rest.t) - cut and moving.movement.all()
    assert np.array_equal(moving.gyr, rest.gyr[cut:]) and np.array_equal(moving.quat_ref, rest.quat_ref[cut:])
    assert np.array_equal(moving.mag, rest.mag[cut:], equal_nan=True)
    first_s = moving.t < moving.t[0] + 1.0  # no rest to start from: the swing within the first second
    assert np.linalg.norm(moving.gyr[first_s], axis=1).max() > np.radians(30)
    assert moving.dataset == "sim-moving" and moving.name.endswith(":moving")
    assert moving.source == "sim-moving:fast_pendulum:1"
    with pytest.raises(ValueError, match="start"):
        scenario_trial("fast_pendulum", 1, start="late")


def test_cli_eval_started_in_the_motion(tmp_path, capsys):
    """The started-in-motion set is a source of ``quatnav eval`` beside the one started at rest:
    its own data set in the tables, the first seconds scored (so a filter's convergence from a
    level guess inside the swing costs it)."""
    out = tmp_path / "r.json"
    rc = quatnav.cli.main(["eval", "sim:fast_shaking", "sim-moving:fast_shaking", "--filters", "qekf",
                           "--peers", "none", "--modes", "9d", "--json", str(out), "--quiet"])
    assert rc == 0
    data = json.loads(out.read_text())
    tr = data["trials"]
    assert set(tr) == {"sim/fast_shaking:0", "sim-moving/fast_shaking:0:moving"}
    at_rest = tr["sim/fast_shaking:0"]["results"]["qekf 9D"]["total"]
    moving = tr["sim-moving/fast_shaking:0:moving"]["results"]["qekf 9D"]["total"]
    assert 0 < at_rest < moving < 10, (at_rest, moving)
    assert "sim-moving mean total" in capsys.readouterr().out
