"""The simulated car (``car_city``): the IMU integrated back to the trajectory through its
mounting, the mounting and GNSS latency are what the parameters say, the stops are at rest, the
start is already accelerating, the outage has no fix, the odometer and magnetometer measure what
they should; ``quatnav simulate car_city --csv DIR`` writes files ``quatnav ins run`` reads."""
from __future__ import annotations

import tomllib

import numpy as np
import pandas as pd
import pytest

from quatnav.core import earth
from quatnav.core import quaternion as quat
from quatnav.core.strapdown import StrapdownState
from quatnav.sim import make_scenario
from quatnav.sim.sensors import earth_field_n


@pytest.fixture(scope="module")
def ideal():
    """car_city with an ideal IMU (no noise, bias, quantization): the samples are the truth."""
    return make_scenario("car_city", seed=1, imu_errors=False)


@pytest.fixture(scope="module")
def car():
    return make_scenario("car_city", seed=1)


def _att_err_deg(a, b):
    return np.degrees(np.linalg.norm(quat.to_rotvec(quat.mul(quat.conj(a), b)), axis=-1))


def test_imu_integrated_through_the_mounting_returns_the_trajectory(ideal):
    from quatnav.filters.strapdown import strapdown_run_cpp
    s, tr = ideal, ideal.truth
    C = np.asarray(s.params["sensor_model"]["C_b_imu"])       # what the parameters say
    gyro_b, accel_b = s.imu.gyro @ C.T, s.imu.accel @ C.T      # x_b = C_b_imu x_imu
    st = StrapdownState(tr.q_nb[0], tr.v_n[0], tr.lat[0], tr.lon[0], tr.h[0])
    out = strapdown_run_cpp(st, gyro_b[1:], accel_b[1:], tr.dt)
    pos = earth.geodetic_to_ned(out["lat"], out["lon"], out["h"], tr.lat[0], tr.lon[0], tr.h[0])
    # 203.5 s at 200 Hz, turns and stops: the strapdown's own error over the whole drive
    assert np.linalg.norm(pos - tr.pos_n[1:], axis=1).max() < 0.01
    assert _att_err_deg(out["q_nb"], tr.q_nb[1:]).max() < 1e-4
    # without the mounting the same samples go nowhere near the trajectory
    bad = strapdown_run_cpp(st, s.imu.gyro[1:2001], s.imu.accel[1:2001], tr.dt)
    assert np.linalg.norm(bad["v_n"] - tr.v_n[1:2001], axis=1).max() > 10.0


def test_mounting_is_what_the_parameters_say(ideal):
    s, tr = ideal, ideal.truth
    sm = s.params["sensor_model"]
    q = quat.from_euler(np.radians(sm["imu_mounting_rpy_deg"]))
    assert sm["imu_mounting_rpy_deg"] == [2.0, -3.0, 90.0]
    np.testing.assert_allclose(sm["q_b_imu"], q, atol=1e-15)
    np.testing.assert_allclose(s.imu.q_b_imu, q, atol=1e-15)
    np.testing.assert_allclose(sm["C_b_imu"], quat.to_rotmat(q), atol=1e-15)
    # the samples are the body-frame truth seen in the IMU axes: x_imu = C_b_imu^T x_b
    C = quat.to_rotmat(q)
    np.testing.assert_allclose(s.imu.gyro[1:], tr.omega_mean_b[1:] @ C, atol=1e-12)
    np.testing.assert_allclose(s.imu.accel[1:], tr.f_mean_b[1:] @ C, atol=1e-12)
    # the magnetometer is in the IMU's package: the same axes
    m_b = quat.rotate_inv(tr.q_nb[s.mag.index], np.broadcast_to(s.mag.field_n, (len(s.mag.t), 3)))
    hard = np.array([8.0, -5.0, 3.0]) * 1e-6
    resid = s.mag.mag - hard - m_b @ C
    assert np.std(resid) < 0.5e-6 and np.abs(resid.mean(0)).max() < 0.05e-6   # the 0.3 uT noise only
    assert np.allclose(s.mag.field_n, earth_field_n(type("M", (), {"intensity_uT": 50.0, "inclination_deg": 53.0,
                                                                   "declination_deg": -8.5})()))


