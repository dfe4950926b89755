"""``quatnav demo --plot``: the command the README starts with, run as a user runs it."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
# the folder holding the quatnav this test session imported (installed, or the source tree with
# its compiled module): the subprocess must run the same package
PACKAGE_DIR = str(Path(__import__("quatnav").__file__).resolve().parents[1])


def _run_demo(*args, cwd):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [PACKAGE_DIR, *filter(None, [os.environ.get("PYTHONPATH")])]), MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-m", "quatnav", "demo", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def test_demo_prints_tables_and_writes_figure(tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("scipy")  # the navigation parts of the demo need quatnav.sim
    png = tmp_path / "out" / "demo.png"  # a folder that does not exist yet
    p = _run_demo("--plot", str(png), cwd=tmp_path)
    assert p.returncode == 0, p.stderr[-3000:]
    out = p.stdout
    # The three tables, each with its rows.
    for line in ("quatnav demo: simulated rotation", "QuaternionEKF paper", "EulerEKF", "MargFilter+bias",
                 "NavFilter13 (paper 002)", "second_order", "ukf",
                 "GpsInsFilter (paper 004)", "static", "turntable", "walk"):
        assert line in out, f"{line!r} missing from the demo's output:\n{out}"
    # The gyro bias is given in deg/s (the scenario's 0.02 rad/s is 1.15 deg/s), not as 4125 deg/h.
    assert "gyro bias [+1.15 -0.86 +0.57] deg/s" in out
    assert "4125" not in out
    # And the figure, named at the end.
    assert out.rstrip().splitlines()[-1] == f"figure written to {png}"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import matplotlib.image as mpimg
    img = mpimg.imread(png)
    assert img.shape[0] > 800 and img.shape[1] > 1200
    # Not blank: many distinct colours, and well away from a single-colour image.
    rgb = (img[..., :3] * 255).astype(np.uint8).reshape(-1, 3)
    assert len(np.unique(rgb, axis=0)) > 200
    assert (rgb.min(axis=1) < 200).mean() > 0.03


def test_demo_table_rows_match_the_returned_figures(capsys):
    """The numbers printed are the numbers returned (attitude part; the bias error in deg/s)."""
    from quatnav.demo import run_demo
    pytest.importorskip("scipy")
    res = run_demo()
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("QuaternionEKF paper"))
    v = res["QuaternionEKF paper"]
    vals = [float(x) for x in row[len("QuaternionEKF paper"):].split()]
    assert vals[:4] == pytest.approx([v["roll_rmse_deg"], v["pitch_rmse_deg"], v["yaw_rmse_deg"],
                                      v["bias_err_deg_s"]], abs=6e-4)
    assert v["bias_err_deg_h"] == pytest.approx(3600 * v["bias_err_deg_s"])
    # MargFilter with paper defaults estimates no bias: its error is the whole bias.
    assert res["MargFilter"]["bias_err_deg_s"] == pytest.approx(np.degrees(np.linalg.norm([0.02, -0.015, 0.01])),
                                                                rel=1e-9)
