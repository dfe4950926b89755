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


def test_tune_command_user_errors():
    import os
    import subprocess
    import sys
    from pathlib import Path

    import quatnav
    env = dict(os.environ, PYTHONPATH=str(Path(quatnav.__file__).resolve().parents[1]))
    for args, expect in ((["--param", "gyro_noise=1:0.1"], "0 < LOW < HIGH"),
                         (["--param", "gyro_noise"], "NAME=LOW:HIGH"),
                         ([], "at least one --param"),
                         (["/nonexistent", "--param", "gyro_noise=1e-3:1e-1"], "no BROAD trials")):
        p = subprocess.run([sys.executable, "-m", "quatnav", "tune", *args], capture_output=True, text=True,
                           env=env, timeout=120)
        assert p.returncode == 2 and expect in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
