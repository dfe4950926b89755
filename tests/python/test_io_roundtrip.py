"""Round trips per format: a simulated run written as RTKLIB .pos (lat/lon, ECEF, ENU), NMEA
(GGA, RMC, HDT), ROS 1 and ROS 2 bags (Imu, NavSatFix, TwistWithCovarianceStamped,
FluidPressure, MagneticField), PX4 ULog (the integral sensor_combined layout) and CSV; read back
by quatnav.io to the format's precision; run by ``quatnav ins run`` / ``quatnav ahrs run`` and
judged by ``quatnav compare`` against the truth: the same figures as the Python API on the same
arrays. Malformed files end the commands with one line and exit status 2."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import quatnav
from quatnav import cli, io
from quatnav.evaluation.track_difference import compare_tracks as compare
from quatnav.core import earth as E
from quatnav.core import quaternion as Q

sys.path.insert(0, str(Path(__file__).parent))
from _formats import (EPOCH, pressure_of_altitude, ulog_integral, write_bag, write_nmea,  # noqa: E402
                      write_pos, write_ulog)

PACKAGE_DIR = str(Path(quatnav.__file__).resolve().parents[1])
QUANTITIES = ("attitude_heading_deg", "attitude_inclination_deg", "position_horizontal_m", "position_vertical_m",
              "velocity_horizontal_m_s")


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """paper004_walk (GNSS 5 Hz with velocity, altimeter, compass), its ins-run CSV files with
    times from EPOCH (formats with a calendar date need them), and the scenario."""
    from quatnav.sim import make_scenario
    from quatnav.sim.io import save_ins_csv
    d = tmp_path_factory.mktemp("walk")
    s = make_scenario("paper004_walk", seed=3)
    save_ins_csv(s, d)
    for f in ("imu", "gnss", "baro", "compass", "truth"):
        x = pd.read_csv(d / f"{f}.csv")
        x["time"] += EPOCH
        x.to_csv(d / f"{f}.csv", index=False, float_format="%.17g")
    return s, d


def _cli_figures(d, tmp_path, args, name, config=None):
    out, js = tmp_path / f"{name}.csv", tmp_path / f"{name}.json"
    assert cli.main(["ins", "run", *args, "--config", str(config or d / "config.toml"), "--out", str(out)]) == 0
    assert cli.main(["compare", str(out), str(d / "truth.csv"), "--json", str(js)]) == 0
    fig = json.loads(js.read_text())
    print(f"\nround trip {name}: " + ", ".join(f"{k} {fig[k]['rms']:.4g}" for k in QUANTITIES))  # pytest -s
    return fig


def _api_figures(d, imu, gnss, baro=None, compass=None, **params):
    """GpsInsFilter on the arrays (io.Log streams), judged with compare() against the truth."""
    lever = [0.1, 0.0, -0.1]
    f = quatnav.GpsInsFilter(lever_arm_b=lever, **params)
    kw = {}
    sig = gnss.sigma
    kw["gps_pos"] = quatnav.Aid(gnss.t, np.column_stack([gnss.lat, gnss.lon, gnss.h]), sig)
    if gnss.vel_n is not None and np.isfinite(gnss.vel_n).all():
        kw["gps_vel"] = quatnav.Aid(gnss.t, gnss.vel_n, gnss.sigma_vel)
    if gnss.quality is not None and gnss.quality_kind:  # the solution kind, as the command passes it
        from quatnav.filters.gpsins import gnss_solution
        kw["gps_solution"] = gnss_solution(gnss.quality, gnss.quality_kind)
    if baro is not None:
        kw["baro"] = quatnav.Aid(baro.t, baro.altitude)
    if compass is not None:
        kw["compass"] = quatnav.Aid(compass.t, compass.heading)
    r = f.run(imu.gyr, imu.acc, t=imu.t, **kw)
    nav = r.navigating
    run = io.Log(source="api", reference=io.Reference(t=r.t[nav], quat=r.quat[nav], lat=r.lat[nav], lon=r.lon[nav],
                                                     h=r.h[nav], vel_n=r.velocity[nav]))
    return compare(run, io.read(d / "truth.csv", kind="reference"))


def _same(cli_fig, api_fig, keys=QUANTITIES):
    for k in keys:
        a, b = cli_fig[k]["rms"], api_fig[k]["rms"]
        # the command's output is rounded (lat/lon 1e-10 deg, the rest 6 significant digits)
        tol = 2e-4 if k.startswith("position") else (1e-4 if k.startswith("velocity") else 2e-4)
        assert a == pytest.approx(b, rel=1e-4, abs=tol), (k, a, b)
        assert cli_fig[k]["n"] == api_fig[k]["n"], k


def _walk_streams(d):
    log = io.read(d / "imu.csv", kind="imu")
    return (log.imu, io.read(d / "baro.csv", kind="baro").baro, io.read(d / "compass.csv", kind="compass").compass)


def test_csv_round_trip(walk, tmp_path):
    s, d = walk
    imu, baro, comp = _walk_streams(d)
    g = io.read(d / "gnss.csv", kind="gnss").gnss
    got = _cli_figures(d, tmp_path, ["--imu", str(d / "imu.csv"), "--gnss", str(d / "gnss.csv"), "--baro",
                                     str(d / "baro.csv"), "--compass", str(d / "compass.csv")], "csv")
    _same(got, _api_figures(d, imu, g, baro, comp))
    assert got["position_horizontal_m"]["rms"] < 3.0


@pytest.mark.parametrize("mode", ["deg", "ecef", "enu"])
def test_rtklib_pos_round_trip(walk, tmp_path, mode):
    s, d = walk
    gs = s.gps
    sig = np.broadcast_to([2.5, 2.5, 5.0], (len(gs.t), 3))
    p = tmp_path / f"sol_{mode}.pos"
    g = write_pos(p, gs.t_valid, gs.lat, gs.lon, gs.h, sig, vel=gs.v_n, mode=mode, q=5)
    # read back to the format's precision: 1e-9 deg / 0.1 mm, the velocity to 1e-6 m/s
    ned = E.geodetic_to_ned(g.lat, g.lon, g.h, gs.lat, gs.lon, gs.h)
    assert np.abs(ned).max() < (2e-4 if mode == "deg" else 3e-4)
    np.testing.assert_allclose(g.t, EPOCH + gs.t_valid, atol=1e-3)
    np.testing.assert_allclose(g.vel_n, gs.v_n, atol=1e-6)
    if mode != "ecef":
        np.testing.assert_allclose(g.sigma, sig, atol=1e-4)
    imu, baro, comp = _walk_streams(d)
    got = _cli_figures(d, tmp_path, ["--imu", str(d / "imu.csv"), "--gnss", str(p), "--baro", str(d / "baro.csv"),
                                     "--compass", str(d / "compass.csv")], f"pos_{mode}")
    _same(got, _api_figures(d, imu, g, baro, comp))


def test_nmea_round_trip_with_true_heading(walk, tmp_path):
    s, d = walk
    gs, cs = s.gps, s.compass
    # the compass at the fixes' times, as the HDT sentence after each GGA
    k = np.searchsorted(cs.t, gs.t_valid)
    speed = np.hypot(gs.v_n[:, 0], gs.v_n[:, 1])
    course = np.arctan2(gs.v_n[:, 1], gs.v_n[:, 0])
    p = tmp_path / "rx.nmea"
    write_nmea(p, gs.t_valid, gs.lat, gs.lon, gs.h, speed=speed, course=course, heading=cs.yaw[k], quality=1)
    log = io.read(p)
    g, c = log.gnss, log.compass
    assert log.format == "nmea" and c.north == "true" and len(c.t) == len(gs.t)
    np.testing.assert_allclose(g.t, EPOCH + gs.t_valid, atol=6e-3)       # hhmmss.ss
    assert np.abs(E.geodetic_to_ned(g.lat, g.lon, g.h, gs.lat, gs.lon, gs.h)).max() < 1.1e-3
    np.testing.assert_allclose(g.vel_n[:, :2], gs.v_n[:, :2], atol=2e-4)   # knots to 1e-4
    np.testing.assert_allclose(np.angle(np.exp(1j * (c.heading - cs.yaw[k]))), 0.0, atol=1e-5)
    np.testing.assert_allclose(g.sigma[0], [2.5, 2.5, 5.0])               # HDOP 1 x 2.5 m (GPS fix)
    imu, baro, _ = _walk_streams(d)
    # NMEA has no vertical velocity: position fixes and the true heading (the file's compass). The
    # fixes are GPS (single) solutions, whose errors the filter takes by default as wandering with
    # gps_error_tau; the simulated ones are white, and the filter is told so.
    cfg = tmp_path / "config.toml"
    cfg.write_text((d / "config.toml").read_text().replace("[filter]\n", "[filter]\ngps_error_tau = 0.0\n"))
    assert "gps_error_tau" in cfg.read_text()
    got = _cli_figures(d, tmp_path, ["--imu", str(d / "imu.csv"), "--gnss", str(p), "--compass", str(p),
                                     "--baro", str(d / "baro.csv")], "nmea", config=cfg)
    g.vel_n = None
    _same(got, _api_figures(d, imu, g, baro, c, gps_error_tau=0.0))
    assert got["position_horizontal_m"]["rms"] < 5.0


@pytest.mark.parametrize("version", [1, 2])
def test_bag_round_trip_ins_run(walk, tmp_path, version):
    pytest.importorskip("rosbags")
    s, d = walk
    imu, baro, _ = _walk_streams(d)
    gs = s.gps
    sig = np.broadcast_to([2.5, 2.5, 5.0], (len(gs.t), 3))
    b = s.baro
    p = tmp_path / ("walk.bag" if version == 1 else "walk")
    write_bag(p, version, EPOCH, imu=(s.imu.t, s.imu.gyro, s.imu.accel),
              fix=(gs.t_valid, gs.lat, gs.lon, gs.h, sig), twist=(gs.t_valid, gs.v_n),
              pressure=(b.t, pressure_of_altitude(b.h)))
    log = io.read(p)
    assert log.streams() == ["imu", "gnss", "baro"]
    np.testing.assert_allclose(log.imu.gyr, s.imu.gyro, atol=1e-15)        # FLU -> FRD exactly
    np.testing.assert_allclose(log.gnss.vel_n, gs.v_n, atol=1e-12)         # Twist: ENU -> NED
    np.testing.assert_allclose(log.gnss.sigma, sig, atol=1e-12)
    np.testing.assert_allclose(log.baro.altitude, b.h, atol=1e-6)          # FluidPressure -> altitude
    np.testing.assert_allclose(log.baro.t, EPOCH + b.t, atol=1e-6)
    g = log.gnss
    g.sigma_vel = np.full_like(g.vel_n, np.nan)   # the bag gives no velocity sigma: the configured one
    got = _cli_figures(d, tmp_path, ["--log", str(p)], f"bag{version}")
    _same(got, _api_figures(d, log.imu, g, log.baro))


# ----------------------------------------------------------------------------------------------
# ahrs run
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def rot():
    from quatnav.demo import rotation_scenario
    return rotation_scenario(n=800, rate=100.0, seed=5)


@pytest.mark.parametrize("version", [1])   # ROS 2 through ahrs run: test_io_rosbag.py
def test_bag_round_trip_ahrs_run(rot, tmp_path, version):
    pytest.importorskip("rosbags")
    s = rot
    p = tmp_path / ("r.bag" if version == 1 else "r")
    t0 = 1_700_000_000.0
    write_bag(p, version, t0, imu=(s.t, s.gyr, s.acc), mag=(s.t, s.mag * 1e-6), q_nb=s.q_nb)
    out, js = tmp_path / "a.csv", tmp_path / "c.json"
    assert cli.main(["ahrs", "run", "--log", str(p), "--out", str(out)]) == 0
    assert cli.main(["compare", str(out), str(p), "--json", str(js)]) == 0    # against the bag's orientation
    got = json.loads(js.read_text())
    log = io.read(p)
    r = quatnav.QuaternionEKF().run(log.imu.gyr, log.imu.acc, io.mag_on_imu_times(log), t=log.imu.t,
                                    on_invalid="skip")
    api = compare(io.Log(reference=io.Reference(t=r.t, quat=r.quat)), log)
    for k in ("attitude_heading_deg", "attitude_inclination_deg", "attitude_total_deg"):
        assert got[k]["rms"] == pytest.approx(api[k]["rms"], rel=1e-6, abs=1e-8), k
    assert got["attitude_inclination_deg"]["rms"] < 3.0


def test_ulog_integral_layout_round_trip(rot, tmp_path):
    pytest.importorskip("pyulog")
    s = rot
    p = tmp_path / "int.ulg"
    t, gyr, acc = ulog_integral(p, s.t, s.gyr, s.acc, mag_gauss=s.mag * 0.01, q_nb=s.q_nb)
    log = io.read(p)
    assert log.format == "ulog" and any("integral layout" in n for n in log.notes)
    np.testing.assert_allclose(log.imu.t, t, atol=1e-9)
    np.testing.assert_allclose(log.imu.gyr, gyr, rtol=1e-6)     # float32 integrals / integer microseconds
    np.testing.assert_allclose(log.imu.gyr, s.gyr, rtol=2e-6, atol=1e-7)
    np.testing.assert_allclose(log.imu.acc, s.acc, rtol=2e-6, atol=1e-6)
    assert log.mag.unit == "gauss"
    np.testing.assert_allclose(log.mag.values, s.mag * 0.01, rtol=1e-6)
    out, js = tmp_path / "a.csv", tmp_path / "c.json"
    assert cli.main(["ahrs", "run", "--log", str(p), "--out", str(out)]) == 0
    assert cli.main(["compare", str(out), str(p), "--json", str(js)]) == 0    # against vehicle_attitude
    got = json.loads(js.read_text())
    r = quatnav.QuaternionEKF().run(log.imu.gyr, log.imu.acc, io.mag_on_imu_times(log), t=log.imu.t,
                                    on_invalid="skip")
    api = compare(io.Log(reference=io.Reference(t=r.t, quat=r.quat)), log)
    for k in ("attitude_heading_deg", "attitude_inclination_deg"):
        assert got[k]["rms"] == pytest.approx(api[k]["rms"], rel=1e-6, abs=1e-8), k


def test_ulog_gps_heading_is_a_true_compass(tmp_path):
    pytest.importorskip("pyulog")
    ts = 1_000_000 + np.arange(10) * 200_000
    hd = np.radians(np.r_[10.0, 20.0, np.nan, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0]).astype(np.float32)
    gps = [("uint64_t", "timestamp"), ("int32_t", "lat"), ("int32_t", "lon"), ("int32_t", "alt_ellipsoid"),
           ("float", "eph"), ("float", "epv"), ("float", "heading"), ("uint8_t", "fix_type")]
    rows = [(ts[k], 473977000 + k, 85456000, 488000, 1.0, 2.0, hd[k], 3) for k in range(10)]
    write_ulog(tmp_path / "g.ulg", {"vehicle_gps_position": (gps, rows)})
    log = io.read(tmp_path / "g.ulg")
    assert len(log.gnss.t) == 10 and log.compass.north == "true"
    np.testing.assert_allclose(log.compass.heading, np.delete(hd, 2), rtol=1e-6)
    np.testing.assert_allclose(log.compass.t, np.delete(ts, 2) * 1e-6)
    np.testing.assert_allclose(np.degrees(log.gnss.lat[1]), 47.3977001, atol=1e-9)


# ----------------------------------------------------------------------------------------------
# malformed files: one line on stderr, exit status 2
# ----------------------------------------------------------------------------------------------
def _one_line_error(args, expect):
    p = subprocess.run([sys.executable, "-m", "quatnav", *args], capture_output=True, text=True,
                       env={"PYTHONPATH": PACKAGE_DIR, "PATH": "/usr/bin:/bin"}, timeout=300)
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in p.stderr, p.stderr
    assert expect in lines[0], lines[0]


def test_malformed_files_one_line(walk, rot, tmp_path):
    s, d = walk
    gs = s.gps
    pos = tmp_path / "cut.pos"
    write_pos(pos, gs.t_valid[:20], gs.lat, gs.lon, gs.h, [2.5, 2.5, 5.0], vel=gs.v_n)
    text = pos.read_text().splitlines()
    pos.write_text("\n".join(text[:-1] + [text[-1][:45]]) + "\n")
    base = ["ins", "run", "--imu", str(d / "imu.csv"), "--out", str(tmp_path / "o.csv")]
    _one_line_error(base + ["--gnss", str(pos)], "truncated file?")
    nm = tmp_path / "nofix.nmea"
    nm.write_text("$GNGGA,120000.00,,,,,0,00,99.9,,M,,M,,*5B\n$GNGSA,A,1,,,,,,,,,,,,,99.9,99.9,99.9*2E\n")
    _one_line_error(base + ["--gnss", str(nm)], "no GGA sentence with a fix")
    # a bag without NavSatFix: no GNSS for ins run; a wrong topic for ahrs run
    pytest.importorskip("rosbags")
    bag = tmp_path / "imu_only"
    write_bag(bag, 2, 1_700_000_000.0, imu=(rot.t, rot.gyr, rot.acc))
    _one_line_error(["ins", "run", "--log", str(bag), "--out", str(tmp_path / "o.csv")], "no GNSS data")
    _one_line_error(["ahrs", "run", "--log", str(bag), "--topic", "imu=/wrong", "--out", str(tmp_path / "o.csv")],
                    "no topic '/wrong'")
    _one_line_error(["ahrs", "run", "--log", str(bag), "--topic", "gnss", "--out", str(tmp_path / "o.csv")],
                    "--topic gnss: expected KIND=TOPIC")
    pytest.importorskip("pyulog")
    ul = tmp_path / "cut.ulg"
    ulog_integral(ul, rot.t, rot.gyr, rot.acc)
    ul.write_bytes(ul.read_bytes()[:120])   # cut inside the format definitions: no data left
    _one_line_error(["ahrs", "run", "--log", str(ul), "--out", str(tmp_path / "o.csv")], "cut.ulg")
