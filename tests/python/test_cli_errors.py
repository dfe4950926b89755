"""Every user mistake on the command line: one line on stderr naming what is wrong, exit status 2,
no traceback; a genuine bug keeps its traceback. Each case runs ``python -m quatnav`` in a
subprocess (a missing optional package is simulated by blocking its import in the subprocess)."""
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import quatnav

PYTHON_DIR = str(Path(quatnav.__file__).resolve().parent.parent)
IMU_HEADER = "time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z"
needs_pandas = pytest.mark.skipif(importlib.util.find_spec("pandas") is None, reason="pandas (extra [io]) not installed")
needs_scipy = pytest.mark.skipif(importlib.util.find_spec("scipy") is None, reason="scipy (extra [sim]) not installed")
GNSS_HEADER = "time,lat,lon,h"

# runs ``quatnav`` with the listed modules made unimportable (as if their extra were not installed)
_BLOCKED = """import runpy, sys
for m in {mods!r}:
    sys.modules[m] = None
sys.argv = ["quatnav"] + sys.argv[1:]
runpy.run_module("quatnav", run_name="__main__", alter_sys=True)
"""


def quatnav_cli(*args, block=(), env=None, cwd=None, code=None):
    e = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    e.pop("QUATNAV_TRACEBACK", None)
    e.update(env or {})
    if code is not None:
        cmd = [sys.executable, "-c", code, *map(str, args)]
    elif block:
        cmd = [sys.executable, "-c", _BLOCKED.format(mods=list(block)), *map(str, args)]
    else:
        cmd = [sys.executable, "-m", "quatnav", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, env=e, cwd=cwd, timeout=300)


def error_line(p) -> str:
    """The one error line of a finished command (warnings aside); asserts status 2, no traceback."""
    lines = [ln for ln in p.stderr.splitlines() if ln.strip() and ": warning: " not in ln]
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "Traceback" not in p.stderr, p.stderr
    assert len(lines) == 1, p.stderr
    assert ": error: " in lines[0]
    assert "np.float64" not in lines[0] and "np.int64" not in lines[0]
    return lines[0]


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """A short consistent IMU (100 Hz, at rest, level) and GNSS log."""
    d = tmp_path_factory.mktemp("logs")
    t = np.arange(0, 20.0, 0.01)
    imu = np.column_stack([t, np.zeros((len(t), 3)), np.zeros(len(t)), np.zeros(len(t)), np.full(len(t), -9.80665)])
    np.savetxt(d / "imu.csv", imu, delimiter=",", header=IMU_HEADER, comments="", fmt="%.9g")
    tg = np.arange(0, 20.0, 1.0)
    gnss = np.column_stack([tg, np.full(len(tg), 47.0), np.full(len(tg), 8.0), np.full(len(tg), 500.0)])
    np.savetxt(d / "gnss.csv", gnss, delimiter=",", header=GNSS_HEADER, comments="", fmt="%.9g")
    return d


def _imu_with_times(d, name, t):
    n = len(t)
    a = np.column_stack([t, np.zeros((n, 5)), np.full(n, -9.8)])
    p = d / name
    np.savetxt(p, a, delimiter=",", header=IMU_HEADER, comments="", fmt="%.17g")
    return p


