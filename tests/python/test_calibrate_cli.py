"""``quatnav calibrate mag|acc|gyro`` on CSV logs, and ``--calibration FILE`` of ``ins run``."""
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scipy")
pytest.importorskip("pandas")
import quatnav  # noqa: E402
import quatnav.calibration as cal  # noqa: E402

PYTHON_DIR = str(Path(quatnav.__file__).resolve().parents[1])
HEADER = "time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,mag_x,mag_y,mag_z"


def run(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("QUATNAV_TRACEBACK", None)
    return subprocess.run([sys.executable, "-m", "quatnav", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=120)


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    d = tmp_path_factory.mktemp("cal")
    rng = np.random.default_rng(0)
    dt = 0.01
    # six static poses joined by motion, gyro bias, magnetometer hard iron on random directions
    six = np.array([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)], float)
    b_acc, b_gyr, hard = np.array([0.1, -0.05, 0.2]), np.array([0.01, -0.02, 0.004]), np.array([20.0, -10.0, 5.0])
    acc, gyr = [], []
    for f in six:
        acc.append(np.tile(9.80665 * f + b_acc, (300, 1)) + rng.normal(scale=0.003, size=(300, 3)))
        gyr.append(np.tile(b_gyr, (300, 1)) + rng.normal(scale=1e-3, size=(300, 3)))
        acc.append(rng.normal(scale=2.0, size=(100, 3)) + 9.80665 * f)
        gyr.append(rng.normal(scale=1.0, size=(100, 3)))
    acc, gyr = np.concatenate(acc), np.concatenate(gyr)
    n = len(acc)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    mag = 50.0 * u + hard + rng.normal(scale=0.2, size=(n, 3))
    t = np.arange(n) * dt
    np.savetxt(d / "log.csv", np.column_stack([t, gyr, acc, mag]), delimiter=",", header=HEADER, comments="",
               fmt="%.9g")
    np.savetxt(d / "nomag.csv", np.column_stack([t, gyr, acc]), delimiter=",", header=HEADER.rsplit(",", 3)[0],
               comments="", fmt="%.9g")
    np.savetxt(d / "nomagz.csv", np.column_stack([t, gyr, acc, mag[:, :2]]), delimiter=",",
               header=HEADER.rsplit(",", 1)[0], comments="", fmt="%.9g")
    return d, b_acc, b_gyr, hard


def test_calibrate_all_three_into_one_file(logs):
    d, b_acc, b_gyr, hard = logs
    out = d / "cal.toml"
    for sensor in ("mag", "acc", "gyro"):
        p = run("calibrate", sensor, d / "log.csv", "--out", out)
        assert p.returncode == 0, p.stderr
        assert f"wrote {out}" in p.stdout and p.stdout.startswith(sensor)
    doc = tomllib.loads(out.read_text())
    assert set(doc) == {"mag", "acc", "gyro"}
    c = cal.load_calibration(out)
    np.testing.assert_allclose(c.mag.offset, hard, atol=0.1)
    np.testing.assert_allclose(c.acc.offset, b_acc, atol=2e-3)
    np.testing.assert_allclose(c.gyro.offset, b_gyr, atol=2e-4)
    assert c.acc.info["poses"] == 6 and c.mag.model == "full"


def test_calibrate_plot_and_json(logs, tmp_path):
    pytest.importorskip("matplotlib")
    d = logs[0]
    p = run("calibrate", "mag", d / "log.csv", "--out", tmp_path / "c.toml", "--model", "offset",
            "--plot", tmp_path / "m.png", "--json", tmp_path / "m.json")
    assert p.returncode == 0, p.stderr
    import json
    import matplotlib.image as mpimg
    img = mpimg.imread(tmp_path / "m.png")
    assert img.shape[1] >= 800 and len(np.unique((img[..., :3] * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50
    got = json.loads((tmp_path / "m.json").read_text())
    saved = tomllib.loads((tmp_path / "c.toml").read_text())["mag"]
    assert got["sensor"] == "mag" and got["model"] == "offset" and got["warnings"] == []
    np.testing.assert_allclose(got["offset"], saved["offset"], rtol=1e-12)


@pytest.mark.parametrize("args, expect", [
    (("mag", "nomag.csv"), "no mag_x"),
    (("mag", "nomagz.csv"), "no mag_z column (needed by 'calibrate mag'; found time, gyro_x"),
    (("acc", "log.csv", "--model", "full"), "acc models are"),
    (("gyro", "log.csv", "--model", "full"), "--model is for mag and acc"),
    (("mag", "missing.csv"), "cannot open"),
])
def test_calibrate_user_errors_are_one_line(logs, args, expect):
    d = logs[0]
    p = run("calibrate", *args, "--out", "x.toml", cwd=d)
    assert p.returncode == 2, p.stderr
    assert "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert expect in p.stderr


def test_ins_run_takes_a_calibration(logs, tmp_path):
    p = run("ins", "run", "-h")
    assert "--calibration" in p.stdout
    t = np.arange(0, 20.0, 0.01)
    imu = np.column_stack([t, np.zeros((len(t), 5)), np.full(len(t), -9.80665)])
    np.savetxt(tmp_path / "imu.csv", imu, delimiter=",", header=HEADER.rsplit(",", 3)[0], comments="", fmt="%.9g")
    tg = np.arange(0, 20.0, 1.0)
    np.savetxt(tmp_path / "gnss.csv", np.column_stack([tg, np.full(len(tg), 47.0), np.full(len(tg), 8.0),
                                                        np.full(len(tg), 500.0)]),
               delimiter=",", header="time,lat,lon,h", comments="", fmt="%.9g")
    (tmp_path / "bad.toml").write_text("[acc]\noffset = [1]\n")
    base = ("ins", "run", "--imu", tmp_path / "imu.csv", "--gnss", tmp_path / "gnss.csv", "--out", tmp_path / "o.csv")
    p = run(*base, "--calibration", tmp_path / "bad.toml")
    assert p.returncode == 2 and "offset must have 3 numbers" in p.stderr, p.stderr
    cal.save_calibration(tmp_path / "good.toml", acc=cal.SensorCalibration("acc", "diagonal", np.zeros(3),
                                                                             np.eye(3)))
    p = run(*base, "--calibration", tmp_path / "good.toml")
    assert p.returncode in (0, 1) and "wrote" in p.stdout, p.stderr


# --- real logs: any format, a real sensor's noise, one rest detector, hints in the command's syntax --
ULOG = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "px4" / "sample_logging_tagged_and_default_params.ulg"


@pytest.mark.data
def test_calibrate_reads_a_ulog(tmp_path):
    """The PX4 SITL log (11 s on the ground): 'calibrate mag' reads its magnetometer (it said
    'not UTF-8 text') and finds it never turned; 'calibrate gyro' takes the bias over its rest."""
    pytest.importorskip("pyulog")
    if not ULOG.exists():
        pytest.skip(f"no {ULOG}")
    p = run("calibrate", "mag", ULOG, "--out", tmp_path / "c.toml")
    assert p.returncode == 2 and "UTF-8" not in p.stderr and "rotate the sensor" in p.stderr, p.stderr
    p = run("calibrate", "gyro", ULOG, "--out", tmp_path / "c.toml")
    assert p.returncode == 0, p.stderr
    g = tomllib.loads((tmp_path / "c.toml").read_text())["gyro"]
    assert np.abs(g["offset"]).max() < 0.01  # a simulated gyro's bias, rad/s


def test_a_real_accelerometers_poses_are_kept(tmp_path):
    """Six poses with a consumer accelerometer's noise (0.05 m/s^2 per axis, BROAD's): all kept
    (the fixed 0.05 m/s^2 of an ideal sensor rejected them); a pose with motion still rejected."""
    rng = np.random.default_rng(3)
    six = np.array([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)], float)
    acc = []
    for f in six:
        acc.append(np.tile(9.80665 * f + [0.1, -0.05, 0.2], (300, 1)) + rng.normal(scale=0.05, size=(300, 3)))
        acc.append(rng.normal(scale=2.0, size=(100, 3)) + 9.80665 * f)
    acc = np.concatenate(acc)
    t = np.arange(len(acc)) * 0.01
    gyr = rng.normal(scale=0.003, size=acc.shape)
    np.savetxt(tmp_path / "acc.csv", np.column_stack([t, gyr, acc]), delimiter=",", comments="", fmt="%.9g",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    p = run("calibrate", "acc", tmp_path / "acc.csv", "--out", tmp_path / "c.toml")
    assert p.returncode == 0, p.stderr
    assert "6 poses" in p.stdout and "rejected" not in p.stdout, p.stdout
    a = tomllib.loads((tmp_path / "c.toml").read_text())["acc"]
    np.testing.assert_allclose(a["offset"], [0.1, -0.05, 0.2], atol=0.02)


def test_no_rest_hint_in_the_commands_syntax(tmp_path):
    rng = np.random.default_rng(4)
    t = np.arange(3000) * 0.01
    gyr = rng.normal(scale=1.0, size=(len(t), 3))
    acc = rng.normal(scale=3.0, size=(len(t), 3)) + [0.0, 0.0, -9.81]
    np.savetxt(tmp_path / "m.csv", np.column_stack([t, gyr, acc]), delimiter=",", comments="", fmt="%.9g",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    p = run("calibrate", "gyro", tmp_path / "m.csv", "--out", tmp_path / "c.toml")
    assert p.returncode == 2 and "give --rest T0 T1" in p.stderr and "rest=(" not in p.stderr, p.stderr


@pytest.mark.data
def test_broad_rest_found_where_ahrs_run_sees_rest(data_dir, tmp_path):
    """BROAD trial 02 (still for its first 40 s, gyro std 0.0017 rad/s): 'calibrate gyro' found no
    rest; now the longest, and QuaternionEKF's own rest detection (ahrs run's at_rest) agrees on
    it."""
    import scipy.io
    d = data_dir / "broad"
    trials = sorted(d.glob("02_*.mat")) if d.is_dir() else []
    if not trials:
        pytest.skip(f"no BROAD trial 02 in {d}")
    raw = scipy.io.loadmat(trials[0])
    g, a = np.asarray(raw["imu_gyr"], float), np.asarray(raw["imu_acc"], float)
    t = np.arange(len(g)) / float(np.squeeze(raw["sampling_rate"]))
    np.savetxt(tmp_path / "imu.csv", np.column_stack([t, g, a]), delimiter=",", comments="", fmt="%.9g",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    p = run("calibrate", "gyro", tmp_path / "imu.csv", "--out", tmp_path / "c.toml", "--json", tmp_path / "c.json")
    assert p.returncode == 0, p.stderr
    import json
    t0, t1 = json.loads((tmp_path / "c.json").read_text())["rest"]
    assert t1 - t0 > 30.0
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = quatnav.QuaternionEKF().run(g, a, t=t)
    inside = (t >= t0 + 2.0) & (t <= t1)  # after the detector's rest_time
    assert r.flag("at_rest")[inside].mean() > 0.9


def test_allan_says_when_the_floor_was_not_reached(tmp_path):
    """White noise only (the deviation falls to the longest tau): the bias instability is an
    upper bound, and the command says so; with a random walk the floor shows, and no warning."""
    import json
    rng = np.random.default_rng(0)
    n, fs = 60000, 100.0
    t = np.arange(n) / fs
    hdr = "time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z"
    white = 1e-3 * rng.standard_normal((n, 3))
    acc_rw = np.cumsum(2e-4 * rng.standard_normal((n, 3)), axis=0) + [0.0, 0.0, -9.81]
    for name, gyr, expect in (("white", white, False), ("walk", white + np.cumsum(2e-5 * rng.standard_normal((n, 3)),
                                                                                  axis=0), True)):
        f = tmp_path / f"{name}.csv"
        np.savetxt(f, np.column_stack([t, gyr, acc_rw + 2e-3 * rng.standard_normal((n, 3))]), delimiter=",",
                   header=hdr, comments="", fmt="%.9g")
        p = run("allan", f, "--out", tmp_path / "n.toml", "--json", tmp_path / "n.json")
        assert p.returncode == 0, p.stderr
        got = json.loads((tmp_path / "n.json").read_text())
        assert [a["floor_reached"] for a in got["gyro"]] == [expect] * 3
        if expect:
            assert "floor was not reached" not in p.stderr, p.stderr
        else:
            assert "gyro x, gyro y, gyro z still falls at the longest tau" in p.stderr
            assert "bias instability <= " in p.stdout
