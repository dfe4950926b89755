"""One set of plausibility checks (quatnav.plausibility.check_imu) in every filter's run and in
'quatnav ahrs run': a gyro in deg/s, an accelerometer in g, a z axis that points up, a sensor
clipped at its range and samples missing are named, as warnings of a category a user filters,
each with its fix; none on the simulated scenarios, on BROAD in forward-right-down, or in rad/s."""
import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import quatnav
from quatnav.plausibility import check_imu, checked_by_caller
from quatnav.sim.scenarios import list_scenarios, make_scenario

PYTHON_DIR = str(Path(quatnav.__file__).resolve().parent.parent)
G0 = 9.80665


@pytest.fixture(scope="module")
def walk():
    return make_scenario("paper004_walk", seed=0)


@pytest.fixture(scope="module")
def handheld():
    return make_scenario("handheld_marg", seed=0)


def _caught(fn):
    """The PlausibilityWarnings ``fn()`` issues (every one, each time)."""
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        fn()
    return [x for x in w if issubclass(x.category, quatnav.PlausibilityWarning)]


def _attitude_runs(s, gyr, acc):
    """Every attitude filter's run on the same samples (t from the scenario)."""
    return {name: (lambda cls=cls: cls().run(gyr, acc, t=s.imu.t, on_invalid="skip"))
            for name, cls in (("QuaternionEKF", quatnav.QuaternionEKF), ("EulerEKF", quatnav.EulerEKF),
                              ("MargFilter", quatnav.MargFilter))}


def _gpsins_run(s, gyr, acc):
    g = s.gps
    return lambda: quatnav.GpsInsFilter().run(gyr, acc, t=s.imu.t, gps_pos=quatnav.Aid(
        g.t_valid, np.column_stack([g.lat, g.lon, g.h])), gps_vel=quatnav.Aid(g.t_valid, g.v_n))


def test_every_filter_names_a_gyro_in_deg_s_and_an_accelerometer_in_g(handheld, walk):
    s = handheld
    runs = _attitude_runs(s, s.imu.gyro, s.imu.accel)
    runs["GpsInsFilter"] = _gpsins_run(walk, walk.imu.gyro, walk.imu.accel)
    for name, run in runs.items():
        assert _caught(run) == [], name  # the same samples in rad/s and m/s^2: quiet
    deg = _attitude_runs(s, np.degrees(s.imu.gyro), s.imu.accel)
    deg["GpsInsFilter"] = _gpsins_run(walk, np.degrees(walk.imu.gyro), walk.imu.accel)
    for name, run in deg.items():
        w = _caught(run)
        assert [type(x.message) for x in w] == [quatnav.UnitWarning], (name, [str(x.message) for x in w])
        text = str(w[0].message)
        assert text.startswith(f"{name}.run: gyr looks like deg/s") and "pi/180" in text, text
        assert w[0].filename == __file__  # it names the caller's line, not quatnav's
    in_g = _attitude_runs(s, s.imu.gyro, s.imu.accel / G0)
    in_g["GpsInsFilter"] = _gpsins_run(walk, walk.imu.gyro, walk.imu.accel / G0)
    for name, run in in_g.items():
        w = [str(x.message) for x in _caught(run)]
        assert any("acc looks like g, not m/s^2" in x and "9.80665" in x for x in w), (name, w)


def test_nav13_names_a_gyro_in_deg_s(walk):
    """(A deg/s gyro shows in its bias at rest, or in rates beyond any MEMS range: a navigation
    grade gyro in a gentle motion, paper 002's, does not.)"""
    s = walk

    def run(gyr):
        f = quatnav.NavFilter13()
        f.reset(s.truth.v_n[0], s.truth.q_nb[0])
        f.run(gyr, s.imu.accel, t=s.imu.t)
    assert _caught(lambda: run(s.imu.gyro)) == []
    w = _caught(lambda: run(np.degrees(s.imu.gyro)))
    assert len(w) == 1 and "NavFilter13.run: gyr looks like deg/s" in str(w[0].message)