# --- argument parsing --------------------------------------------------------------------------
@pytest.mark.parametrize("args, expect", [
    ((), "give a command"),
    (("nope",), "invalid choice: 'nope'"),
    (("ins",), "give a command (run"),
    (("ins", "run", "--imu", "x.csv"), "required: --out"),
    (("ins", "run", "--imu", "x.csv", "--out", "o.csv"), "give --imu IMU and --gnss GNSS, or --log FILE"),
    (("eval",), "give a source (broad, sim"),
    (("eval", "nowhere"), "nowhere: no such file or folder"),
    (("eval", "sim:nope"), "unknown scenario 'nope'"),
    (("eval", "sim", "--modes", "7d"), "--modes 7d: expected a comma list of 9d, 6d"),
    (("tune",), "give at least one --param"),
    (("tune", "--param", "gyro_noise=1e-3:1e-1", "--set", "acc_sigma"), "--set acc_sigma: expected NAME=VALUE"),
    (("experiment",), "give a command"),
    (("experiment", "nope"), "invalid choice: 'nope'"),
    (("experiment", "nav13", "--runs", "0"), "--runs: expected a positive integer, got 0"),
    (("experiment", "marg-turn", "--seeds", "x"), "invalid int value: 'x'"),
    (("simulate",), "give a scenario NAME"),
    (("simulate", "nope", "--out", "x.npz"), "unknown scenario name 'nope'"),
    (("simulate", "paper004_walk", "--seed", "-1", "--out", "x.npz"), "--seed"),
    (("simulate", "paper004_walk"), "nothing to write"),
    (("bench", "-n", "0"), "-n: expected at least 1"),
    (("demo", "--seed", "-1"), "--seed: expected a non-negative integer, got -1"),
    (("experiment", "walk-rtk", "--seed", "-2"), "--seed: expected a non-negative integer, got -2"),
    (("experiment", "gpsins", "--outage-start", "-50"), "--outage-start: the outage -50 to -40 s lies outside"),
    (("experiment", "gpsins", "--outage-length", "0"), "--outage-length"),
    (("experiment", "nav13", "--accel-noise-scale", "0"), "--accel-noise-scale"),
    (("experiment", "navego", "--seconds", "-1"), "--seconds"),
    (("experiment", "marg-turn", "--seeds", "1", "--gain", "-1"), "gain: expected a non-negative finite number"),
    (("simulate", "paper004_walk", "--out", "x.npz", "--plot", "x.xyz"), "--plot x.xyz: matplotlib cannot write .xyz"),
    (("ahrs", "run", "--imu", "x.csv", "--out", "o.csv", "--plot", "p.jpg2"), "cannot write .jpg2 files (it writes"),
    (("ahrs", "run", "--imu", "x.csv", "--out", "o.csv", "--declination", "400"), "expected degrees east within +-180"),
    (("--nosuch",), "quatnav: error: unrecognized arguments: --nosuch (see 'quatnav -h')"),
    (("ins", "run", "--imu", "x.csv", "--out", "o.csv", "--nosuch"),
     "quatnav ins run: error: unrecognized arguments: --nosuch (see 'quatnav ins run -h')"),
    (("ins", "--nosuch", "run", "--imu", "x.csv", "--out", "o.csv"), "quatnav ins run: error: unrecognized arguments"),
    (("calibrate", "mag", "x.csv", "--out", "c.toml", "--nosuch", "1"),
     "quatnav calibrate: error: unrecognized arguments: --nosuch 1 (see 'quatnav calibrate -h')"),
])
def test_usage_errors_are_one_line(args, expect, tmp_path):
    line = error_line(quatnav_cli(*args, cwd=tmp_path))
    assert expect in line, line


@pytest.mark.parametrize("opt, path, expect", [
    ("--out", "no/such.npz", "--out no/such.npz: cannot write (no such directory: "),
    ("--csv", "no/such/dir", "--csv no/such/dir: cannot create it (no such directory: "),
    ("--csv", "no/such.csv", "--csv no/such.csv: cannot write (no such directory: "),
])
def test_simulate_refuses_an_output_folder_whose_parent_is_missing(opt, path, expect, tmp_path):
    """--out and --csv alike: a path into a folder that does not exist is refused before the
    scenario is made, and no folder is created (--csv DIR creates DIR itself, not its parents)."""
    line = error_line(quatnav_cli("simulate", "paper004_static", opt, path, cwd=tmp_path))
    assert expect in line, line
    assert not (tmp_path / "no").exists()


