"""Noise parameters from the Allan deviation: recovery on simulated sensors, the filter
parameters under each filter's names, the TOML that 'ins run --config' reads, the 'quatnav
allan' command, and static stretches of real data (the shared data folder of conftest.py: skipped
when it is absent)."""
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import quatnav
from quatnav.calibration.noise import FILTER_NOISE, fit_allan, motion_evidence, noise_parameters
from quatnav.filters.tables import PARAM_TABLES

PYTHON_DIR = str(Path(quatnav.__file__).resolve().parents[1])


@pytest.fixture(scope="module")
def simulated():
    """6 h at rest at 5 Hz from quatnav.sim's sensor models: white noise and bias random walk."""
    from quatnav.sim import sensors, trajectory
    traj = trajectory.make_trajectory([trajectory.Rest(20000.0)], 5.0, earth_rate=False)
    spec = sensors.ImuSpec(gyro=sensors.GyroSpec(noise_density_dps_per_sqrt_hz=0.1, rrw_deg_per_h_per_sqrt_h=2000.0),
                           accel=sensors.AccelSpec(noise_density_ug_per_sqrt_hz=200.0, bias_rw_ug_per_sqrt_h=20000.0))
    imu = sensors.simulate_imu(traj, spec, np.random.default_rng(0))
    return imu, spec.gyro.si(), spec.accel.si()


def test_recovers_simulated_white_noise_and_random_walk_within_ten_percent(simulated):
    imu, g, a = simulated
    m = noise_parameters(imu.rate_hz, gyr=imu.gyro, acc=imu.accel)
    assert m.term("gyro", "white") == pytest.approx(g["white_density"], rel=0.10)
    assert m.term("acc", "white") == pytest.approx(a["white_density"], rel=0.10)
    assert m.term("gyro", "bias_rw") == pytest.approx(g["rrw_density"], rel=0.10)
    assert m.term("acc", "bias_rw") == pytest.approx(a["rrw_density"], rel=0.10)
    assert m.bias_source("gyro") == "rate_random_walk"
    for ax in m.gyro:   # each axis within its own stated confidence (3 sigma)
        assert abs(ax.white / g["white_density"] - 1) < 3 * ax.white_rel_err + 0.02
        assert abs(ax.rate_random_walk / g["rrw_density"] - 1) < 3 * ax.rate_random_walk_rel_err + 0.05


def test_filter_parameters_use_each_filters_names_and_ins_run_reads_the_file(simulated, tmp_path):
    imu, g, a = simulated
    m = noise_parameters(imu.rate_hz, gyr=imu.gyro, acc=imu.accel)
    fp = m.filter_params()
    for f, d in fp.items():
        names = {p.name: p for p in PARAM_TABLES[f]}
        assert set(d) == set(FILTER_NOISE[f]) and set(d) <= set(names)
        assert all("sqrt(Hz)" in names[k].unit for k in d)
        getattr(quatnav, f)(**d)   # accepted by the filter
    p = tmp_path / "noise.toml"
    p.write_text(m.to_toml())
    doc = tomllib.loads(p.read_text())
    assert doc["filter"] == fp["GpsInsFilter"] and doc["parameters"]["QuaternionEKF"] == fp["QuaternionEKF"]
    assert len(doc["allan"]["gyro"]["white"]) == 3
    from quatnav.pipeline import load_config
    assert load_config(p) == fp["GpsInsFilter"]


def test_white_noise_only_gives_the_bias_instability_equivalent():
    rng = np.random.default_rng(1)
    x = rng.normal(scale=0.01, size=(20000, 3))
    m = noise_parameters(100.0, gyr=x)
    assert m.term("gyro", "white") == pytest.approx(0.001, rel=0.05)
    assert m.bias_source("gyro") == "bias_instability" and np.isfinite(m.term("gyro", "bias_rw"))
    assert m.acc is None and "acc_noise" not in m.filter_params()["GpsInsFilter"]
    with pytest.raises(ValueError, match="gyr and/or acc"):
        noise_parameters(100.0)


def test_fit_on_exact_curves():
    taus = np.logspace(-2, 3, 60)
    N, K = 1e-3, 1e-5
    adev = np.sqrt(N ** 2 / taus + K ** 2 * taus / 3)
    r = fit_allan(taus, adev, 10 ** 9, 100.0)
    assert r.white == pytest.approx(N, rel=0.02) and r.rate_random_walk == pytest.approx(K, rel=0.05)
    assert r.bias_instability == pytest.approx(adev.min() / 0.664)


def test_allan_command(tmp_path):
    pytest.importorskip("pandas")
    pytest.importorskip("matplotlib")
    rng = np.random.default_rng(2)
    n = 6000
    t = np.arange(n) / 100.0
    gyr = rng.normal(scale=0.01, size=(n, 3))
    acc = rng.normal(scale=0.02, size=(n, 3)) + [0, 0, -9.81]
    np.savetxt(tmp_path / "rest.csv", np.column_stack([t, gyr, acc]), delimiter=",", comments="", fmt="%.9g",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-m", "quatnav", "allan", tmp_path / "rest.csv", "--out", tmp_path / "n.toml",
                        "--plot", tmp_path / "a.png"], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    # white noise alone: no motion, and no bias-instability floor within the log (said so)
    assert "not static" not in p.stderr and "floor was not reached" in p.stderr, p.stderr
    doc = tomllib.loads((tmp_path / "n.toml").read_text())
    assert doc["filter"]["gyro_noise"] == pytest.approx(0.001, rel=0.05)
    assert doc["filter"]["acc_noise"] == pytest.approx(0.002, rel=0.05)
    assert (tmp_path / "a.png").stat().st_size > 1000