def test_upside_down_variant():
    s = make_scenario("car_city_upside_down", seed=1, imu_errors=False)
    assert s.params["sensor_model"]["imu_mounting_rpy_deg"] == [180.0, 0.0, 0.0]
    stop = s.params["events"]["stops"][0]
    at_rest = (s.imu.t > stop[0] + 0.1) & (s.imu.t < stop[1] - 0.1)
    f = s.imu.accel[at_rest].mean(0)
    # forward-left-up axes: gravity's reaction on +z, and the forward acceleration of the
    # moving start still on +x
    assert f[2] == pytest.approx(9.8, abs=0.05) and abs(f[0]) < 1e-6 and abs(f[1]) < 1e-6
    assert s.imu.accel[1, 0] > 3.9 and abs(s.imu.accel[1, 1]) < 1e-3  # Coriolis only


def test_latency_and_time_stamps(ideal):
    s, tr, g = ideal, ideal.truth, ideal.gps
    sm = s.params["sensor_model"]
    assert sm["gnss_latency_s"] == 0.125 and sm["gnss_time_stamp"] == "delivery"
    np.testing.assert_allclose(g.t - g.t_valid, 0.125, atol=1e-9)
    np.testing.assert_array_equal(g.t_stamp, g.t)       # the receiver stamps fixes on arrival
    # the position of a fix (noise removed with the fix's own noise: compare the antenna truth)
    lever = np.array(sm["lever_arm_b_m"])
    ant = tr.pos_n + quat.rotate(tr.q_nb, np.broadcast_to(lever, tr.pos_n.shape))
    err_valid = np.linalg.norm(g.pos_n - ant[g.index_valid], axis=1)
    err_stamp = np.linalg.norm(g.pos_n - ant[g.index], axis=1)
    moving = np.linalg.norm(tr.v_n[g.index_valid], axis=1) > 5.0
    # against the truth at the time of validity: the receiver's noise (0.3/0.6 m); at the stamp:
    # 0.125 s of driving (over 0.6 m at more than 5 m/s) more
    assert np.sqrt(np.mean(err_valid[moving] ** 2)) < 0.8
    assert np.median(err_stamp[moving] - err_valid[moving]) > 0.5
    # the written file carries the late stamps
    assert s.params["gps"]["latency_s"] == 0.125 and s.params["gps"]["time_stamp"] == "delivery"


def test_stops_are_at_rest_and_the_start_accelerates(ideal):
    s, tr = ideal, ideal.truth
    ev = s.params["events"]
    assert len(ev["stops"]) == 3 and all(b - a >= 6.0 for a, b in ev["stops"])
    for a, b in ev["stops"]:
        k = (tr.t > a) & (tr.t <= b)   # the sample at t = a ends the braking interval
        assert np.abs(tr.v_n[k]).max() < 1e-9 and np.abs(tr.omega_nb_b[k]).max() < 1e-9
        # the IMU senses gravity and the Earth's rate only
        fi = s.imu.accel[k[s.imu.index]]
        assert np.abs(np.linalg.norm(fi, axis=1) - earth.gravity(tr.lat[k][0], tr.h[k][0])).max() < 1e-6
        assert np.abs(np.linalg.norm(s.imu.gyro[k[s.imu.index]], axis=1) - earth.OMEGA_IE).max() < 1e-9
    # moving from the first sample, accelerating at about 4 m/s^2 along the track
    v0 = tr.v_n[0]
    assert np.linalg.norm(v0) == pytest.approx(2.0)
    a_along = tr.a_n[:5] @ v0 / np.linalg.norm(v0)
    assert np.all((a_along > 3.9) & (a_along < 4.1))
    assert ev["moving_start"]["accel_m_s2"] == pytest.approx(a_along[0])
    # levelling from the accelerometer at t = 0 is off by about atan(4 / 9.8)
    f_b = tr.f_ib_b[0]
    pitch_from_acc = np.arctan2(f_b[0], np.hypot(f_b[1], f_b[2]))
    assert abs(np.degrees(pitch_from_acc - tr.rpy[0, 1])) > 20.0


