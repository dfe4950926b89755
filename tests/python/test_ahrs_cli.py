"""``quatnav ahrs run`` and ``quatnav compare``: a simulated rotation written as CSV, filtered by
the command, compared with the truth; the figures equal the Python API's on the same arrays."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import quatnav
from quatnav import cli
from quatnav.evaluation.track_difference import attitude_difference, slerp_at, stats
from quatnav.core import quaternion as Q
from quatnav.demo import rotation_scenario

from conftest import DATA

PACKAGE_DIR = str(Path(quatnav.__file__).resolve().parents[1])
PX4 = DATA / "px4"


@pytest.fixture(scope="module")
def sim(tmp_path_factory):
    d = tmp_path_factory.mktemp("ahrs")
    s = rotation_scenario(n=1500, rate=100.0, seed=2)
    cols = {"time": s.t}
    for i, c in enumerate("xyz"):
        cols[f"gyro_{c}"] = s.gyr[:, i]
    for i, c in enumerate("xyz"):
        cols[f"accel_{c}"] = s.acc[:, i]
    for i, c in enumerate("xyz"):
        cols[f"mag_{c}"] = s.mag[:, i]
    pd.DataFrame(cols).to_csv(d / "imu.csv", index=False, float_format="%.17g")
    truth = {"time": s.t, **{f"q_{c}": s.q_nb[:, i] for i, c in enumerate("wxyz")}}
    pd.DataFrame(truth).to_csv(d / "truth.csv", index=False, float_format="%.17g")
    return s, d


@pytest.mark.parametrize("name,cls", [("qekf", "QuaternionEKF"), ("euler-ekf", "EulerEKF"), ("marg", "MargFilter")])
def test_ahrs_run_equals_api(sim, name, cls):
    s, d = sim
    out = d / f"{name}.csv"
    assert cli.main(["ahrs", "run", "--imu", str(d / "imu.csv"), "--filter", name, "--out", str(out)]) == 0
    df = pd.read_csv(out)
    r = getattr(quatnav, cls)().run(s.gyr, s.acc, s.mag, t=s.t, on_invalid="skip")
    np.testing.assert_allclose(df[["q_w", "q_x", "q_y", "q_z"]].to_numpy(), r.quat, atol=1e-9)
    np.testing.assert_allclose(df["yaw"].to_numpy(), np.degrees(r.euler[:, 2]), atol=1e-7)
    assert (df["flags"].to_numpy() == r.flags).all()
    assert set(df.columns) >= {"time", "roll", "pitch", "gyro_bias_x_deg_s", "flag_names"}
    # compare against the truth = the API's metric on the same arrays
    js = d / f"{name}.json"
    assert cli.main(["compare", str(out), str(d / "truth.csv"), "--json", str(js)]) == 0
    got = json.loads(js.read_text())
    e = attitude_difference(s.t, r.quat, s.t, s.q_nb)
    for k in ("heading", "inclination"):
        assert got[f"attitude_{k}_deg"]["rms"] == pytest.approx(stats(e[f"{k}_deg"])["rms"], rel=1e-6)
    # every filter, MargFilter included (its 1 s accelerometer low-pass is carried by a gyro whose
    # bias it does not estimate; docs/broad.md)
    assert got["attitude_inclination_deg"]["rms"] < 3.0


def test_ahrs_options(sim, tmp_path):
    s, d = sim
    out = tmp_path / "a.csv"
    assert cli.main(["ahrs", "run", "--imu", str(d / "imu.csv"), "--no-mag", "--rate", "50", "--declination", "5",
                     "--out", str(out), "--plot", str(tmp_path / "a.png")]) == 0
    df = pd.read_csv(out)
    assert len(df) == 750
    _figure_ok(tmp_path / "a.png", 900, 500)  # attitude and gyro bias, 10 in wide


@pytest.mark.parametrize("name", ["qekf", "euler-ekf", "marg"])
def test_declination_turns_every_filters_yaw(sim, name, tmp_path):
    """--declination D gives yaw + D from every filter (true north; MargFilter's own declination
    parameter only concerns GPS velocities, so its output is turned like EulerEKF's)."""
    s, d = sim
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    base = ["ahrs", "run", "--imu", str(d / "imu.csv"), "--filter", name]
    assert cli.main(base + ["--out", str(a)]) == 0
    assert cli.main(base + ["--out", str(b), "--declination", "8.1"]) == 0
    dy = (pd.read_csv(b)["yaw"] - pd.read_csv(a)["yaw"] + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(dy.to_numpy()[100:], 8.1, atol=0.05)


def test_times_in_milliseconds_are_refused(sim, tmp_path):
    """The same file with its times in ms: one line naming the unit, exit status 2 (it ran with
    20 s steps before)."""
    s, d = sim
    df = pd.read_csv(d / "imu.csv")
    df["time"] *= 1000.0
    df.to_csv(tmp_path / "ms.csv", index=False)
    r = subprocess.run([sys.executable, "-m", "quatnav", "ahrs", "run", "--imu", str(tmp_path / "ms.csv"), "--out",
                        str(tmp_path / "o.csv")], capture_output=True, text=True, cwd=tmp_path,
                       env={**__import__("os").environ, "PYTHONPATH": PACKAGE_DIR})
    assert r.returncode == 2 and "look like milliseconds" in r.stderr and "Traceback" not in r.stderr, r.stderr


def test_slerp_at():
    q = Q.normalize(np.array([[1.0, 0, 0, 0], [np.cos(0.5), 0, 0, np.sin(0.5)]]))
    mid = slerp_at(np.array([0.5]), np.array([0.0, 1.0]), q)
    np.testing.assert_allclose(mid[0], [np.cos(0.25), 0, 0, np.sin(0.25)], atol=1e-12)


def test_errors_one_line(sim, tmp_path):
    s, d = sim
    g = tmp_path / "gnss.csv"
    g.write_text("time,lat,lon,h\n0,40,-105,1600\n")
    env = {"PYTHONPATH": PACKAGE_DIR, "PATH": "/usr/bin:/bin"}
    p = subprocess.run([sys.executable, "-m", "quatnav", "ahrs", "run", "--log", str(g), "--out", str(tmp_path / "o.csv")],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 2 and "no IMU data" in p.stderr and len(p.stderr.strip().splitlines()) == 1
    p = subprocess.run([sys.executable, "-m", "quatnav", "compare", str(d / "truth.csv"), str(g)],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 2 and "Traceback" not in p.stderr


def test_px4_against_its_own_estimate(tmp_path):
    pytest.importorskip("pyulog")
    f = PX4 / "sample_appended_multiple.ulg"
    if not f.exists():
        pytest.skip(f"{PX4} absent")
    out, js = tmp_path / "px4.csv", tmp_path / "c.json"
    assert cli.main(["ahrs", "run", "--log", str(f), "--filter", "qekf", "--out", str(out),
                     "--plot", str(tmp_path / "p.png")]) == 0
    assert cli.main(["compare", str(out), str(f), "--json", str(js)]) == 0
    got = json.loads(js.read_text())
    assert got["attitude_inclination_deg"]["rms"] < 2.0 and got["attitude_heading_deg"]["rms"] < 5.0


def test_parquet_output(sim, tmp_path):
    pytest.importorskip("pyarrow")
    s, d = sim
    out, js = tmp_path / "a.parquet", tmp_path / "c.json"
    assert cli.main(["ahrs", "run", "--imu", str(d / "imu.csv"), "--out", str(out)]) == 0
    df = pd.read_parquet(out)
    assert len(df) == len(s.t) and "flag_names" in df
    assert cli.main(["compare", str(out), str(d / "truth.csv"), "--json", str(js)]) == 0
    assert json.loads(js.read_text())["attitude_inclination_deg"]["n"] == len(s.t)
    # quatnav.io reads it as the CSV of its columns, every digit kept
    log = quatnav.io.read(out)
    assert log.format == "parquet" and log.source == str(out) and log.reference is not None
    np.testing.assert_array_equal(log.reference.quat, df[["q_w", "q_x", "q_y", "q_z"]].to_numpy())


def test_ahrs_run_applies_a_calibration(sim, tmp_path):
    # a gyro offset and a magnetometer hard iron written to a calibration file: the command
    # filters the calibrated samples, i.e. equals the API on cal.apply(...) of the same arrays
    from quatnav import calibration as cal
    s, d = sim
    path = tmp_path / "cal.toml"
    cal.save_calibration(path, gyro=cal.SensorCalibration("gyro", "offset", np.array([0.01, -0.02, 0.005]), np.eye(3)),
                         mag=cal.SensorCalibration("mag", "offset", np.array([3.0, -2.0, 1.0]), np.eye(3)))
    out = tmp_path / "q.csv"
    assert cli.main(["ahrs", "run", "--imu", str(d / "imu.csv"), "--calibration", str(path), "--out", str(out)]) == 0
    g, a, m = cal.apply(cal.load_calibration(path), gyr=s.gyr, acc=s.acc, mag=s.mag)
    assert not np.allclose(g, s.gyr) and not np.allclose(m, s.mag)
    r = quatnav.QuaternionEKF().run(g, a, m, t=s.t, on_invalid="skip")
    np.testing.assert_allclose(pd.read_csv(out)[["q_w", "q_x", "q_y", "q_z"]].to_numpy(), r.quat, atol=1e-9)


def test_ahrs_run_json_summary(sim, tmp_path, capsys):
    """--json FILE writes the summary, as ins run's does; --json - prints only the JSON on stdout
    (the other output goes to stderr)."""
    s, d = sim
    out, js = tmp_path / "a.csv", tmp_path / "a.json"
    assert cli.main(["ahrs", "run", "--imu", str(d / "imu.csv"), "--out", str(out), "--json", str(js)]) == 0
    got = json.loads(js.read_text())
    assert got["output"] == str(out) and got["rows"] == got["imu_samples"] == len(s.t)
    assert got["filter"] == "QuaternionEKF" and got["magnetometer"] is True and got["smoothed"] is False
    assert got["declination_rad"] == 0.0 and got["warnings"] == []
    r = quatnav.QuaternionEKF().run(s.gyr, s.acc, s.mag, t=s.t, on_invalid="skip")
    assert got["flags"] == {n: int(r.flag(n).sum()) for n in r.flags_seen()}
    capsys.readouterr()
    assert cli.main(["ahrs", "run", "--imu", str(d / "imu.csv"), "--out", str(out), "--filter", "euler-ekf",
                     "--no-mag", "--declination", "3", "--json", "-"]) == 0
    cap = capsys.readouterr()
    got = json.loads(cap.out)
    assert got["filter"] == "EulerEKF" and got["magnetometer"] is False
    assert got["declination_rad"] == pytest.approx(np.radians(3.0))
    assert f"wrote {out}" in cap.err


def test_ahrs_run_help_documents_json():
    p = subprocess.run([sys.executable, "-m", "quatnav", "ahrs", "run", "-h"], capture_output=True, text=True,
                       env={"PYTHONPATH": PACKAGE_DIR, "PATH": "/usr/bin:/bin"})
    assert p.returncode == 0 and "--json FILE" in p.stdout and "--json - prints it" in p.stdout


def test_no_mag_does_not_claim_a_magnetometer(data_dir, tmp_path, capsys):
    """The SITL ULog has a magnetometer: without --no-mag the command says where it was read from;
    with --no-mag it says nothing of the kind (neither printed nor in the --json notes)."""
    pytest.importorskip("pyulog")
    f = data_dir / "px4" / "sample_logging_tagged_and_default_params.ulg"
    out, js = tmp_path / "a.csv", tmp_path / "a.json"
    assert cli.main(["ahrs", "run", "--log", str(f), "--out", str(out)]) == 0
    assert "note: magnetometer from " in capsys.readouterr().out
    assert cli.main(["ahrs", "run", "--log", str(f), "--out", str(out), "--no-mag", "--json", str(js)]) == 0
    text = capsys.readouterr().out
    assert "(no magnetometer: heading free)" in text and "magnetometer from" not in text
    got = json.loads(js.read_text())
    assert got["magnetometer"] is False and not any("magnetometer" in n for n in got.get("notes", []))


def _figure_ok(path, min_w, min_h):
    """A PNG of a real figure: its size, and more than a few colours (not blank)."""
    import matplotlib.image as mpimg
    img = mpimg.imread(path)
    assert img.shape[1] >= min_w and img.shape[0] >= min_h, img.shape
    assert len(np.unique((img[..., :3] * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50, "blank figure"