GRADES = {  # datasheet-like figures: white noise, bias instability, bias random walk
    "consumer MEMS": (dict(noise_density_dps_per_sqrt_hz=0.01, bias_instability_deg_per_h=10.0, bias_corr_time_s=200.0,
                           rrw_deg_per_h_per_sqrt_h=5.0),
                      dict(noise_density_ug_per_sqrt_hz=150.0, bias_instability_ug=50.0, bias_corr_time_s=200.0,
                           bias_rw_ug_per_sqrt_h=50.0)),
    "tactical": (dict(arw_deg_per_sqrt_h=0.1, bias_instability_deg_per_h=1.0, bias_corr_time_s=300.0),
                 dict(noise_density_ug_per_sqrt_hz=30.0, bias_instability_ug=20.0, bias_corr_time_s=300.0)),
    "navigation": (dict(arw_deg_per_sqrt_h=0.002, bias_instability_deg_per_h=0.003, bias_corr_time_s=1000.0),
                   dict(noise_density_ug_per_sqrt_hz=5.0, bias_instability_ug=5.0, bias_corr_time_s=1000.0)),
}


def _imu(segments, grade, seed=0):
    from quatnav.sim import sensors, trajectory
    g, a = GRADES[grade]
    traj = trajectory.make_trajectory(segments, 100.0, earth_rate=False)
    spec = sensors.ImuSpec(gyro=sensors.GyroSpec(**g), accel=sensors.AccelSpec(**a))
    return sensors.simulate_imu(traj, spec, np.random.default_rng(seed))


@pytest.mark.parametrize("grade", list(GRADES))
def test_motion_evidence_static_versus_moving(grade):
    """20 min at rest with the noise, bias instability and bias random walk of each grade: no
    evidence of motion; the same sensor turned by hand for 20 s in the middle: the gyro says so."""
    from quatnav.sim.trajectory import RandomMotion, Rest
    imu = _imu([Rest(1200.0)], grade)
    assert motion_evidence(imu.t, imu.gyro, imu.accel) is None
    imu = _imu([Rest(600.0), RandomMotion(20.0, amplitude=(0.3, 0.3, 0.6)), Rest(580.0)], grade)
    why = motion_evidence(imu.t, imu.gyro, imu.accel)
    assert why is not None and "1 s mean changes by" in why
    assert 600.0 <= float(why.split("between t = ")[1].split(" s")[0]) <= 621.0
    assert motion_evidence(imu.t, acc=imu.accel) is not None  # the accelerometer alone sees it too