def test_outage_turns_and_odometer(ideal, car):
    s, tr = ideal, ideal.truth
    (a, b), = s.params["events"]["gnss_outages"]
    assert b - a == 30.0
    assert not np.any((s.gps.t_valid >= a) & (s.gps.t_valid < b))
    assert np.any(np.abs(s.gps.t_valid - (a - 0.1)) < 1e-9) and np.any(np.abs(s.gps.t_valid - b) < 1e-9)
    # a turn inside the outage
    k = (tr.t >= a) & (tr.t < b)
    assert np.degrees(np.abs(tr.omega_nb_b[k, 2]).max()) > 10.0
    # the odometer gives the forward body speed, with its 0.3 % scale error and 0.01 m/s steps
    o = car.odometer
    v_b = quat.rotate_inv(tr.q_nb[o.index], tr.v_n[o.index])
    assert np.abs(v_b[:, 1:]).max() < 1e-9            # a car does not slide: no lateral/vertical speed
    moving = v_b[:, 0] > 5.0
    ratio = np.median(o.speed[moving] / v_b[moving, 0])
    assert ratio == pytest.approx(1.003, abs=5e-4)
    np.testing.assert_allclose(np.round(o.speed / 0.01) * 0.01, o.speed, atol=1e-12)


def test_noisy_imu_errors_are_in_the_imu_frame(car):
    s, tr = car, car.truth
    C = np.asarray(s.params["sensor_model"]["C_b_imu"])
    err = s.imu.gyro[1:] - tr.omega_mean_b[1:] @ C - s.imu.gyro_bias[1:]
    assert np.abs(err.mean(0)).max() < 2e-4                      # white noise and quantization only
    np.testing.assert_allclose(s.imu.gyro_bias[0], np.radians(np.array([300.0, -250.0, 400.0]) / 3600.0),
                               atol=np.radians(30 / 3600.0))
    assert not s.imu.saturated.any()


def test_simulate_car_writes_ins_run_files(tmp_path, capsys):
    from quatnav import cli
    d = tmp_path / "car"
    assert cli.main(["simulate", "car_city", "--seed", "2", "--csv", str(d)]) == 0
    for f in ("imu.csv", "gnss.csv", "mag.csv", "odometer.csv", "config.toml", "scenario.toml", "truth.csv"):
        assert (d / f).exists(), f
    sc = tomllib.loads((d / "scenario.toml").read_text())
    assert sc["imu"]["mounting_rpy_deg"] == [2.0, -3.0, 90.0]
    assert sc["gnss"] == {"lever_arm_b_m": [-0.4, 0.2, -1.4], "latency_s": 0.125, "time_stamp": "delivery"}
    assert sc["events"]["gnss_outages"] == [[102.5, 132.5]]
    assert sc["mag"]["declination_deg"] == -8.5 and sc["mag"]["hard_iron_uT"] == [8.0, -5.0, 3.0]
    s = make_scenario("car_city", seed=2)
    g = pd.read_csv(d / "gnss.csv")
    np.testing.assert_allclose(g["time"], s.gps.t_valid + 0.125, atol=1e-9)   # stamped late
    imu = pd.read_csv(d / "imu.csv")
    np.testing.assert_allclose(imu[["gyro_x", "gyro_y", "gyro_z"]].to_numpy(), s.imu.gyro, rtol=1e-15, atol=0)
    # 'ins run' reads them (its result without the mounting and latency is not judged here)
    out = tmp_path / "out.csv"
    rc = cli.main(["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"),
                   "--config", str(d / "config.toml"), "--out", str(out)])
    assert rc in (0, 1) and out.exists()
    # the IMU yawed by 90 deg: named, with the yaw that imu_rotation needs
    import re
    err = capsys.readouterr().err
    m = re.search(r"travels at (\S+) deg from the body x axis.*add a yaw of (\S+) rad", err)
    assert m and abs(float(m.group(1)) + 90.0) <= 2.0 and abs(np.degrees(float(m.group(2))) - 90.0) < 2.0, err
    C = sc["imu"]["C_b_imu"]
    (d / "mounted.toml").write_text((d / "config.toml").read_text().replace("[filter]\n", f"[filter]\nimu_rotation = {C}\n"))
    rc = cli.main(["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"),
                   "--config", str(d / "mounted.toml"), "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 0 and "travels at" not in err and "headings gated out" not in err
    # its magnetometer, hard iron uncalibrated and declination not given: most headings gated out, said
    rc = cli.main(["ins", "run", "--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"), "--mag", str(d / "mag.csv"),
                   "--config", str(d / "mounted.toml"), "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 0 and re.search(r"magnetometer: \d+ of \d+ headings gated out .*--mag-calibrate", err), err
