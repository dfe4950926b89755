"""``quatnav compare`` against a reference in another convention (east-north-up, a
forward-left-up body: most motion-capture systems, BROAD's opt_quat, ROS): the options read it,
the common mismatch (about 180 deg that another convention removes) is named with the option,
and the figure has one panel per quantity both tracks have, velocity included."""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import quatnav
from quatnav import cli
from quatnav.core import quaternion as Q

pytest.importorskip("pandas")
PYTHON_DIR = str(Path(quatnav.__file__).resolve().parent.parent)
#: ENU from NED (x_e = y_n, y_e = x_n, z_e = -z_n) and a forward-left-up body from forward-right-down
Q_ENU_NED = Q.conj(Q.enu_to_ned(np.array([1.0, 0.0, 0.0, 0.0])))
Q_FRD_FLU = np.array([0.0, 1.0, 0.0, 0.0])


@pytest.fixture(scope="module")
def tracks(tmp_path_factory):
    """The handheld scenario's truth as quatnav writes it (NED, FRD), and as an ENU and an
    ENU/FLU reference."""
    from quatnav.sim.scenarios import make_scenario
    d = tmp_path_factory.mktemp("cmp")
    s = make_scenario("handheld_marg", seed=2)
    k = s.imu.index
    t, q = s.imu.t, s.truth.q_nb[k]
    hdr = "time,q_w,q_x,q_y,q_z"
    # the run: the truth with a small known error (0.5 deg about down)
    run = Q.mul(Q.from_rotvec(np.array([0.0, 0.0, np.radians(0.5)])), q)
    for name, quat in (("run", run), ("ned", q), ("enu", Q.mul(Q_ENU_NED, q)),
                       ("enu_flu", Q.mul(Q.mul(Q_ENU_NED, q), Q_FRD_FLU))):
        np.savetxt(d / f"{name}.csv", np.column_stack([t, quat]), delimiter=",", header=hdr, comments="", fmt="%.12g")
    return d


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "quatnav", *map(str, args)], capture_output=True, text=True, env=env,
                          timeout=300)


@pytest.mark.parametrize("ref, options, expect", [
    ("enu", ("--ref-frame", "enu"), "compare with --ref-frame enu (ref_frame='enu')"),
    ("enu_flu", ("--ref-frame", "enu", "--ref-body", "flu"), "compare with --ref-frame enu --ref-body flu"),
])
def test_a_reference_in_enu(tracks, tmp_path, ref, options, expect):
    d = tracks
    js = tmp_path / "c.json"
    p = _cli("compare", d / "run.csv", d / f"{ref}.csv", "--json", js)
    assert p.returncode == 0, p.stderr
    got = json.loads(js.read_text())
    assert got["attitude_total_deg"]["p50"] > 80.0  # read as NED/FRD: the mismatch (180 deg, or 90 with both)
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("quatnav compare: warning: ") and expect in lines[0], p.stderr
    assert got["warnings"] == [lines[0].split("warning: ", 1)[1]]
    p = _cli("compare", d / "run.csv", d / f"{ref}.csv", *options, "--json", js)
    assert p.returncode == 0 and p.stderr == "", p.stderr
    got = json.loads(js.read_text())
    assert got["attitude_total_deg"]["max"] == pytest.approx(0.5, abs=1e-3)  # the run's known error
    assert got["attitude_heading_deg"]["max"] == pytest.approx(0.5, abs=1e-3)
    assert (got["ref_frame"], got["ref_body"]) == (options[1], options[3] if len(options) > 2 else "frd")
    assert "(read as ENU" in p.stdout


def test_a_matching_reference_gets_no_hint(tracks, tmp_path):
    p = _cli("compare", tracks / "run.csv", tracks / "ned.csv")
    assert p.returncode == 0 and p.stderr == "", p.stderr