def test_allan_command_warns_of_a_moving_log(tmp_path):
    pytest.importorskip("pandas")
    from quatnav.sim.trajectory import Rest, Rotate
    imu = _imu([Rest(60.0), Rotate("pitch", 4.0, angle=np.pi / 2), Rest(60.0)], "consumer MEMS")
    np.savetxt(tmp_path / "moved.csv", np.column_stack([imu.t, imu.gyro, imu.accel]), delimiter=",", comments="",
               fmt="%.9g", header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-m", "quatnav", "allan", tmp_path / "moved.csv", "--out", tmp_path / "n.toml"],
                       capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("quatnav allan: warning: LOG "), p.stderr
    assert "is not static: the " in lines[0] and "'s 1 s mean changes by " in lines[0] and "--rest-only" in lines[0]
    assert "motion, being signal, would be read as noise" in lines[0]


@pytest.mark.data
def test_static_stretch_of_the_real_walk(data_dir):
    """The longest rest of the gnss_imu_walk log (about 15 s at 166 Hz, near the end).
    Measured: gyro white 1.0e-4, 6.8e-5, 4.7e-5 rad/s/sqrt(Hz); accelerometer 5.8e-4, 7.2e-4,
    3.0e-5 m/s^2/sqrt(Hz) (the z axis looks quantized); the log is far too short for a rate
    random walk (the bias noise comes from the bias-instability equivalent)."""
    from quatnav.datasets import gnss_imu_walk
    from quatnav.calibration import rest_segments
    d = data_dir / "gnss_imu_walk"
    if not (d / "imu_1730_sf.csv").exists():
        pytest.skip(f"gnss_imu_walk data not found in {d}")
    w = gnss_imu_walk.load(d)
    segs = rest_segments(w.imu_t, w.accel_s, w.gyro_s, acc_std=0.05, gyr_std=0.01)
    a, b = max(segs, key=lambda s: s[1] - s[0])
    assert w.imu_t[b - 1] - w.imu_t[a] > 10.0
    assert motion_evidence(w.imu_t[a:b], w.gyro_s[a:b], w.accel_s[a:b]) is None
    m = noise_parameters(1.0 / np.median(np.diff(w.imu_t)), gyr=w.gyro_s[a:b], acc=w.accel_s[a:b])
    assert 1e-5 < m.term("gyro", "white") < 1e-3     # consumer MEMS range
    assert 1e-5 < m.term("acc", "white") < 1e-2
    assert m.bias_source("gyro") == "bias_instability"


@pytest.mark.data
def test_rest_phase_of_a_broad_trial(data_dir):
    """The first rest phase of BROAD trial 02 (40 s at 286 Hz). Measured: gyro white 1.2e-4,
    2.9e-4, 1.1e-4 rad/s/sqrt(Hz), bias instability 6-8e-5 rad/s; accelerometer white 2.6e-3,
    2.9e-3, 4.1e-3 m/s^2/sqrt(Hz)."""
    from quatnav.datasets import broad
    d = data_dir / "broad"
    trials = broad.list_trials(d) if d.is_dir() else []
    if not trials:
        pytest.skip(f"BROAD data not found in {d}")
    tr = broad.load_trial(trials[0])
    rest = ~tr.movement
    edges = np.flatnonzero(np.diff(np.concatenate([[0], rest.astype(int), [0]])))
    a, b = max(zip(edges[::2], edges[1::2]), key=lambda s: s[1] - s[0])
    t = np.arange(len(tr.gyr)) / tr.rate
    assert motion_evidence(t[a:b], tr.gyr[a:b], tr.acc[a:b]) is None
    assert motion_evidence(t, tr.gyr, tr.acc) is not None  # the whole trial moves
    m = noise_parameters(tr.rate, gyr=tr.gyr[a:b], acc=tr.acc[a:b])
    assert 1e-5 < m.term("gyro", "white") < 1e-3
    assert 1e-4 < m.term("acc", "white") < 1e-1


def test_rest_thresholds_from_the_sensors_noise(tmp_path):
    """A noisy accelerometer (0.06 m/s^2 per axis, above the fixed 0.05 m/s^2 of the window's
    deviation): the fixed thresholds find no rest, the ones scaled to the quietest windows find
    the two rests of rest - turn - rest, and `allan --rest-only` takes the longer one quietly."""
    pytest.importorskip("pandas")
    from quatnav.calibration import rest_segments
    from quatnav.sim.trajectory import Rest, Rotate
    imu = _imu([Rest(60.0), Rotate("pitch", 4.0, angle=np.pi / 2), Rest(40.0)], "consumer MEMS")
    acc = imu.accel + np.random.default_rng(1).normal(0.0, 0.06, imu.accel.shape)
    assert rest_segments(imu.t, acc, imu.gyro) == []
    segs = rest_segments(imu.t, acc, imu.gyro, acc_std=None, gyr_std=None)
    assert len(segs) == 2
    (a0, b0), (a1, b1) = segs
    assert imu.t[a0] < 0.5 and 59.0 < imu.t[b0 - 1] < 60.0 and 64.0 < imu.t[a1] < 65.0 and imu.t[b1 - 1] > 103.0
    np.savetxt(tmp_path / "noisy.csv", np.column_stack([imu.t, imu.gyro, acc]), delimiter=",", comments="",
               fmt="%.9g", header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-m", "quatnav", "allan", tmp_path / "noisy.csv", "--rest-only", "--out",
                        tmp_path / "n.toml"], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0 and "not static" not in p.stderr, p.stderr
    # A log that never rests: its quietest windows are motion; the thresholds stay bounded.
    from quatnav.sim.trajectory import RandomMotion
    imu = _imu([RandomMotion(60.0, amplitude=(0.3, 0.3, 0.6))], "consumer MEMS")
    assert rest_segments(imu.t, imu.accel, imu.gyro, acc_std=None, gyr_std=None) == []


@pytest.mark.data
def test_rest_segments_of_the_broad_trials(data_dir):
    """BROAD's protocol rests about 35-45 s at the start and at the end of every trial; the fixed
    0.05 m/s^2 finds none of them (the accelerometer's noise alone is 0.086), the scaled
    thresholds find both in each trial."""
    from quatnav.calibration import rest_segments
    from quatnav.datasets import broad
    d = data_dir / "broad"
    trials = broad.list_trials(d) if d.is_dir() else []
    if not trials:
        pytest.skip(f"BROAD data not found in {d}")
    tr = broad.load_trial(trials[0])
    t = np.arange(len(tr.gyr)) / tr.rate
    assert rest_segments(t, tr.acc, tr.gyr) == []
    segs = rest_segments(t, tr.acc, tr.gyr, acc_std=None, gyr_std=None)
    long = [(a, b) for a, b in segs if t[b - 1] - t[a] > 25.0]
    assert len(long) == 2 and t[long[0][0]] < 1.0 and t[long[1][1] - 1] > t[-1] - 30.0
    for a, b in long:
        assert not tr.movement[a:b].mean() > 0.02  # the dataset's own labels: at rest
        assert motion_evidence(t[a:b], tr.gyr[a:b], tr.acc[a:b]) is None
