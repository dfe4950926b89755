"""Parameter optimization over several logs: Powell and Latin-hypercube search, the same result
serial, through a process pool and through a dask.distributed cluster; the flatness report."""
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

pytest.importorskip("scipy")
from quatnav.evaluation.optimize import optimize, scenario_heading_metric  # noqa: E402

LOGS = [("handheld_marg", 0, 15.0), ("handheld_marg", 1, 15.0)]


def _quadratic(params, log):
    """A metric with a known optimum: log-space bowl centred at a = log, b = 2 log."""
    return (np.log(params["a"] / log) ** 2 + np.log(params["b"] / (2 * log)) ** 2
            + params.get("offset", 0.0))


def test_powell_finds_a_known_optimum_in_log_space():
    r = optimize(_quadratic, [0.01, 0.04], {"a": (1e-4, 1.0), "b": (1e-4, 1.0)}, base={"offset": 1.0},
                 budget=200)
    # mean of two bowls: optimum at the geometric mean of the centres
    assert r.params["a"] == pytest.approx(0.02, rel=0.01) and r.params["b"] == pytest.approx(0.04, rel=0.01)
    assert r.params["offset"] == 1.0 and len(r.per_log) == 2
    assert all(lo > 0 and hi > 0 for lo, hi in r.flatness.values())   # worse either side
    assert r.flatness["a"][0] == pytest.approx(np.log(0.9) ** 2, rel=0.05)


def test_lhs_is_a_seeded_sample_within_bounds():
    r1 = optimize(_quadratic, [0.01], {"a": (1e-3, 1.0), "b": (1e-3, 1.0)}, method="lhs", budget=30, seed=3)
    r2 = optimize(_quadratic, [0.01], {"a": (1e-3, 1.0), "b": (1e-3, 1.0)}, method="lhs", budget=30, seed=3)
    assert r1.params == r2.params and r1.evaluations == 30
    assert all(1e-3 <= p["a"] <= 1.0 for p, _ in r1.history)
    assert r1.score == min(s for _, s in r1.history[:30])


def test_bad_arguments():
    with pytest.raises(ValueError, match="0 < low < high"):
        optimize(_quadratic, [1.0], {"a": (0.0, 1.0)})
    with pytest.raises(ValueError, match="method"):
        optimize(_quadratic, [1.0], {"a": (0.1, 1.0)}, method="grid")
    with pytest.raises(ValueError, match="logs"):
        optimize(_quadratic, [], {"a": (0.1, 1.0)})


@pytest.fixture(scope="module")
def serial_sweep():
    return optimize(scenario_heading_metric(), LOGS, {"mag_sigma": (0.02, 3.0)}, method="lhs", budget=3, seed=1)


def test_filter_sweep_on_simulated_logs(serial_sweep):
    r = serial_sweep
    assert len(r.per_log) == 2 and np.all(np.isfinite(r.per_log)) and r.score < 5.0
    assert set(r.flatness) == {"mag_sigma"}


def test_process_pool_gives_the_serial_result(serial_sweep):
    with ProcessPoolExecutor(max_workers=2) as ex:
        r = optimize(scenario_heading_metric(), LOGS, {"mag_sigma": (0.02, 3.0)}, method="lhs", budget=3, seed=1,
                     executor=ex)
    assert r.params == serial_sweep.params and r.per_log == serial_sweep.per_log
    assert r.flatness == serial_sweep.flatness


def test_dask_distributed_cluster_gives_the_serial_result(serial_sweep):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        r = optimize(scenario_heading_metric(), LOGS, {"mag_sigma": (0.02, 3.0)}, method="lhs", budget=3, seed=1,
                     executor=client.get_executor())
    assert r.params == serial_sweep.params and r.per_log == serial_sweep.per_log
    assert r.flatness == serial_sweep.flatness


def test_tune_command_user_errors(tmp_path):
    import os
    import subprocess
    import sys
    from pathlib import Path

    import quatnav
    # Without the shared data (as an installed package run elsewhere): the mistakes in the
    # arguments are still the ones reported.
    env = dict(os.environ, PYTHONPATH=str(Path(quatnav.__file__).resolve().parents[1]),
               QUATNAV_DATA=str(tmp_path / "no-data"))
    for args, expect in ((["--param", "gyro_noise=1:0.1"], "0 < LOW < HIGH"),
                         (["--param", "gyro_noise"], "NAME=LOW:HIGH"),
                         ([], "at least one --param"),
                         (["/nonexistent", "--param", "gyro_noise=1e-3:1e-1"], "/nonexistent: no such file or folder"),
                         (["--param", "gyro_noise=1e-3:1e-1", "--set", "acc_sigma=x"], "--set acc_sigma=x"),
                         (["--param", "gyro_noise=1e-3:1e-1", "--set", "nope=1"], "--set")):
        p = subprocess.run([sys.executable, "-m", "quatnav", "tune", *args], capture_output=True, text=True,
                           env=env, timeout=120)
        assert p.returncode == 2 and expect in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr


