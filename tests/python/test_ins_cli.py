"""``quatnav ins run``: CSV files written from the simulator's paper-004 walk, run in-process and
once as a subprocess, checked against the truth; every input-error path; the files of
``quatnav simulate --csv DIR`` run unchanged; IMU gaps coasted; plausibility warnings."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import quatnav
from quatnav import cli
from quatnav.core import earth
from quatnav.plausibility import AxesWarning, UnitWarning

pytest.importorskip("pandas")
from quatnav.sim.scenarios import make_scenario  # noqa: E402

LEVER = (0.1, 0.0, -0.1)
PYTHON_DIR = str(Path(quatnav.__file__).resolve().parent.parent)


def _write(path, header, cols, fmt="%.9f"):
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(header), comments="", fmt=fmt)
    return str(path)


@pytest.fixture(scope="module")
def walk():
    return make_scenario("paper004_walk", seed=0)


@pytest.fixture(scope="module")
def files(walk, tmp_path_factory):
    s, d = walk, tmp_path_factory.mktemp("ins")
    g = s.gps
    # columns in a different order from the documentation, and an extra column
    imu = _write(d / "imu.csv", ["accel_x", "accel_y", "accel_z", "time", "gyro_x", "gyro_y", "gyro_z", "temp"],
                 [*s.imu.accel.T, s.imu.t, *s.imu.gyro.T, np.full(len(s.imu.t), 25.0)], fmt="%.12g")
    gnss = _write(d / "gnss.csv", ["time", "lat", "lon", "h", "v_n", "v_e", "v_d"],
                  [g.t_valid, np.degrees(g.lat), np.degrees(g.lon), g.h, *g.v_n.T], fmt="%.12f")
    baro = _write(d / "baro.csv", ["time", "h"], [s.baro.t, s.baro.h])
    compass = _write(d / "compass.csv", ["time", "heading"], [s.compass.t, np.degrees(s.compass.yaw)])
    cfg = d / "cfg.toml"
    cfg.write_text("# antenna 10 cm forward, 10 cm up\n[filter]\nlever_arm_b = [0.1, 0.0, -0.1]\n"
                   "gps_pos_sigma_h = 2.5\ngate_gps_pos = 21.108\n")
    return dict(dir=d, imu=imu, gnss=gnss, baro=baro, compass=compass, config=str(cfg))


def _args(fl, out):
    return ["ins", "run", "--imu", fl["imu"], "--gnss", fl["gnss"], "--baro", fl["baro"], "--compass", fl["compass"],
            "--config", fl["config"], "--out", str(out)]


def _read(out):
    with open(out) as fh:
        header = fh.readline().strip().split(",")
    return header, np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)


def test_run_in_process_against_truth_and_api(walk, files, capsys):
    s = walk
    out = files["dir"] / "out.csv"
    assert cli.main(_args(files, out)) == 0
    cap = capsys.readouterr()
    assert "wrote" in cap.out and cap.err == ""  # consistent input: no warning
    header, a = _read(out)
    from quatnav.pipeline import OUTPUT_COLUMNS
    assert tuple(header) == OUTPUT_COLUMNS
    c = {n: a[:, i] for i, n in enumerate(header)}
    # same numbers as the Python API on the same data (the files' printed digits: the rest
    # detector's thresholds make the result depend on them discontinuously)
    def back(path, cols):
        tab = np.genfromtxt(path, delimiter=",", names=True)
        return np.column_stack([tab[c] for c in cols])
    imu = back(files["imu"], ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"))
    gn = back(files["gnss"], ("time", "lat", "lon", "h", "v_n", "v_e", "v_d"))
    ba, co = back(files["baro"], ("time", "h")), back(files["compass"], ("time", "heading"))
    r = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(
        imu[:, 1:4], imu[:, 4:7], t=imu[:, 0],
        gps_pos=quatnav.Aid(gn[:, 0], np.column_stack([np.radians(gn[:, 1:3]), gn[:, 3]])),
        gps_vel=quatnav.Aid(gn[:, 0], gn[:, 4:7]), baro=quatnav.Aid(ba[:, 0], ba[:, 1]),
        compass=quatnav.Aid(co[:, 0], np.radians(co[:, 1])))
    nav = r.navigating
    assert len(a) == nav.sum() > 0.9 * len(s.imu.t)
    np.testing.assert_allclose(c["time"], r.t[nav], atol=1e-6)
    np.testing.assert_allclose(np.radians(c["lat"]), r.lat[nav], atol=1e-9)  # ~1 cm
    np.testing.assert_allclose(c["yaw"], np.degrees(r.euler[nav, 2]), atol=1e-3)
    np.testing.assert_allclose(c["gyro_bias_z_deg_h"], np.degrees(r.bias[nav, 2]) * 3600, rtol=1e-5)
    np.testing.assert_allclose(c["sigma_psi_d_deg"], np.degrees(r.sigma[nav, 8]), rtol=1e-5)
    # against the truth: horizontal position within the filter's own sigma
    i = np.searchsorted(s.truth.t, c["time"])
    assert np.allclose(s.truth.t[i], c["time"], atol=1e-6)
    lat, h = s.truth.lat[i], s.truth.h[i]
    R_M, R_N = earth.radii(lat)
    dn = (np.radians(c["lat"]) - lat) * (R_M + h)
    de = (np.radians(c["lon"]) - s.truth.lon[i]) * (R_N + h) * np.cos(lat)
    rms = np.sqrt(np.mean(dn ** 2 + de ** 2))
    sig = np.sqrt(np.mean(c["sigma_n"] ** 2 + c["sigma_e"] ** 2))
    assert rms < 3.0 * sig, (rms, sig)  # 2-dof: E[err^2] = sig^2 when consistent
    assert rms < 2.0  # GPS 2.5 m per axis; the paper's bound is 30 m
    yaw_err = np.angle(np.exp(1j * np.radians(c["yaw"] - np.degrees(s.truth.rpy[i, 2]))))
    assert np.degrees(np.abs(yaw_err[len(i) // 5:])).max() < 5.0
    assert np.all(np.isfinite(a))


def test_run_as_subprocess(files):
    out = files["dir"] / "out_sub.csv"
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-m", "quatnav", "ins", "run", "--imu", files["imu"], "--gnss", files["gnss"],
                        "--out", str(out)], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    header, a = _read(out)
    assert header[:10] == ["time", "lat", "lon", "h", "v_n", "v_e", "v_d", "roll", "pitch", "yaw"]
    assert len(a) > 1000
    # an input error from a subprocess: one line, no traceback, exit status 2
    p = subprocess.run([sys.executable, "-m", "quatnav", "ins", "run", "--imu", files["gnss"], "--gnss", files["gnss"],
                        "--out", str(out)], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1
    assert "missing column 'gyro_x'" in p.stderr


def test_help_documents_the_columns(capsys):
    with pytest.raises(SystemExit):
        cli.main(["ins", "run", "--help"])
    h = capsys.readouterr().out
    for name in ("gyro_x", "accel_z", "lat", "lon", "v_n", "sigma_vn", "heading", "[filter]",
                 "gyro_bias_{x,y,z}_deg_h", "accel_bias_{x,y,z}_m_s2", "sigma_psi_{n,e,d}_deg"):
        assert name in h, name


def _lines(path):
    return Path(path).read_text().splitlines()


def _bad(tmp_path, fl, name, lines):
    p = tmp_path / f"bad_{name}.csv"
    p.write_text("\n".join(lines) + "\n")
    return dict(fl, **{name: str(p)})


def _error(capsys, fl, out):
    rc = cli.main(_args(fl, out))
    err = capsys.readouterr().err.strip()
    assert rc == 2
    assert len(err.splitlines()) == 1 and err.startswith("quatnav ins run: error: ")
    return err


def test_input_errors_name_file_line_and_column(files, tmp_path, capsys):
    out = tmp_path / "o.csv"
    imu = _lines(files["imu"])
    # missing column
    hdr = imu[0].replace("gyro_y", "gyro_yy")
    err = _error(capsys, _bad(tmp_path, files, "imu", [hdr] + imu[1:50]), out)
    assert "bad_imu.csv" in err and "line 1" in err and "'gyro_y'" in err and "missing column" in err
    # unsorted times (IMU time is the 4th column)
    rows = imu[:50]
    rows[10], rows[11] = rows[11], rows[10]
    err = _error(capsys, _bad(tmp_path, files, "imu", rows), out)
    assert "line 12" in err and "'time'" in err and "backwards" in err
    # duplicate time in the GNSS
    g = _lines(files["gnss"])
    g[6] = g[5]
    err = _error(capsys, _bad(tmp_path, files, "gnss", g), out)
    assert "bad_gnss.csv" in err and "line 7" in err and "duplicate time" in err
    # NaN in a required column
    g = _lines(files["gnss"])
    f = g[3].split(",")
    f[1] = "nan"
    g[3] = ",".join(f)
    err = _error(capsys, _bad(tmp_path, files, "gnss", g), out)
    assert "line 4" in err and "'lat'" in err and "not a finite number" in err
    # empty cell in a required column, text in a numeric one
    b = _lines(files["baro"])
    b[20] = b[20].split(",")[0] + ","
    err = _error(capsys, _bad(tmp_path, files, "baro", b), out)
    assert "bad_baro.csv" in err and "line 21" in err and "'h'" in err and "empty" in err
    c = _lines(files["compass"])
    c[2] = c[2].split(",")[0] + ",north"
    err = _error(capsys, _bad(tmp_path, files, "compass", c), out)
    assert "line 3" in err and "'heading'" in err and "'north'" in err
    # a velocity given in part
    g = _lines(files["gnss"])
    f = g[8].split(",")
    f[5] = ""
    g[8] = ",".join(f)
    err = _error(capsys, _bad(tmp_path, files, "gnss", g), out)
    assert "line 9" in err and "'v_e'" in err
    # latitude out of range (radians given by mistake is fine; 95 deg is not)
    g = _lines(files["gnss"])
    f = g[2].split(",")
    f[1] = "95.0"
    g[2] = ",".join(f)
    err = _error(capsys, _bad(tmp_path, files, "gnss", g), out)
    assert "line 3" in err and "'lat'" in err
    # missing file, empty file
    err = _error(capsys, dict(files, baro=str(tmp_path / "nope.csv")), out)
    assert "nope.csv" in err and "cannot open" in err
    err = _error(capsys, _bad(tmp_path, files, "compass", []), out)
    assert "empty file" in err


def test_config_errors(files, tmp_path, capsys):
    out = tmp_path / "o.csv"
    for text, expect in (("[filter]\ngyro_noize = 1e-3\n", "unknown parameter 'gyro_noize'"),
                         ("[filter]\nlever_arm_b = [0.1, 0.0]\n", "lever_arm_b must be a list of 3"),
                         ("[filter]\ngyro_noise = 'big'\n", "gyro_noise must be a number"),
                         ("[filter]\ngyro_noise = -1.0\n", "gyro_noise"),
                         ("[filters]\ngyro_noise = 1.0\n", "'filters'"),
                         ("[filter\n", "not valid TOML")):
        cfg = tmp_path / "c.toml"
        cfg.write_text(text)
        err = _error(capsys, dict(files, config=str(cfg)), out)
        assert "c.toml" in err and expect in err, (text, err)


def test_no_navigation_exits_1(files, tmp_path, capsys):
    # GNSS fixes all before the IMU starts: navigation never starts
    g = _lines(files["gnss"])
    out = tmp_path / "o.csv"
    fl = _bad(tmp_path, files, "gnss", [g[0], "-5.0" + g[1][g[1].index(","):]])
    assert cli.main(_args(fl, out)) == 1
    assert "navigation never started" in capsys.readouterr().out
    from quatnav.pipeline import OUTPUT_COLUMNS
    with open(out) as fh:
        assert fh.read().splitlines() == [",".join(OUTPUT_COLUMNS)]


# --- simulate --csv DIR -> ins run ---------------------------------------------------------------
def test_simulate_csv_dir_runs_through_ins_run(tmp_path, capsys):
    """The files of 'quatnav simulate NAME --csv DIR' are the input of 'quatnav ins run' as they are;
    its output against the simulated truth (truth.csv) is within the filter's own accuracy."""
    d = tmp_path / "run"
    assert cli.main(["simulate", "paper004_walk", "--seed", "3", "--csv", str(d)]) == 0
    for f in ("imu.csv", "gnss.csv", "baro.csv", "compass.csv", "config.toml", "truth.csv"):
        assert (d / f).stat().st_size > 0, f
    out = d / "out.csv"
    capsys.readouterr()
    assert cli.main(["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"), "--baro",
                     str(d / "baro.csv"), "--compass", str(d / "compass.csv"), "--config", str(d / "config.toml"),
                     "--out", str(out)]) == 0
    assert capsys.readouterr().err == ""  # no plausibility warning on consistent data
    header, a = _read(out)
    c = {n: a[:, i] for i, n in enumerate(header)}
    th, tr = _read(d / "truth.csv")
    assert th == ["time", "lat", "lon", "h", "v_n", "v_e", "v_d", "roll", "pitch", "yaw"]
    i = np.searchsorted(tr[:, 0], c["time"])
    assert np.allclose(tr[i, 0], c["time"], atol=1e-6)
    lat = np.radians(tr[i, 1])
    R_M, R_N = earth.radii(lat)
    dn = np.radians(c["lat"] - tr[i, 1]) * (R_M + tr[i, 3])
    de = np.radians(c["lon"] - tr[i, 2]) * (R_N + tr[i, 3]) * np.cos(lat)
    assert len(a) > 0.9 * len(tr)
    assert np.sqrt(np.mean(dn ** 2 + de ** 2)) < 2.0  # GNSS 2.5 m per axis
    dv = np.column_stack([c[k] for k in ("v_n", "v_e", "v_d")]) - tr[i, 4:7]
    assert np.sqrt(np.mean(np.sum(dv ** 2, axis=1))) < 0.3
    yaw_err = np.degrees(np.angle(np.exp(1j * np.radians(c["yaw"] - tr[i, 9]))))
    assert np.abs(yaw_err[len(i) // 5:]).max() < 5.0


# --- gaps and plausibility warnings ----------------------------------------------------------------
def _imu_table(fl):
    lines = _lines(fl["imu"])
    header = lines[0].split(",")
    return header, np.loadtxt(fl["imu"], delimiter=",", skiprows=1)


def _write_imu(tmp_path, fl, header, a, name="imu_mod.csv"):
    p = _write(tmp_path / name, header, a.T, fmt="%.12g")
    return dict(fl, imu=p)


def _warnings(capsys):
    err = capsys.readouterr().err
    assert ": error: " not in err, err
    return [ln for ln in err.splitlines() if ln.startswith("quatnav ins run: warning: ")]


def test_gap_is_coasted_and_reported_with_file_lines(walk, files, tmp_path, capsys):
    header, a = _imu_table(files)
    k0 = 2500  # drop 3 s (150 samples at 50 Hz) in the middle of the walk
    b = np.delete(a, np.s_[k0:k0 + 150], axis=0)
    fl = _write_imu(tmp_path, files, header, b)
    out = tmp_path / "o.csv"
    assert cli.main(_args(fl, out)) == 0
    w = _warnings(capsys)
    assert len(w) == 1 and f"lines {k0 + 1}-{k0 + 2}: 3.02 s" in w[0] and "coasted" in w[0], w
    _, o = _read(out)
    t_in = b[:, header.index("time")]
    assert np.all(np.isin(o[:, 0].round(6), t_in.round(6)))  # one row per file row, none for the coasting steps
    s = walk
    i = np.searchsorted(s.truth.t, o[:, 0])
    lat = s.truth.lat[i]
    R_M, R_N = earth.radii(lat)
    dn = (np.radians(o[:, 1]) - lat) * R_M
    de = (np.radians(o[:, 2]) - s.truth.lon[i]) * R_N * np.cos(lat)
    assert np.sqrt(np.mean(dn ** 2 + de ** 2)) < 3.0  # the fixes during the gap still hold the position


def _text(w):
    """A check's warning as its message (None: no warning)."""
    return None if w is None else str(w)


def test_no_warnings_on_the_simulated_scenarios():
    from quatnav.plausibility import plausibility_warnings
    for name in ("paper004_static", "paper004_turntable", "paper004_walk", "paper002_straight_then_circle"):
        s = make_scenario(name, seed=1)
        g = s.gps
        assert plausibility_warnings(s.imu.t, s.imu.gyro, s.imu.accel, g.t_valid, np.degrees(g.lat),
                                     np.degrees(g.lon)) == [], name


@pytest.mark.parametrize("change, expect", [
    ("gyro_deg", "gyro_x/y/z look like deg/s"),
    ("accel_g", "accel_x/y/z look like g, not m/s^2"),
    ("accel_mg", "look like milli-g"),
    ("z_up", "gravity appears on +z"),
    ("x_down", "gravity appears on +x"),
])
def test_imu_plausibility_warnings(files, tmp_path, capsys, change, expect):
    header, a = _imu_table(files)
    g = [header.index(f"gyro_{x}") for x in "xyz"]
    f = [header.index(f"accel_{x}") for x in "xyz"]
    if change == "gyro_deg":
        a[:, g] = np.degrees(a[:, g])
    elif change == "accel_g":
        a[:, f] /= 9.80665
    elif change == "accel_mg":
        a[:, f] *= 1000 / 9.80665
    elif change == "z_up":  # forward-left-up
        a[:, [g[1], g[2], f[1], f[2]]] *= -1
    elif change == "x_down":  # z of the body along x of the file: rotate the axes
        a[:, g] = a[:, [g[2], g[1], g[0]]] * [-1, 1, 1]
        a[:, f] = a[:, [f[2], f[1], f[0]]] * [-1, 1, 1]
    fl = _write_imu(tmp_path, files, header, a)
    cli.main(_args(fl, tmp_path / "o.csv"))
    w = _warnings(capsys)
    hits = [x for x in w if expect in x]
    assert len(hits) == 1, w  # printed once
    assert "imu_mod.csv" in hits[0]


def test_gnss_in_radians_and_times_that_do_not_overlap(files, tmp_path, capsys):
    g = _lines(files["gnss"])
    h = g[0].split(",")
    a = np.loadtxt(files["gnss"], delimiter=",", skiprows=1)
    r = a.copy()
    r[:, [h.index("lat"), h.index("lon")]] = np.radians(r[:, [h.index("lat"), h.index("lon")]])
    fl = dict(files, gnss=_write(tmp_path / "g_rad.csv", h, r.T, fmt="%.12g"))
    cli.main(_args(fl, tmp_path / "o.csv"))
    w = _warnings(capsys)
    assert len([x for x in w if "look like radians" in x]) == 1, w
    s = a.copy()
    s[:, h.index("time")] += 1e5  # a different clock
    fl = dict(files, gnss=_write(tmp_path / "g_late.csv", h, s.T, fmt="%.12g"))
    assert cli.main(_args(fl, tmp_path / "o.csv")) == 1
    cap = capsys.readouterr()
    assert "do not overlap" in cap.err and cap.err.count("do not overlap") == 1
    assert "navigation never started: the GNSS and IMU times do not overlap" in cap.out


def test_magnetometer_units():
    from quatnav.plausibility import check_magnetometer
    rng = np.random.default_rng(0)
    m = rng.standard_normal((500, 3))
    m = 48.0 * m / np.linalg.norm(m, axis=1, keepdims=True)  # uT
    assert check_magnetometer(m) is None
    for scale, unit in ((1e-6, "tesla"), (0.01, "gauss"), (10.0, "milligauss"), (1000.0, "nanotesla")):
        w = check_magnetometer(m * scale)
        assert isinstance(w, UnitWarning) and f"looks like {unit}" in str(w), (scale, w)
    assert "check the unit" in _text(check_magnetometer(m * 1e-3))


@pytest.mark.data
def test_plausibility_on_real_logs(data_dir):
    """No warning on NaveGo's run nor on the real walk in body axes; the walk's own sensor axes
    (z up) and its file's unit (g) are named."""
    from quatnav.datasets import gnss_imu_walk as W
    from quatnav.datasets import navego
    from quatnav.plausibility import plausibility_warnings
    for sub in ("navego_synthetic", "gnss_imu_walk"):
        if not (data_dir / sub).is_dir():
            pytest.skip(f"{sub} not in {data_dir}")
    n = navego.load(data_dir / "navego_synthetic")
    assert plausibility_warnings(n.imu_t, n.gyro, n.accel, n.gnss_t, *np.degrees(n.gnss_llh[:, :2]).T) == []
    w = W.load(data_dir / "gnss_imu_walk")
    ll = np.degrees(w.gnss_llh[:, :2]).T
    assert plausibility_warnings(w.imu_t, W.to_body(w.gyro_s), W.to_body(w.accel_s), w.gnss_t, *ll) == []
    raw = plausibility_warnings(w.imu_t, w.gyro_s, w.accel_s, w.gnss_t, *ll)
    assert len(raw) == 1 and isinstance(raw[0], AxesWarning) and "gravity appears on +z" in str(raw[0])
    in_g = plausibility_warnings(w.imu_t, w.gyro_s, w.accel_s / W.G0, w.gnss_t, *ll)
    assert any(isinstance(x, UnitWarning) and "look like g, not m/s^2" in str(x) for x in in_g)


# --- what real logs need: mounting, time offset, initial state, magnetometer, odometer,
# --- increments, diagnostics ---------------------------------------------------------------------
def test_upside_down_imu_warns_and_imu_rotation_fixes_it(walk, files, tmp_path, capsys):
    """The IMU upside down (roll 180 deg): a warning that names imu_rotation; with
    imu_rotation = [pi, 0, 0] in [filter] no warning and the same result as the right axes."""
    header, a = _imu_table(files)
    g = [header.index(f"gyro_{x}") for x in "yz"]
    f = [header.index(f"accel_{x}") for x in "yz"]
    a[:, g + f] *= -1
    fl = _write_imu(tmp_path, files, header, a)
    cli.main(_args(fl, tmp_path / "o1.csv"))
    w = _warnings(capsys)
    assert any("gravity appears on +z" in x and "imu_rotation" in x for x in w), w
    cfg = tmp_path / "rot.toml"
    cfg.write_text(Path(files["config"]).read_text() + "imu_rotation = [3.141592653589793, 0.0, 0.0]\n")
    assert cli.main(_args(dict(fl, config=str(cfg)), tmp_path / "o2.csv")) == 0
    assert _warnings(capsys) == []
    assert cli.main(_args(files, tmp_path / "o3.csv")) == 0
    capsys.readouterr()
    _, a2 = _read(tmp_path / "o2.csv")
    _, a3 = _read(tmp_path / "o3.csv")
    np.testing.assert_allclose(a2[:, 1:3], a3[:, 1:3], rtol=0, atol=1e-8)  # lat, lon (deg)


def test_gnss_on_another_clock_names_the_offset(files, tmp_path, capsys):
    from quatnav.plausibility import check_clock, check_motion_start
    # a 10 s log whose GNSS times are 18 s ahead (GPS time against UTC): no overlap, the offset named
    t10 = np.arange(0.0, 10.0, 0.01)
    assert "GPS time against UTC" in _text(check_clock(t10 + 1e9, np.arange(0.0, 10.0, 0.2) + 1e9 + 18.0))
    assert check_clock(t10, np.arange(0.0, 10.0, 0.2)) is None
    t = np.arange(0.0, 100.0, 0.01)
    # the motion seen 0.8 s later by the GNSS than by the gyro: within 1 s, no warning; 3 s: a warning
    gyro = np.zeros((len(t), 3))
    gyro[t > 20.0, 2] = 0.5
    tg = np.arange(0.0, 100.0, 0.2)
    assert check_motion_start(t, gyro, tg, np.where(tg > 20.8, 1.5, 0.0)) is None
    msg = _text(check_motion_start(t, gyro, tg, np.where(tg > 23.0, 1.5, 0.0)))
    import re
    offset = float(re.search(r"gps_time_offset = (\S+)", msg).group(1))
    assert abs(offset + 3.0) < 0.3, msg  # the GNSS sampling (0.2 s) and the smoothing (0.2 s) limit it


def test_initial_state_mag_odometer_increments_and_diagnostics(walk, files, tmp_path, capsys):
    import csv
    s = walk
    d = files["dir"]
    # increments instead of rates
    dt = np.diff(s.imu.t, prepend=s.imu.t[0] - 0.02)[:, None]
    inc = _write(d / "imu_inc.csv", ["time", "dtheta_x", "dtheta_y", "dtheta_z", "dvel_x", "dvel_y", "dvel_z"],
                 [s.imu.t, *(s.imu.gyro * dt).T, *(s.imu.accel * dt).T], fmt="%.12g")
    # a magnetometer from the truth (field 20 uT north, 40 uT down) and an odometer
    from quatnav.core import quaternion as Q
    k = s.imu.index
    m_b = np.array([Q.rotate_inv(q, [20.0, 0.0, 40.0]) for q in s.truth.q_nb[k]])
    mag = _write(d / "mag.csv", ["time", "mag_x", "mag_y", "mag_z"], [s.imu.t, *m_b.T], fmt="%.9g")
    v_b = np.array([Q.rotate_inv(q, v) for q, v in zip(s.truth.q_nb[k], s.truth.v_n[k])])
    odo = _write(d / "odo.csv", ["time", "speed"], [s.imu.t[::10], v_b[::10, 0]], fmt="%.9g")
    cfg = d / "init.toml"
    k0 = 0
    cfg.write_text(Path(files["config"]).read_text() + "\n[initial]\n"
                   f"euler = [{float(s.truth.rpy[k0, 0])!r}, {float(s.truth.rpy[k0, 1])!r}, {float(s.truth.rpy[k0, 2])!r}]\n")
    out, diag = d / "o_all.csv", d / "diag.csv"
    args = ["ins", "run", "--imu", inc, "--gnss", files["gnss"], "--mag", mag, "--odometer", odo,
            "--config", str(cfg), "--out", str(out), "--diagnostics", str(diag), "--json", str(d / "s.json")]
    assert cli.main(args) == 0
    cap = capsys.readouterr()
    assert "alignment given, heading from given" in cap.out
    import json
    summary = json.loads((d / "s.json").read_text())
    assert summary["alignment"]["method"] == "given"
    assert summary["decisions"]["mag"].get("accepted", 0) > 100
    assert summary["decisions"]["odometer"].get("accepted", 0) > 100
    rows = list(csv.DictReader(open(diag)))
    from quatnav.pipeline import DIAGNOSTICS_COLUMNS
    assert tuple(rows[0]) == DIAGNOSTICS_COLUMNS
    aids = {r["aid"] for r in rows}
    assert {"gps_pos", "gps_vel", "mag", "odometer"} <= aids
    assert all(r["decision"] in ("accepted", "weighted", "rejected", "inflated", "reset", "skipped", "aligned", "none")
               for r in rows)
    times = [float(r["time"]) for r in rows]
    assert times == sorted(times)
    for r in rows:  # every number a plain float ('nan' where none), as any CSV reader takes it
        for c in ("innovation_0", "innovation_1", "innovation_2", "nis", "inflation", "q_scale"):
            float(r[c])
    # against the truth: the same accuracy as the rates run
    header, a = _read(out)
    c = {n: a[:, i] for i, n in enumerate(header)}
    i = np.searchsorted(s.truth.t, c["time"])
    dn = (np.radians(c["lat"]) - s.truth.lat[i]) * 6.36e6
    assert np.sqrt(np.mean(dn ** 2)) < 2.0


def test_config_initial_and_rotation_errors(files, tmp_path, capsys):
    for text, expect in (("[initial]\neuler = [0, 0]\n", "[initial] euler must be a list of 3 numbers"),
                         ("[initial]\nv_n = [0, 0, 0]\n", "exactly one of euler (rad) and q_nb"),
                         ("[initial]\nbogus = 1\n", "[initial] unknown key 'bogus'"),
                         ("[filter]\nimu_rotation = [1, 2]\n", "imu_rotation must be [roll, pitch, yaw]"),
                         ("[filter]\nimu_rotation = [[1, 0, 0], [0, 1, 0], [0, 0, -1]]\n", "not a rotation matrix"),
                         ("[filter]\nzupt = 1\n", "zupt must be true or false"),
                         ("[initial]\neuler = [0, 30, 0]\n", "not [roll, pitch, yaw] in radians (pitch within"),
                         ("[initial]\neuler = [0, 0, 90]\n", "if these are degrees: [0, 0, 1.5708]"),
                         ("[filter]\nimu_rotation = [180, 0, 0]\n", "if these are degrees: [3.14159, 0, 0]")):
        cfg = tmp_path / "c.toml"
        cfg.write_text(text)
        assert cli.main(_args(dict(files, config=str(cfg)), tmp_path / "o.csv")) == 2
        err = capsys.readouterr().err
        assert expect in err and err.count("\n") == 1, err


def test_plot_shows_the_innovations_and_sigmas(files, tmp_path, monkeypatch):
    """--plot: six panels, among them the position one-sigma and every aid's NIS over time."""
    pytest.importorskip("matplotlib")
    import matplotlib.figure
    seen = {}
    save = matplotlib.figure.Figure.savefig

    def spy(fig, path, *a, **k):
        seen["labels"] = [ax.get_ylabel() for ax in fig.axes]
        seen["legend"] = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
        return save(fig, path, *a, **k)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", spy)
    png = tmp_path / "nav.png"
    assert cli.main(_args(files, tmp_path / "o.csv") + ["--plot", str(png)]) == 0
    assert png.stat().st_size > 10000
    assert "innovation NIS" in seen["labels"] and "position one-sigma, m" in seen["labels"]
    assert {"gps_pos", "gps_vel", "baro", "compass"} <= set(seen["legend"])


def test_motion_start_check_is_quiet_on_a_car_pulling_away_straight():
    """A car moving from t = 0, stopping at 40-48 s and pulling away straight: the GNSS sees the
    start at 48.5 s, the gyro only at the first turn; the specific force sees the start too, so no
    clock offset is suggested. Starts 30 s apart are not read as a clock offset either."""
    from quatnav.plausibility import check_motion_start
    t = np.arange(0.0, 120.0, 0.01)
    gyro = np.zeros((len(t), 3))
    gyro[(t > 80.0) & (t < 85.0), 2] = 0.4  # the first turn
    accel = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    accel[(t > 48.5) & (t < 53.0), 0] = 2.5  # pulling away
    accel[(t > 35.0) & (t < 40.0), 0] = -2.0  # braking before the stop
    tg = np.arange(0.0, 120.0, 0.1)
    speed = np.where((tg > 40.0) & (tg < 48.9), 0.0, 8.0)
    assert check_motion_start(t, gyro, tg, speed, accel=accel) is None
    assert check_motion_start(t, gyro, tg, speed) is None  # gyro only: 31 s apart, different events
    late = np.where((tg > 40.0) & (tg < 51.0), 0.0, 8.0)  # the GNSS 2.5 s late
    msg = _text(check_motion_start(t, gyro, tg, late, accel=accel))
    assert msg is not None and "gps_time_offset = -2." in msg


def test_motion_start_check_ignores_a_stop_the_imu_sees_early():
    """A car pulling away at 48.5 s (seen by both), its last turn ending at 101 s and then braking
    gently to a stop at 105 s: the braking looks still to the IMU, which sees the stop 4 s before
    the GNSS does. That is not the threshold's lag (which makes the GNSS stop early): with one
    clock no offset is suggested (it suggested about 2 s), with the GNSS 3 s late the start names it."""
    from quatnav.plausibility import check_motion_start
    t = np.arange(0.0, 130.0, 0.005)
    gyro = np.zeros((len(t), 3))
    gyro[(t > 80.0) & (t < 85.0), 2] = 0.4
    gyro[(t > 95.0) & (t < 101.0), 2] = -0.4  # the last turn
    accel = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    accel[(t > 48.5) & (t < 53.0), 0] = 2.5  # pulling away
    accel[(t > 101.0) & (t < 105.0), 0] = -0.3  # braking gently to the stop
    tg = np.arange(0.0, 130.0, 0.1)
    speed = np.where(tg < 48.5, 0.0, np.minimum(2.5 * (tg - 48.5), 11.25))
    speed = np.where(tg > 101.0, np.maximum(1.2 - 0.3 * (tg - 101.0), 0.0), speed)
    speed[tg > 105.0] = 0.0
    assert check_motion_start(t, gyro, tg, speed, accel=accel) is None
    msg = _text(check_motion_start(t, gyro, tg + 3.0, speed, accel=accel))
    assert msg is not None and "stops" not in msg and -3.5 < _offset_named(msg) < -2.9, msg


def test_motion_start_check_is_quiet_after_a_moving_start_with_a_rotated_imu():
    """The car of test above, but accelerating at 4 m/s^2 from t = 0 (a moving start) with the
    IMU mounted turned 90 deg in yaw and tilted: the specific force at the start of the log is not
    the one at rest, so the pull-away is measured against the steady second before it. With the
    GNSS on the IMU's clock: no warning; 3 s late: the offset named, to the detection lags."""
    from quatnav.plausibility import check_motion_start
    from quatnav.core import quaternion as quat
    rng = np.random.default_rng(3)
    t = np.arange(0.0, 120.0, 0.005)
    gyro = 0.002 * rng.standard_normal((len(t), 3))
    gyro[(t > 80.0) & (t < 85.0), 2] += 0.4  # the first turn
    f_b = np.tile([0.0, 0.0, -9.81], (len(t), 1))
    f_b[t < 6.0, 0] = 4.0  # the moving start
    f_b[(t > 34.0) & (t < 40.0), 0] = -2.0  # braking to the stop at 40-48 s
    pull = (t > 48.5) & (t < 53.5)
    f_b[pull, 0] = 1.5 * (53.5 - t[pull]) / 5.0  # pulling away, straight, the acceleration tapering
    C_imu_b = quat.to_rotmat(quat.from_euler([0.05, -0.03, np.pi / 2])).T  # body -> IMU axes
    accel = f_b @ C_imu_b.T + 0.05 * rng.standard_normal((len(t), 3))
    tg = np.arange(0.0, 120.0, 0.1)
    speed = np.where((tg > 40.0) & (tg < 48.8), 0.0, 8.0)
    assert check_motion_start(t, gyro, tg, speed, accel=accel) is None
    late = np.where((tg > 40.0) & (tg < 51.8), 0.0, 8.0)  # the GNSS 3 s late
    msg = _text(check_motion_start(t, gyro, tg, late, accel=accel))
    import re
    offset = float(re.search(r"gps_time_offset = (\S+)", msg).group(1))
    assert -3.5 < offset < -2.5, msg


def _offset_named(msg):
    import re
    return float(re.search(r"gps_time_offset = (\S+)", msg).group(1))


@pytest.mark.parametrize("shift", [0.0, -8.0, -3.0, 5.0])
def test_motion_start_check_cancels_the_speed_thresholds_lag(shift):
    """A walker: the gyro active from the first step at 10 s to the last at 110 s, the GNSS speed
    ramping over 4 s to 1.2 m/s and back, so it crosses 0.5 m/s 1.67 s after the start and 1.67 s
    before the stop. The start alone suggested a 1.67 s offset on one clock; start and stop
    together find none, and the GNSS shifted by ``shift`` s is named to within the sampling."""
    from quatnav.plausibility import check_motion_start
    t = np.arange(0.0, 130.0, 0.01)
    gyro = np.zeros((len(t), 3))
    walking = (t > 10.0) & (t < 110.0)
    gyro[walking, 1] = 0.8 * np.sin(2 * np.pi * 1.8 * t[walking])  # the gait
    tg = np.arange(0.0, 130.0, 0.25)
    speed = np.clip(np.minimum(tg - 10.0, 110.0 - tg) / 4.0, 0.0, 1.0) * 1.2
    msg = _text(check_motion_start(t, gyro, tg + shift, speed))
    if shift == 0.0:
        assert msg is None
    else:
        assert "stops at" in msg and abs(_offset_named(msg) + shift) < 0.3, msg
    # the IMU still for a second at 116 s and the GNSS stop 8 s before that: not the same event
    # (the differences 8 s apart), so the start alone decides: 1.67 s late
    g2 = gyro.copy()
    g2[(t > 110.0) & (t < 116.0), 1] = 0.8 * np.sin(2 * np.pi * 1.8 * t[(t > 110.0) & (t < 116.0)])
    msg = _text(check_motion_start(t, g2, tg + shift, speed))
    assert "stops at" not in msg and abs(_offset_named(msg) + shift + 1.67) < 0.3, msg


def test_motion_start_check_on_the_real_walk(data_dir):
    """The real walk (RTK, one clock): the GNSS speed passes 0.5 m/s 1.3 s after the first step;
    no offset is suggested, and GNSS times shifted by -8 s (the case that was misread as 6.7 s)
    or +5 s are named to within 0.5 s."""
    from quatnav.plausibility import check_motion_start
    from quatnav.datasets import gnss_imu_walk as W
    if not (data_dir / "gnss_imu_walk").is_dir():
        pytest.skip("gnss_imu_walk not in the data folder")
    w = W.load(data_dir / "gnss_imu_walk")
    gyro, accel = W.to_body(w.gyro_s), W.to_body(w.accel_s)
    speed = np.hypot(w.vel_n[:, 0], w.vel_n[:, 1])
    assert check_motion_start(w.imu_t, gyro, w.gnss_t, speed, accel=accel) is None
    for shift in (-8.0, 5.0):
        msg = _text(check_motion_start(w.imu_t, gyro, w.gnss_t + shift, speed, accel=accel))
        assert abs(_offset_named(msg) + shift) < 0.5, msg


@pytest.mark.parametrize("n, w", [(1000, 40), (1000, 41), (30, 1), (30, 7), (5, 9), (2, 4), (4, 2), (1, 1)])
def test_box_mean_is_numpys_centred_convolution(n, w):
    """The smoothing of the motion-start check (cumulative sums) against ``np.convolve(...,
    mode="same")`` of a box, column by column, at both edges and for a window longer than the
    record."""
    from quatnav.plausibility._signals import box_mean as _box_mean
    x = np.random.default_rng(n + w).normal(9.8, 1.0, (n, 3))
    ref = np.column_stack([np.convolve(x[:, c], np.ones(w) / w, mode="same")[:n] for c in range(3)])
    if w > n:  # numpy's "same" output then has w rows, centred on the record
        ref = np.column_stack([np.convolve(x[:, c], np.ones(w) / w, mode="full")[(w - 1) // 2:][:n] for c in range(3)])
    np.testing.assert_allclose(_box_mean(x, w), ref, rtol=0, atol=1e-12)
    np.testing.assert_allclose(_box_mean(x[:, 0], w), ref[:, 0], rtol=0, atol=1e-12)


def _drive(beta, tilt=(0.0, 0.0), seed=0):
    """A car driving 300 s with turns and speed changes; the IMU yawed by beta (and tilted) from
    the body: (t, accel in the IMU axes, GNSS times, GNSS north/east velocity)."""
    from quatnav.core import quaternion as quat
    rng = np.random.default_rng(seed)
    dt = 0.005
    t = np.arange(0.0, 300.0, dt)
    k = (t // 4).astype(int)  # a new manoeuvre every 4 s
    a_long = rng.uniform(-1.5, 1.5, k.max() + 1)[k]
    rate = rng.uniform(-0.15, 0.15, k.max() + 1)[k]
    s = np.maximum(10.0 + np.cumsum(a_long) * dt, 4.0)
    a_long = np.gradient(s, dt)
    psi = np.cumsum(rate) * dt
    f_b = np.column_stack([a_long, s * rate, np.full(len(t), -9.81)]) + 0.05 * rng.standard_normal((len(t), 3))
    C_b_imu = quat.to_rotmat(quat.from_euler([tilt[0], tilt[1], beta]))
    accel = f_b @ C_b_imu  # x_imu = C_b_imu^T x_b, row by row
    gi = np.arange(0, len(t), 20)  # GNSS at 10 Hz
    v = np.column_stack([s * np.cos(psi), s * np.sin(psi)])[gi] + 0.03 * rng.standard_normal((len(gi), 2))
    return t, accel, t[gi], v


@pytest.mark.parametrize("beta_deg", [0.0, 90.0, -30.0, 145.0, 180.0])
def test_forward_axis_is_the_mounting_yaw(beta_deg):
    """The direction of travel from the accelerations is -beta for an IMU yawed by beta (tilted
    by 3 and -2 deg), within a degree; its warning names imu_rotation's yaw beta, and is quiet
    within 20 deg."""
    from quatnav.plausibility import check_forward_axis, forward_axis
    t, accel, tg, v = _drive(np.radians(beta_deg), tilt=(np.radians(3.0), np.radians(-2.0)))
    ang, n, agree = forward_axis(t, accel, tg, v)
    err = (np.degrees(ang) + beta_deg + 180.0) % 360.0 - 180.0
    assert abs(err) < 1.0 and agree > 0.95 and n > 250, (np.degrees(ang), n, agree)
    msg = _text(check_forward_axis(t, accel, tg, v))
    if beta_deg == 0.0:
        assert msg is None
    else:
        import re
        yaw = float(re.search(r"add a yaw of (\S+) rad", msg).group(1))
        assert abs((np.degrees(yaw) - beta_deg + 180.0) % 360.0 - 180.0) < 1.0, msg


def test_forward_axis_needs_speed_and_agreement():
    """Below 3 m/s (a walker's GNSS speed: no course to speak of) there is no answer; a velocity
    of noise alone (no relation to the specific force) gives a low agreement and no warning."""
    from quatnav.plausibility import check_forward_axis, forward_axis
    t, accel, tg, v = _drive(np.radians(90.0))
    assert forward_axis(t, accel, tg, v * 3.0 / np.hypot(v[:, 0], v[:, 1]).max()) is None
    rng = np.random.default_rng(1)
    noise = np.column_stack([10.0 + 3.0 * rng.standard_normal(len(tg)), 3.0 * rng.standard_normal(len(tg))])
    r = forward_axis(t, accel, tg, noise)
    assert r is None or r[2] < 0.3
    assert check_forward_axis(t, accel, tg, noise) is None