def test_no_warnings_on_the_simulated_scenarios():
    """The checks of every filter (attitude: gravity on +z only; navigation: off -z at rest) are
    quiet on every scenario in its body axes; the upside-down car's IMU axes are named, and so is
    the gyro that clips at 500 deg/s. Two fast motions are not quiet (false alarms of the checks,
    listed here until they tell them apart): the forearm swinging while running (3-4 g centripetal
    by design), whose median specific force, 2.4 g, is taken for a wrong unit; and the forearm
    swinging while walking, whose periodic peaks, quantized to 0.061 deg/s, repeat the largest
    rate in 3 sampled rows, taken for a plateau (with seed 0 the running forearm's do)."""
    expected = {"car_city_upside_down": [quatnav.AxesWarning], "fast_gyro_saturation": [quatnav.SaturationWarning],
                "fast_limb_run": [quatnav.UnitWarning], "fast_limb_walk": [quatnav.SaturationWarning]}
    for name in list_scenarios():
        s = make_scenario(name, seed=1)
        if s.imu is None:
            continue
        for axes in ("up", "frd"):
            w = check_imu(s.imu.gyro, s.imu.accel, t=s.imu.t, axes=axes)
            assert [type(x) for x in w] == expected.get(name, []), (name, axes, [str(x) for x in w])


def test_a_level_turntable_is_not_taken_for_deg_s():
    """A rotation about the vertical keeps the accelerometer steady at any rate (a level
    turntable, a car circling): 0.3 rad/s about z from the first sample is rad/s, and not named.
    The same IMU in deg/s with a 0.3 deg/s bias about each horizontal axis is named, as is a
    still IMU in deg/s (bias and noise about every axis) whose accelerometer is tilted."""
    rng = np.random.default_rng(3)
    t = np.arange(1000) * 0.01
    acc = np.array([0.0, 0.0, -G0]) + 0.02 * rng.standard_normal((1000, 3))
    gyr = np.array([0.0, 0.0, 0.3]) + 0.002 * rng.standard_normal((1000, 3))
    w = _caught(lambda: quatnav.QuaternionEKF().run(gyr, acc, t=t))
    assert [x for x in w if issubclass(x.category, quatnav.UnitWarning)] == []
    for axes in ("up", "frd"):
        assert check_imu(gyr, acc, steps=0.01, axes=axes) == []
    deg = np.degrees(gyr) + np.array([0.3, -0.3, 0.0]) + 0.05 * rng.standard_normal((1000, 3))
    assert [type(x) for x in check_imu(deg, acc, steps=0.01)] == [quatnav.UnitWarning]
    tilt = np.array([[1, 0, 0], [0, np.cos(0.4), -np.sin(0.4)], [0, np.sin(0.4), np.cos(0.4)]])
    still = np.radians([1.0, -1.5, 0.5]) + 0.001 * rng.standard_normal((1000, 3))  # MEMS biases
    assert check_imu(still, acc @ tilt.T, steps=0.01) == []
    assert [type(x) for x in check_imu(np.degrees(still), acc @ tilt.T, steps=0.01)] == [quatnav.UnitWarning]


def test_a_clipped_sensor_and_missing_samples(handheld):
    s = handheld
    assert np.abs(s.imu.gyro).max() > 2.5  # the clips below bite
    w = _caught(lambda: quatnav.QuaternionEKF().run(np.clip(s.imu.gyro, -2.5, 2.5), s.imu.accel, t=s.imu.t))
    assert [type(x.message) for x in w] == [quatnav.SaturationWarning], [str(x.message) for x in w]
    assert "gyro_range = 2.5" in str(w[0].message)
    # told the range, the filter skips those samples itself: no warning
    assert _caught(lambda: quatnav.QuaternionEKF(gyro_range=2.5).run(np.clip(s.imu.gyro, -2.5, 2.5), s.imu.accel,
                                                                       t=s.imu.t)) == []
    # a plateau below 2 rad/s is not named: a slow motion's largest rate may repeat in a quantized log
    assert check_imu(np.clip(s.imu.gyro, -1.5, 1.5), s.imu.accel, t=s.imu.t) == []
    # samples missing: 0.5 s of a 200 Hz record, within max_dt (1 s)
    keep = np.ones(len(s.imu.t), bool)
    keep[3000:3100] = False
    w = _caught(lambda: quatnav.QuaternionEKF().run(s.imu.gyro[keep], s.imu.accel[keep], t=s.imu.t[keep]))
    assert [type(x.message) for x in w] == [quatnav.GapWarning]
    assert "1 time step longer than ten median steps" in str(w[0].message) and "at row 3000" in str(w[0].message)