# ----------------------------------------------------------------------------------------------
# The GNSS/INS metric: horizontal RMS of GpsInsFilter against the truth or RTK
# ----------------------------------------------------------------------------------------------
SIM_LOGS = ["sim:paper004_walk:1", "sim:paper001_constant_turn:0"]


@pytest.fixture(scope="module")
def gnss_serial():
    from quatnav.evaluation.optimize import gnss_ins_metric
    return optimize(gnss_ins_metric(), SIM_LOGS, {"gps_vel_sigma": (0.02, 1.0)}, method="lhs", budget=3, seed=2)


def test_gnss_ins_metric_is_the_horizontal_rms_against_the_truth(gnss_serial):
    import quatnav
    from quatnav.core import earth as E
    from quatnav.evaluation.optimize import gnss_ins_metric, parse_gnss_ins_log
    from quatnav.sim import make_scenario
    r = gnss_serial
    assert len(r.per_log) == 2 and np.all(np.isfinite(r.per_log)) and set(r.flatness) == {"gps_vel_sigma"}
    # recomputed by hand for one log at the best parameters
    s = make_scenario("paper001_constant_turn", seed=0)
    g = s.gps
    res = quatnav.GpsInsFilter(lever_arm_b=(0.8, 0.3, -0.9), gps_vel_sigma=r.params["gps_vel_sigma"]).run(
        s.imu.gyro, s.imu.accel, t=s.imu.t, on_invalid="skip",
        gps_pos=quatnav.Aid(g.t, np.column_stack([g.lat, g.lon, g.h]), np.broadcast_to([0.01, 0.01, 0.02], (len(g.t), 3))),
        gps_vel=quatnav.Aid(g.t, g.v_n, np.full((len(g.t), 3), 0.02)))
    m = res.navigating
    d = E.geodetic_to_ned(res.lat[m], res.lon[m], res.h[m], s.truth.lat[0], s.truth.lon[0], s.truth.h[0]) \
        - s.truth.pos_n[s.imu.index[m]]
    assert r.per_log[1] == pytest.approx(np.sqrt(np.mean(d[:, 0] ** 2 + d[:, 1] ** 2)), rel=1e-12)
    # an accelerometer noise far too large (the INS ignored, every fix followed) is worse: the
    # metric sees the filter's tuning (0.80 against 0.41 m when measured)
    f = gnss_ins_metric()
    assert f({"acc_noise": 10.0}, SIM_LOGS[0]) > 1.5 * f({}, SIM_LOGS[0])
    assert parse_gnss_ins_log("walk-degraded") == ("walk", "degraded")
    with pytest.raises(ValueError, match="sim:NAME"):
        parse_gnss_ins_log("sim:")


def test_gnss_ins_metric_process_pool_and_dask_give_the_serial_result(gnss_serial):
    from quatnav.evaluation.optimize import gnss_ins_metric
    kw = dict(method="lhs", budget=3, seed=2)
    with ProcessPoolExecutor(max_workers=2) as ex:
        r = optimize(gnss_ins_metric(), SIM_LOGS, {"gps_vel_sigma": (0.02, 1.0)}, executor=ex, **kw)
    assert r.params == gnss_serial.params and r.per_log == gnss_serial.per_log and r.flatness == gnss_serial.flatness
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        r = optimize(gnss_ins_metric(), SIM_LOGS, {"gps_vel_sigma": (0.02, 1.0)}, executor=client.get_executor(), **kw)
    assert r.params == gnss_serial.params and r.per_log == gnss_serial.per_log


@pytest.mark.data
def test_gnss_ins_metric_on_the_walk_and_navego(data_dir):
    from quatnav.evaluation.optimize import gnss_ins_metric
    if not (data_dir / "gnss_imu_walk").is_dir() or not (data_dir / "navego_synthetic").is_dir():
        pytest.skip("walk or NaveGo data absent")
    f = gnss_ins_metric(seconds=60.0, directory=data_dir)
    walk_rtk, walk_deg, nav = f({}, "walk"), f({}, "walk-degraded"), f({}, "navego")
    # the filter fed RTK stays at the RTK fixes; fed 2.5 m GNSS it is off by a fraction of that
    assert walk_rtk < 0.1 and 0.1 < walk_deg < 2.5 and 0.1 < nav < 3.0
    assert f({"gyro_noise": 1e-5}, "walk-degraded") != walk_deg   # the parameters reach the filter