@needs_pandas
@pytest.mark.parametrize("cmd, opt, path", [
    ("ahrs", "--out", "no/o.csv"), ("ahrs", "--json", "no/s.json"), ("ahrs", "--plot", "no/such/p.png"),
    ("ins", "--out", "no/o.csv"), ("ins", "--json", "no/s.json"), ("ins", "--diagnostics", "no/d.csv"),
    ("ins", "--kml", "no/t.kml"), ("ins", "--gpx", "no/t.gpx"),
])
def test_an_output_into_a_missing_folder_is_refused_before_the_run(logs, tmp_path, cmd, opt, path):
    """Refused in one line before the run (it used to end the whole run in a traceback); --plot
    may create its own folder, not a chain of them."""
    args = ["--imu", logs / "imu.csv"] + (["--gnss", logs / "gnss.csv"] if cmd == "ins" else [])
    out = [] if opt == "--out" else ["--out", tmp_path / "o.csv"]
    line = error_line(quatnav_cli(cmd, "run", *args, *out, opt, path, cwd=tmp_path))
    assert f"{opt} {path}: cannot write (no such directory: " in line, line
    assert not (tmp_path / "no").exists() and not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize("plot", ["figs/p.png", "p.png"])
def test_plot_creates_its_own_folder(logs, tmp_path, plot):
    p = quatnav_cli("ahrs", "run", "--imu", logs / "imu.csv", "--out", tmp_path / "o.csv", "--plot", plot, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / plot).is_file()


# --- ins run -----------------------------------------------------------------------------------
@needs_pandas
@pytest.mark.parametrize("scale, unit", [(1e3, "milliseconds"), (1e6, "microseconds"), (1e9, "nanoseconds")])
def test_ins_run_names_the_time_unit(logs, tmp_path, scale, unit):
    imu = _imu_with_times(tmp_path, "imu.csv", np.arange(0, 20.0, 0.01) * scale)
    line = error_line(quatnav_cli("ins", "run", "--imu", imu, "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv"))
    assert f"times look like {unit}" in line and "a 100 Hz IMU" in line and "exceeds max_dt = 1 s" in line, line
    assert str(imu) in line


@needs_pandas
def test_ins_run_steps_of_1000_s(logs, tmp_path):
    imu = _imu_with_times(tmp_path, "imu.csv", np.arange(0, 50) * 1000.0)
    line = error_line(quatnav_cli("ins", "run", "--imu", imu, "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv"))
    assert "median time step 1000 s" in line and "microseconds" in line, line


@needs_pandas
def test_ins_run_gap_is_coasted_not_an_error(logs, tmp_path):
    t = np.concatenate([np.arange(0, 10.0, 0.01), np.arange(14.0, 20.0, 0.01)])  # 4 s gap after line 1001
    imu = _imu_with_times(tmp_path, "imu.csv", t)
    p = quatnav_cli("ins", "run", "--imu", imu, "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv")
    assert p.returncode in (0, 1), p.stderr
    warn = [ln for ln in p.stderr.splitlines() if "gap" in ln]
    assert len(warn) == 1 and "lines 1001-1002" in warn[0] and "4.01 s" in warn[0] and "coasted" in warn[0], p.stderr
    assert "Traceback" not in p.stderr and ": error: " not in p.stderr


@pytest.mark.parametrize("text, expect", [
    ("[filter]\ndeclination = 8.5\n", "np.radians(8.5)"),
    ("[filter]\ncompass_sigma = 2.0\n", "compass_sigma"),
    ("[filter]\nmax_dt = -1.0\n", "max_dt"),
    ("[filter]\ngyro_noize = 1.0\n", "unknown parameter 'gyro_noize'"),
])
def test_ins_run_config_errors(logs, tmp_path, text, expect):
    cfg = tmp_path / "c.toml"
    cfg.write_text(text)
    line = error_line(quatnav_cli("ins", "run", "--imu", logs / "imu.csv", "--gnss", logs / "gnss.csv",
                                  "--config", cfg, "--out", tmp_path / "o.csv"))
    assert expect in line and "c.toml" in line, line


@needs_pandas
def test_ins_run_missing_file_and_bad_cell(logs, tmp_path):
    line = error_line(quatnav_cli("ins", "run", "--imu", tmp_path / "nope.csv", "--gnss", logs / "gnss.csv",
                                  "--out", tmp_path / "o.csv"))
    assert "nope.csv" in line and "cannot open" in line
    bad = tmp_path / "bad.csv"
    bad.write_text("# a comment\n" + IMU_HEADER + "\n0,0,0,0,0,0,-9.8\n\n0.01,0,zero,0,0,0,-9.8\n")
    line = error_line(quatnav_cli("ins", "run", "--imu", bad, "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv"))
    assert "line 5, column 'gyro_y': not a finite number ('zero')" in line, line