def test_users_filter_by_category(handheld):
    s = handheld

    def run():
        return quatnav.QuaternionEKF().run(np.degrees(s.imu.gyro), s.imu.accel, t=s.imu.t)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", quatnav.UnitWarning)
        run()
    assert not [x for x in w if issubclass(x.category, quatnav.PlausibilityWarning)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", quatnav.UnitWarning)
        with pytest.raises(quatnav.UnitWarning, match="deg/s"):
            run()
    with checked_by_caller():  # a pipeline that checked the inputs itself
        assert _caught(run) == []


@pytest.mark.data
def test_broad_as_exported(data_dir):
    """BROAD's IMU z axis points up: named (roll +-180 deg otherwise); in forward-right-down
    ([x, -y, -z]) nothing; np.degrees(gyr) named on every trial, rad/s on none."""
    from quatnav.datasets import broad
    d = data_dir / "broad"
    if not d.is_dir():
        pytest.skip(f"no BROAD data in {data_dir}")
    frd = np.array([1.0, -1.0, -1.0])
    for p in broad.list_trials(d):
        tr = broad.load_trial(p)
        up = check_imu(tr.gyr, tr.acc, steps=tr.dt)
        assert [type(x) for x in up] == [quatnav.AxesWarning] and "points up" in str(up[0]), p.stem
        assert check_imu(tr.gyr * frd, tr.acc * frd, steps=tr.dt) == [], p.stem
        deg = check_imu(np.degrees(tr.gyr) * frd, tr.acc * frd, steps=tr.dt)
        assert [type(x) for x in deg] == [quatnav.UnitWarning], p.stem
    w = _caught(lambda: quatnav.QuaternionEKF().run(np.degrees(tr.gyr), tr.acc, tr.mag, dt=tr.dt))
    assert {type(x.message) for x in w} == {quatnav.UnitWarning, quatnav.AxesWarning}


def _cli(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "quatnav", *map(str, args)], capture_output=True, text=True, env=env,
                          cwd=cwd, timeout=300)


def test_ahrs_run_names_deg_s_and_z_up(handheld, tmp_path):
    """'ahrs run' on an IMU CSV in deg/s exits 0 with a warning that names the fix, once (the
    filter's own check stays quiet inside the command), and lists it in --json."""
    s = handheld
    hdr = "time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z"
    for name, gyr, acc, expect, category in (
            ("deg", np.degrees(s.imu.gyro), s.imu.accel, "gyro_x/y/z look like deg/s", "UnitWarning"),
            ("up", s.imu.gyro * [1, -1, -1], s.imu.accel * [1, -1, -1], "gravity appears on +z", "AxesWarning")):
        f = tmp_path / f"imu_{name}.csv"
        np.savetxt(f, np.column_stack([s.imu.t, gyr, acc]), delimiter=",", header=hdr, comments="", fmt="%.9g")
        js = tmp_path / f"{name}.json"
        p = _cli("ahrs", "run", "--imu", f, "--out", tmp_path / "o.csv", "--json", js)
        assert p.returncode == 0, p.stderr
        lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("quatnav ahrs run: warning: IMU ") and expect in lines[0], \
            p.stderr
        assert [w for w in json.loads(js.read_text())["warnings"] if expect in w] == [lines[0].split("warning: ", 1)[1]]


def test_pipelines_report_each_warning_once(walk):
    """run_ins and run_ahrs check their inputs with the files' names; the filters inside stay
    quiet: one deg/s warning, kept in the run and issued to the caller."""
    from quatnav import io
    from quatnav.pipeline import run_ahrs, run_ins
    s = walk
    g = s.gps
    log = io.Log(source="walk", imu=io.Imu(t=s.imu.t, gyr=np.degrees(s.imu.gyro), acc=s.imu.accel),
                 gnss=io.Gnss(t=g.t_valid, lat=g.lat, lon=g.lon, h=g.h, vel_n=g.v_n))
    for run in (lambda: run_ins(log), lambda: run_ahrs(log)):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            r = run()
        deg = [x for x in w if issubclass(x.category, quatnav.UnitWarning)]
        assert len(deg) == 1 and str(deg[0].message).startswith("IMU walk: "), [str(x.message) for x in w]
        assert [x for x in r.warnings if isinstance(x, quatnav.UnitWarning)] == [deg[0].message]