def test_tune_gnss_ins_command(tmp_path):
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    import quatnav
    env = dict(os.environ, PYTHONPATH=str(Path(quatnav.__file__).resolve().parents[1]))
    js = tmp_path / "t.json"
    p = subprocess.run([sys.executable, "-m", "quatnav", "tune", "--target", "gnss-ins", "--logs",
                        "sim:paper001_constant_turn", "--param", "gps_vel_sigma=0.02:1", "--method", "lhs",
                        "--budget", "2", "--json", str(js)], capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    got = json.loads(js.read_text())
    assert got["target"] == "gnss-ins" and got["unit"] == "m" and list(got["per_log"]) == ["sim:paper001_constant_turn"]
    assert "sim:paper001_constant_turn:" in p.stdout
    for args, expect in ((["--logs", "sim:nope"], "unknown scenario 'nope'"), (["--logs", "bogus"], "--logs: log 'bogus'"),
                         (["--logs", "walk", "/nonexistent"], "no gnss_imu_walk folder"),
                         (["--logs", "sim:paper004_walk", "--param", "gyro_sigma=1:2"], "--param")):
        q = subprocess.run([sys.executable, "-m", "quatnav", "tune", "--target", "gnss-ins", "--param",
                            "gyro_noise=1e-4:1e-2", *args], capture_output=True, text=True, env=env, timeout=120)
        assert q.returncode == 2 and expect in q.stderr and len(q.stderr.strip().splitlines()) == 1, q.stderr


def test_tune_help_examples_name_real_parameters():
    """Every example of `quatnav tune -h` names parameters its filter has."""
    import re
    import quatnav
    from quatnav.cli.ahrs import FILTERS
    from quatnav.evaluation.optimize import TUNE_EPILOG
    text = TUNE_EPILOG.replace("\\\n", " ")
    examples = [ln for ln in text.splitlines() if ln.strip().startswith("quatnav tune")]
    assert len(examples) >= 3
    for ex in examples:
        m = re.search(r"--filter (\S+)", ex)
        cls = quatnav.GpsInsFilter if "gnss-ins" in ex else getattr(quatnav, FILTERS[m.group(1) if m else "qekf"])
        names = {p.name for p in cls.PARAMS}
        for p in re.findall(r"--param (\w+)=", ex):
            assert p in names, (ex, p)


def _cli(*args, env=None, timeout=300):
    import os
    import subprocess
    import sys
    from pathlib import Path

    import quatnav
    e = dict(os.environ, PYTHONPATH=str(Path(quatnav.__file__).resolve().parents[1]), **(env or {}))
    return subprocess.run([sys.executable, "-m", "quatnav", "tune", *map(str, args)], capture_output=True, text=True,
                          env=e, timeout=timeout)


def test_default_data_folder_is_not_the_installation(tmp_path):
    """Without QUATNAV_DATA an installed package looks in ./shared/data, never inside itself; no data
    there is one line with exit status 2 that says what to give."""
    import quatnav.datasets as D
    from pathlib import Path
    site = tmp_path / "venv" / "lib" / "python3.11" / "site-packages" / "quatnav" / "datasets" / "__init__.py"
    monkey = Path(D.__file__)
    try:
        D.__file__ = str(site)
        import os
        old = os.environ.pop("QUATNAV_DATA", None)
        cwd = os.getcwd()
        os.chdir(tmp_path)
        try:
            assert D.data_dir() == tmp_path / "shared" / "data"
        finally:
            os.chdir(cwd)
            if old is not None:
                os.environ["QUATNAV_DATA"] = old
    finally:
        D.__file__ = str(monkey)
    p = _cli("--param", "acc_sigma=0.1:1", env={"QUATNAV_DATA": str(tmp_path / "none")})
    line = p.stderr.strip()
    assert p.returncode == 2 and len(line.splitlines()) == 1, p.stderr
    assert "no trials in" in line and "QUATNAV_DATA" in line and "give the folder" in line, line


def test_tune_attitude_on_own_trials(tmp_path):
    """quatnav tune on a user's trials in the generic format (the benchmark's metric)."""
    import json
    from test_benchmark import make_trial
    from quatnav.datasets.trials import save_trial
    for i in range(2):
        save_trial(make_trial(n=1500, seed=i, name=f"t{i}"), tmp_path / f"t{i}.csv", ref_frame="ENU")
    js = tmp_path / "r.json"
    p = _cli(tmp_path, "--mode", "6d", "--param", "acc_sigma=0.05:2", "--method", "lhs", "--budget", "3",
             "--set", "gyro_noise=0.005", "--json", js)
    assert p.returncode == 0, p.stderr
    got = json.loads(js.read_text())
    assert got["target"] == "attitude" and got["unit"] == "deg" and sorted(got["per_log"]) == ["t0", "t1"]
    assert got["params"]["gyro_noise"] == 0.005 and 0.05 <= got["params"]["acc_sigma"] <= 2
    from quatnav.evaluation.optimize import attitude_metric
    from quatnav.evaluation.benchmark import resolve_sources
    spec = resolve_sources([tmp_path / "t0.csv"])[0]
    direct = attitude_metric(mode="6D")({"acc_sigma": got["params"]["acc_sigma"], "gyro_noise": 0.005}, spec)
    assert got["per_log"]["t0"] == pytest.approx(direct)


def test_tune_gnss_ins_on_own_log(tmp_path):
    """A user's GNSS/INS log (IMU and GNSS CSV files) scored against its own GNSS at held-out outages."""
    import json
    from quatnav.evaluation.optimize import held_out_outages, log_outage_error
    from quatnav.sim import make_scenario
    s = make_scenario("paper004_walk", seed=0)
    imu, g = s.imu, s.gps
    np.savetxt(tmp_path / "imu.csv", np.column_stack([imu.t, imu.gyro, imu.accel]), delimiter=",",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z", comments="", fmt="%.17g")
    np.savetxt(tmp_path / "gnss.csv", np.column_stack([g.t_stamp, np.degrees(g.lat), np.degrees(g.lon), g.h, g.v_n]),
               delimiter=",", header="time,lat,lon,h,v_n,v_e,v_d", comments="", fmt="%.17g")
    outs = held_out_outages(g.t_stamp, 2, 8.0)
    assert len(outs) == 2 and outs[0][0] >= g.t_stamp[0] + 30 and outs[-1][1] <= g.t_stamp[-1] - 8.0
    log = f"{tmp_path / 'imu.csv'}+{tmp_path / 'gnss.csv'}"
    lever = tuple(float(x) for x in s.params["gps"]["lever_arm_b_m"])
    e = log_outage_error({"lever_arm_b": lever}, log, 2, 8.0)
    assert 0.05 < e < 10.0  # meters of drift in 8 s outages of a MEMS IMU, not zero, not lost
    assert log_outage_error({"lever_arm_b": lever, "acc_noise": 3.0}, log, 2, 8.0) != e
    js = tmp_path / "g.json"
    p = _cli("--target", "gnss-ins", "--logs", log, "--outages", "2", "--outage-length", "8", "--set",
             "lever_arm_b=" + ",".join(map(str, lever)), "--param", "gps_vel_sigma=0.02:1", "--method", "lhs",
             "--budget", "2", "--json", js)
    assert p.returncode == 0, p.stderr
    assert list(json.loads(js.read_text())["per_log"]) == [log]
    # an IMU in g: one warning named by the file, before the evaluations, which do not repeat it
    import warnings
    import quatnav
    from quatnav.evaluation.optimize import log_warnings
    assert log_warnings(log) == []
    np.savetxt(tmp_path / "imu_g.csv", np.column_stack([imu.t, imu.gyro, imu.accel / 9.80665]), delimiter=",",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z", comments="", fmt="%.17g")
    log_g = f"{tmp_path / 'imu_g.csv'}+{tmp_path / 'gnss.csv'}"
    w = log_warnings(log_g)
    assert [type(x) for x in w] == [quatnav.UnitWarning] and "imu_g.csv" in str(w[0]) and "like g" in str(w[0])
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        log_outage_error({"lever_arm_b": lever}, log_g, 2, 8.0)
    assert not [r for r in rec if issubclass(r.category, quatnav.PlausibilityWarning)], [str(r.message) for r in rec]
    q = _cli("--target", "gnss-ins", "--logs", tmp_path / "imu.csv", "--param", "gps_vel_sigma=0.02:1")
    assert q.returncode == 2 and "no GNSS data" in q.stderr and len(q.stderr.strip().splitlines()) == 1, q.stderr
