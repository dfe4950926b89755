"""ROS 1 and ROS 2 bags written with rosbags from a simulated rotation, read back by
quatnav.io: the truth is recovered (ENU/FLU converted to NED/FRD), and ``ahrs run --log`` on
the bag gives what the Python API gives on the same arrays."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

pytest.importorskip("rosbags")
from rosbags.typesys import Stores, get_typestore  # noqa: E402

import quatnav  # noqa: E402
from quatnav import cli, io  # noqa: E402
from quatnav.core import quaternion as Q  # noqa: E402
from quatnav.demo import rotation_scenario  # noqa: E402
from quatnav.io.rosbag import FLU_TO_FRD, Q_FLU_FRD  # noqa: E402

T0 = 1_700_000_000.0
LAT, LON, H = math.radians(47.3977), math.radians(8.5456), 488.0


def _write(path, version, s):
    ts = get_typestore(Stores.ROS2_HUMBLE if version == 2 else Stores.ROS1_NOETIC)
    T = ts.types
    Header, Time = T["std_msgs/msg/Header"], T["builtin_interfaces/msg/Time"]
    V3, Qm = T["geometry_msgs/msg/Vector3"], T["geometry_msgs/msg/Quaternion"]
    if version == 2:
        from rosbags.rosbag2 import Writer
        w = Writer(path, version=8)
        ser = ts.serialize_cdr
    else:
        from rosbags.rosbag1 import Writer
        w = Writer(path)
        ser = ts.serialize_ros1

    def hdr(t):
        sec = int(t)
        kw = dict(stamp=Time(sec=sec, nanosec=int(round((t - sec) * 1e9))), frame_id="imu")
        return Header(seq=0, **kw) if version == 1 else Header(**kw)

    # the body FLU and nav ENU quantities of the simulated FRD/NED truth
    q_enu_flu = Q.mul(Q.mul(Q.conj(Q.Q_NED_ENU), s.q_nb), Q.conj(Q_FLU_FRD))
    gyr, acc, mag = s.gyr * FLU_TO_FRD, s.acc * FLU_TO_FRD, s.mag * 1e-6 * FLU_TO_FRD
    with w:
        ci = w.add_connection("/imu/data", "sensor_msgs/msg/Imu", typestore=ts)
        cm = w.add_connection("/imu/mag", "sensor_msgs/msg/MagneticField", typestore=ts)
        cg = w.add_connection("/fix", "sensor_msgs/msg/NavSatFix", typestore=ts)
        for k in range(len(s.t)):
            t = T0 + s.t[k]
            ns = int(round(t * 1e9))
            q = q_enu_flu[k]
            m = T["sensor_msgs/msg/Imu"](header=hdr(t), orientation=Qm(x=q[1], y=q[2], z=q[3], w=q[0]),
                                         orientation_covariance=np.zeros(9), angular_velocity=V3(*gyr[k]),
                                         angular_velocity_covariance=np.zeros(9),
                                         linear_acceleration=V3(*acc[k]), linear_acceleration_covariance=np.zeros(9))
            w.write(ci, ns, ser(m, "sensor_msgs/msg/Imu"))
            m = T["sensor_msgs/msg/MagneticField"](header=hdr(t), magnetic_field=V3(*mag[k]),
                                                   magnetic_field_covariance=np.zeros(9))
            w.write(cm, ns, ser(m, "sensor_msgs/msg/MagneticField"))
            if k % 20 == 0:
                st = T["sensor_msgs/msg/NavSatStatus"](status=0, service=1)
                cov = np.diag([4.0, 9.0, 16.0]).ravel()  # E, N, U variances
                m = T["sensor_msgs/msg/NavSatFix"](header=hdr(t), status=st, latitude=math.degrees(LAT),
                                                   longitude=math.degrees(LON), altitude=H,
                                                   position_covariance=cov, position_covariance_type=2)
                w.write(cg, ns, ser(m, "sensor_msgs/msg/NavSatFix"))


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
    from quatnav.compare_cli import attitude_difference, stats
    d = attitude_difference(r.t, r.quat, T0 + sim.t, sim.q_nb)
    assert got["attitude_inclination_deg"]["rms"] == pytest.approx(stats(d["inclination_deg"])["rms"], abs=1e-4)