def test_ins_run_output_not_writable(logs, tmp_path):
    line = error_line(quatnav_cli("ins", "run", "--imu", logs / "imu.csv", "--gnss", logs / "gnss.csv",
                                  "--out", tmp_path / "no" / "such" / "o.csv"))
    assert "cannot write" in line


# --- eval broad --------------------------------------------------------------------------------
def test_eval_broad_without_dir_names_quatnav_data(tmp_path):
    line = error_line(quatnav_cli("eval", "broad", env={"QUATNAV_DATA": str(tmp_path)}))
    assert "no DIR given" in line and "QUATNAV_DATA" in line and str(tmp_path / "broad") in line, line


def test_eval_broad_wrong_dir(tmp_path):
    line = error_line(quatnav_cli("eval", "broad", tmp_path / "nope", "--peers", "none"))
    assert "no such directory" in line and "nope" in line
    (tmp_path / "f.txt").write_text("x")
    line = error_line(quatnav_cli("eval", "broad", tmp_path / "f.txt"))
    assert "not a directory" in line
    line = error_line(quatnav_cli("eval", "broad", tmp_path, "--peers", "none"))  # none is accepted: the DIR is wrong
    assert "no BROAD trials" in line and "--peers" not in line, line


@pytest.mark.parametrize("args, expect", [
    (("--peers", "none", "--filters", "none"), "select nothing"),
    (("--peers", "vqf,bogus"), "--peers: unknown name 'bogus'"),
    (("--filters", "kalman"), "--filters: unknown name 'kalman'"),
    (("--jobs", "0"), "--jobs"),
])
def test_eval_broad_options(tmp_path, args, expect):
    line = error_line(quatnav_cli("eval", "broad", tmp_path, *args))
    assert expect in line, line


# --- experiments on missing data ------------------------------------------------------------------
@pytest.mark.parametrize("name", ["navego", "walk-rtk", "marg-broad"])
def test_experiment_without_data(tmp_path, name):
    line = error_line(quatnav_cli("experiment", name, "--data", tmp_path / "nope"))
    assert "--data" in line and "QUATNAV_DATA" in line, line


# --- missing optional packages ---------------------------------------------------------------------
@pytest.mark.parametrize("args, block, extra", [
    (("simulate", "paper004_walk", "--out", "x.npz"), ["scipy"], "sim"),
    (("experiment", "gpsins"), ["scipy"], "eval"),
    (("bench", "-n", "1000", "--repeat", "1", "--filters", "QuaternionEKF"), ["scipy"], "sim"),
    (("eval", "broad", "BROAD", "--peers", "none"), ["scipy", "h5py"], "eval"),
    (("demo", "--plot", "x.png"), ["matplotlib"], "eval"),
    (("simulate", "paper004_walk", "--plot", "x.png"), ["matplotlib"], "eval"),
    (("ins", "run", "--imu", "imu.csv", "--gnss", "gnss.csv", "--out", "o.csv"), ["pandas"], "io"),
])
def test_missing_extra_is_named(logs, tmp_path, args, block, extra):
    (tmp_path / "BROAD").mkdir()
    (tmp_path / "BROAD" / "01_trial.mat").write_bytes(b"MATLAB 5.0 MAT-file")  # read only with scipy
    for f in ("imu.csv", "gnss.csv"):
        (tmp_path / f).write_text((logs / f).read_text())
    line = error_line(quatnav_cli(*args, block=block, cwd=tmp_path))
    assert f"pip install 'quatnav[{extra}]'" in line and block[0] in line, line
    if "--plot" in args:
        assert "--plot needs" in line


