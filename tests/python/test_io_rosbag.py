"""ROS 1 and ROS 2 bags written with rosbags from a simulated rotation, read back by
quatnav.io: the truth is recovered (ENU/FLU converted to NED/FRD), and ``ahrs run --log`` on
the bag gives what the Python API gives on the same arrays."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rosbags")

import quatnav  # noqa: E402
from quatnav import cli, io  # noqa: E402
from quatnav.core import quaternion as Q  # noqa: E402
from quatnav.demo import rotation_scenario  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from _formats import write_bag  # noqa: E402

T0 = 1_700_000_000.0
LAT, LON, H = math.radians(47.3977), math.radians(8.5456), 488.0


def _write(path, version, s):
    """The rotation as a bag: Imu (with the truth as orientation), MagneticField, and a
    NavSatFix every 20th sample with E, N, U variances 4, 9, 16 m^2."""
    k = np.arange(0, len(s.t), 20)
    write_bag(path, version, T0, imu=(s.t, s.gyr, s.acc), mag=(s.t, s.mag * 1e-6), q_nb=s.q_nb,
              fix=(s.t[k], np.full(len(k), LAT), np.full(len(k), LON), np.full(len(k), H),
                   np.tile([3.0, 2.0, 4.0], (len(k), 1))))


@pytest.fixture(scope="module")
def sim():
    return rotation_scenario(n=600, rate=100.0, seed=4)


@pytest.mark.parametrize("version", [1, 2])
def test_bag_round_trip(tmp_path, sim, version):
    p = tmp_path / ("run.bag" if version == 1 else "run")
    _write(p, version, sim)
    log = io.read(p)
    assert log.format == "rosbag"
    np.testing.assert_allclose(log.imu.t, T0 + sim.t, atol=2e-9 * T0)
    np.testing.assert_allclose(log.imu.gyr, sim.gyr, atol=1e-12)
    np.testing.assert_allclose(log.imu.acc, sim.acc, atol=1e-12)
    np.testing.assert_allclose(log.mag.values * 1e6, sim.mag, atol=1e-9)
    e = Q.mul(log.reference.quat, Q.conj(sim.q_nb))
    assert np.all(np.abs(e[:, 0]) > 1 - 1e-12)  # q_nb recovered up to sign
    g = log.gnss
    assert len(g.t) == 30
    np.testing.assert_allclose(g.sigma[0], [3.0, 2.0, 4.0])  # N, E, D from the ENU covariance
    assert g.lat[0] == pytest.approx(LAT) and g.h[0] == pytest.approx(H)
    with pytest.raises(ValueError, match=r"no topic '/nope'"):
        io.read(p, imu_topic="/nope")
    with pytest.raises(ValueError, match=r"'/fix' is sensor_msgs/msg/NavSatFix, not sensor_msgs/msg/Imu"):
        io.read(p, imu_topic="/fix")


def test_bag_ahrs_run_equals_api(tmp_path, sim):
    p = tmp_path / "run"
    _write(p, 2, sim)
    out, js = tmp_path / "a.csv", tmp_path / "c.json"
    assert cli.main(["ahrs", "run", "--log", str(p), "--out", str(out)]) == 0
    import pandas as pd
    df = pd.read_csv(out)
    r = quatnav.QuaternionEKF().run(sim.gyr, sim.acc, sim.mag * 1e-6, t=T0 + sim.t, on_invalid="skip")
    np.testing.assert_allclose(df[["q_w", "q_x", "q_y", "q_z"]].to_numpy(), r.quat, atol=1e-6)
    assert cli.main(["compare", str(out), str(p), "--json", str(js)]) == 0  # against the bag's own orientation
    got = json.loads(js.read_text())
    from quatnav.evaluation.track_difference import attitude_difference, stats
    d = attitude_difference(r.t, r.quat, T0 + sim.t, sim.q_nb)
    assert got["attitude_inclination_deg"]["rms"] == pytest.approx(stats(d["inclination_deg"])["rms"], abs=1e-4)