def test_to_ned_frd_turns_vectors_and_quaternions():
    from quatnav.evaluation.track_difference import to_ned_frd
    v_enu = np.array([[1.0, 2.0, 3.0]])  # east, north, up
    np.testing.assert_array_equal(to_ned_frd(None, v_enu, "enu", "frd")[1], [[2.0, 1.0, -3.0]])
    q = Q.from_euler(np.radians([10.0, -20.0, 30.0]))[None]
    back, _ = to_ned_frd(Q.mul(Q.mul(Q_ENU_NED, q), Q_FRD_FLU), None, "enu", "flu")
    assert abs(abs(np.dot(back[0], q[0])) - 1.0) < 1e-12  # the same rotation (q or -q)
    with pytest.raises(ValueError, match="frame, body"):
        to_ned_frd(q, None, "nwu", "frd")


def _figure_axes(monkeypatch, argv):
    """Run ``quatnav`` in-process and return, per axes of the figure it saves, (ylabel, lines)."""
    pytest.importorskip("matplotlib")
    import matplotlib.figure
    seen = {}
    save = matplotlib.figure.Figure.savefig

    def spy(fig, path, *a, **k):
        seen["axes"] = [(ax.get_ylabel(), len(ax.get_lines()), ax.get_xlabel()) for ax in fig.axes]
        return save(fig, path, *a, **k)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", spy)
    assert cli.main(argv) == 0
    return seen["axes"]


def test_plot_has_a_panel_per_quantity(tracks, tmp_path, monkeypatch):
    """Attitude only: one panel (no empty second one); a navigation track against the truth:
    attitude, position and velocity."""
    axes = _figure_axes(monkeypatch, ["compare", str(tracks / "run.csv"), str(tracks / "ned.csv"), "--plot",
                                      str(tmp_path / "a.png")])
    assert [a[0] for a in axes] == ["attitude difference [deg]"] and axes[0][1] == 2
    d = tmp_path / "walk"
    assert cli.main(["simulate", "paper004_walk", "--seed", "1", "--csv", str(d)]) == 0
    assert cli.main(["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"), "--config",
                     str(d / "config.toml"), "--out", str(tmp_path / "nav.csv")]) == 0
    axes = _figure_axes(monkeypatch, ["compare", str(tmp_path / "nav.csv"), str(d / "truth.csv"), "--plot",
                                      str(tmp_path / "b.png")])
    assert [a[0] for a in axes] == ["attitude difference [deg]", "position difference [m]",
                                    "velocity difference [m/s]"]
    assert all(n == 2 for _, n, _ in axes)
    assert axes[-1][2] == "time [s]"


@pytest.mark.data
def test_broad_against_its_optical_reference(data_dir, tmp_path):
    """BROAD's opt_quat (body to ENU) against 'ahrs run' on the trial's IMU as exported: 179.8 deg
    read as NED, with the hint; 1.3 deg RMS with --ref-frame enu."""
    d = data_dir / "broad"
    trials = sorted(d.glob("02_*.mat")) if d.is_dir() else []
    if not trials:
        pytest.skip(f"no BROAD trial 02 in {d}")
    import scipy.io
    raw = scipy.io.loadmat(trials[0])
    g, a, m, q = (np.asarray(raw[k], float) for k in ("imu_gyr", "imu_acc", "imu_mag", "opt_quat"))
    t = np.arange(len(g)) / float(np.squeeze(raw["sampling_rate"]))
    np.savetxt(tmp_path / "imu.csv", np.column_stack([t, g, a, m]), delimiter=",", comments="", fmt="%.9g",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,mag_x,mag_y,mag_z")
    ok = np.isfinite(q).all(axis=1)
    np.savetxt(tmp_path / "ref.csv", np.column_stack([t[ok], q[ok]]), delimiter=",", comments="", fmt="%.9g",
               header="time,q_w,q_x,q_y,q_z")
    assert _cli("ahrs", "run", "--imu", tmp_path / "imu.csv", "--out", tmp_path / "run.csv").returncode == 0
    js = tmp_path / "c.json"
    p = _cli("compare", tmp_path / "run.csv", tmp_path / "ref.csv", "--json", js)
    assert json.loads(js.read_text())["attitude_total_deg"]["p50"] > 170.0
    assert "--ref-frame enu" in p.stderr
    p = _cli("compare", tmp_path / "run.csv", tmp_path / "ref.csv", "--ref-frame", "enu", "--json", js)
    assert p.returncode == 0 and p.stderr == ""
    assert json.loads(js.read_text())["attitude_total_deg"]["rms"] < 3.0