# --- not user errors -----------------------------------------------------------------------------
_BUG = """import sys
import numpy as np
import quatnav.pipeline.ins as m
def broken(*a, **k):
    return np.zeros(3) + np.zeros(4)   # a ValueError from numpy: a bug, not the user's mistake
m._run = broken
from quatnav.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_a_bug_keeps_its_traceback(logs, tmp_path):
    p = quatnav_cli("ins", "run", "--imu", logs / "imu.csv", "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv",
                    code=_BUG)
    assert p.returncode == 1 and "Traceback" in p.stderr and "broadcast" in p.stderr


def test_traceback_on_request(tmp_path):
    p = quatnav_cli("eval", "broad", tmp_path / "nope", env={"QUATNAV_TRACEBACK": "1"})
    assert p.returncode == 1 and "Traceback" in p.stderr and "UsageError" in p.stderr


# --- help and JSON ---------------------------------------------------------------------------------
def test_help_documents_quatnav_data_and_experiments():
    top = quatnav_cli("-h")
    assert top.returncode == 0 and "QUATNAV_DATA" in top.stdout
    ev = quatnav_cli("eval", "broad", "-h")
    assert "QUATNAV_DATA" in ev.stdout and "quatnav[eval]" in ev.stdout
    ex = quatnav_cli("experiment", "-h")
    assert "QUATNAV_DATA" in ex.stdout
    from quatnav import experiments
    for name in experiments.EXPERIMENTS:
        line = next(ln for ln in ex.stdout.splitlines() if ln.strip().startswith(name + " "))
        assert len(line.split(name, 1)[1].strip()) > 20, line  # a one-line description
        assert experiments.summary(name) in line


@needs_pandas
@needs_scipy
def test_json_to_stdout(logs, tmp_path):
    p = quatnav_cli("simulate", "--list", "--json", "-")
    assert p.returncode == 0 and "paper004_walk" in json.loads(p.stdout)
    p = quatnav_cli("ins", "run", "--imu", logs / "imu.csv", "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv",
                    "--json", "-")
    d = json.loads(p.stdout)  # only the JSON document on stdout; the summary line went to stderr
    assert d["output"] == str(tmp_path / "o.csv") and "warnings" in d and "wrote" in p.stderr
    p = quatnav_cli("demo", "--json", "-")
    d = json.loads(p.stdout)
    assert p.returncode == 0 and 0 < d["QuaternionEKF"]["roll_rmse_deg"] < 5 and "result" not in d["QuaternionEKF"]
    p = quatnav_cli("simulate", "paper004_static", "--json", tmp_path / "s.json")
    assert p.returncode == 0 and json.loads((tmp_path / "s.json").read_text())["sensors"]["imu"] > 0


@needs_pandas
def test_ins_run_gap_too_long_to_coast(logs, tmp_path):
    t = np.concatenate([np.arange(0, 5.0, 0.01), 5.0 + 1e7 + np.arange(0, 5.0, 0.01)])  # 116 days
    imu = _imu_with_times(tmp_path, "imu.csv", t)
    line = error_line(quatnav_cli("ins", "run", "--imu", imu, "--gnss", logs / "gnss.csv", "--out", tmp_path / "o.csv"))
    assert "coasting steps" in line and "lines 501-502" in line and "split the log" in line, line


def test_a_misspelled_config_key_gets_a_suggestion(logs, tmp_path):
    """One short line with the key it most likely meant (it was 1,249 characters listing every
    parameter)."""
    cfg = tmp_path / "c.toml"
    cfg.write_text("[filter]\nlever_arm = [0.1, 0.0, 0.0]\n")
    line = error_line(quatnav_cli("ins", "run", "--imu", logs / "imu.csv", "--gnss", logs / "gnss.csv", "--config",
                                  cfg, "--out", tmp_path / "o.csv"))
    assert "unknown parameter 'lever_arm' (did you mean 'lever_arm_b'" in line and len(line) - len(str(cfg)) < 200, line
    cfg.write_text("[inital]\neuler = [0.0, 0.0, 0.0]\n")
    line = error_line(quatnav_cli("ins", "run", "--imu", logs / "imu.csv", "--gnss", logs / "gnss.csv", "--config",
                                  cfg, "--out", tmp_path / "o.csv"))
    assert "did you mean 'initial'" in line, line


def test_ins_run_help_says_whose_position_it_writes():
    h = quatnav_cli("ins", "run", "-h").stdout
    assert "the IMU's position and velocity, not the" in h and "antenna's" in h
