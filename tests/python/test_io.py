"""quatnav.io: the readers (RTKLIB .pos, NMEA, CSV, PX4 ULog), format detection, the errors of
malformed files, and the Log helpers."""
from __future__ import annotations

import calendar
import math
import time as time_mod
from functools import reduce
from pathlib import Path

import numpy as np
import pytest

from quatnav import io
from quatnav.io.nmea import checksum_ok

from conftest import DATA

WALK_POS = DATA / "gnss_imu_walk" / "gnss_1730_sf.pos"
PX4 = DATA / "px4"

LAT0, LON0, H0 = math.radians(40.0966916), math.radians(-105.1471665), 1601.435


def _track(n=20):
    t = calendar.timegm((2025, 8, 28, 17, 30, 0, 0, 0, 0)) + 0.25 * np.arange(n)
    lat = LAT0 + 1e-7 * np.arange(n)
    lon = LON0 - 2e-7 * np.arange(n)
    h = H0 + 0.01 * np.arange(n)
    return t, lat, lon, h


def write_pos(path, mode="deg", time="date", vel=True, n=20, q=None):
    """A small RTKLIB .pos writer in the layout rtkpost writes."""
    t, lat, lon, h = _track(n)
    q = np.ones(n, int) if q is None else q
    pos_lab = {"deg": "latitude(deg) longitude(deg)  height(m)", "dms": "latitude(d'\") longitude(d'\")  height(m)",
               "ecef": "x-ecef(m)      y-ecef(m)      z-ecef(m)"}[mode]
    sd_lab = "sdx(m) sdy(m) sdz(m) sdxy(m) sdyz(m) sdzx(m)" if mode == "ecef" else "sdn(m) sde(m) sdu(m) sdne(m) sdeu(m) sdun(m)"
    lines = ["% program   : RTKPOST ver.2.4.3", f"%  GPST {pos_lab} Q  ns {sd_lab} age(s) ratio"
             + (" vn(m/s) ve(m/s) vu(m/s) sdvn sdve sdvu sdvne sdveu sdvun" if vel else "")]
    from quatnav.core import earth as E
    for k in range(n):
        if time == "date":
            ts = time_mod.gmtime(int(t[k]))
            tt = f"{ts.tm_year:04d}/{ts.tm_mon:02d}/{ts.tm_mday:02d} {ts.tm_hour:02d}:{ts.tm_min:02d}:{ts.tm_sec + t[k] % 1:06.3f}"
        else:
            g = t[k] - calendar.timegm((1980, 1, 6, 0, 0, 0, 0, 0, 0))
            tt = f"{int(g // 604800)} {g % 604800:.3f}"
        if mode == "deg":
            p = f"{math.degrees(lat[k]):.9f} {math.degrees(lon[k]):.9f} {h[k]:.4f}"
        elif mode == "dms":
            def dms(x):
                a = abs(math.degrees(x)); d = int(a); m = int((a - d) * 60); s = (a - d - m / 60) * 3600
                return f"{'-' if x < 0 else ''}{d} {m:02d} {s:.7f}"
            p = f"{dms(lat[k])} {dms(lon[k])} {h[k]:.4f}"
        else:
            xyz = E.geodetic_to_ecef(lat[k], lon[k], h[k])
            p = " ".join(f"{v:.4f}" for v in np.ravel(xyz))
        row = f"{tt} {p} {q[k]} 20 0.0100 0.0120 0.0300 0 0 0 0.0 999.9"
        if vel:
            row += " 1.0000 -0.5000 0.1000 0.05 0.05 0.05 0 0 0"
        lines.append(row)
    Path(path).write_text("\n".join(lines) + "\n")
    return t, lat, lon, h


@pytest.mark.parametrize("mode,time", [("deg", "date"), ("dms", "date"), ("ecef", "week"), ("deg", "week")])
def test_pos_layouts(tmp_path, mode, time):
    p = tmp_path / "sol.pos"
    t, lat, lon, h = write_pos(p, mode, time)
    log = io.read(p)
    g = log.gnss
    assert log.format == "rtklib-pos" and log.imu is None
    np.testing.assert_allclose(g.t, t, atol=1e-3)
    tol = 1e-4 / 6.4e6  # 0.1 mm
    np.testing.assert_allclose(g.lat, lat, atol=tol if mode != "dms" else 5e-6 / 3600 * math.pi / 180 * 1e2)
    np.testing.assert_allclose(g.lon, lon, atol=tol if mode != "dms" else 5e-6 / 3600 * math.pi / 180 * 1e2)
    np.testing.assert_allclose(g.h, h, atol=1e-3)
    np.testing.assert_allclose(g.vel_n[0], [1.0, -0.5, -0.1])
    if mode != "ecef":
        np.testing.assert_allclose(g.sigma[0], [0.01, 0.012, 0.03])
    assert (g.quality == 1).all() and (g.weight == 1).all()
    np.testing.assert_allclose(g.utc, g.t - 18.0)  # GPST less the leap seconds: the date of the recording


def test_pos_quality_without_sigma_columns(tmp_path):
    p = tmp_path / "sol.pos"
    q = np.array([1, 2, 5, 4] * 5)
    write_pos(p, q=q, vel=False)
    txt = p.read_text().replace("0.0100 0.0120 0.0300", "0.0000 0.0000 0.0000")
    p.write_text(txt)
    g = io.read(p).gnss
    assert g.vel_n is None
    assert g.sigma[0, 0] < g.sigma[1, 0] < g.sigma[3, 0] < g.sigma[2, 0]  # fix < float < dgps < single
    assert list(g.weight[:3]) == [1.0, 0.5, 0.1]


def test_pos_truncated_and_not_pos(tmp_path):
    p = tmp_path / "sol.pos"
    write_pos(p, n=5)
    lines = p.read_text().splitlines()
    p.write_text("\n".join(lines[:-1] + [lines[-1][:40]]) + "\n")
    with pytest.raises(ValueError, match=r"sol\.pos: solution row 5 .*truncated"):
        io.read(p)
    p.write_text("2025/08/28 17:30:39.749 40.0 -105.0 1600.0 1 25\n")
    with pytest.raises(ValueError, match="not an RTKLIB .pos"):
        io.read(p, format="rtklib")


def test_walk_pos_file():
    if not WALK_POS.exists():
        pytest.skip(f"{WALK_POS} absent")
    g = io.read(WALK_POS).gnss
    from quatnav.datasets.gnss_imu_walk import read_pos
    d = read_pos(WALK_POS)
    np.testing.assert_array_equal(g.t, d["t"])
    np.testing.assert_array_equal(g.lat, d["lat"])
    np.testing.assert_allclose(g.vel_n[:, 2], -d["vel_neu"][:, 2])
    assert set(np.unique(g.quality)) <= {1, 2}


def _nmea(body):
    return f"${body}*{reduce(lambda a, c: a ^ ord(c), body, 0):02X}"


def test_nmea(tmp_path):
    lines = []
    for k in range(5):
        s = 3600 * 23 + 59 * 60 + 58 + k  # crosses midnight
        hh, mm, ss = (s // 3600) % 24, (s // 60) % 60, s % 60
        tt = f"{hh:02d}{mm:02d}{ss:05.2f}"
        lines.append(_nmea(f"GNGGA,{tt},4005.80150,N,10508.82999,W,4,12,0.8,1580.0,M,-21.0,M,1.0,0000"))
        lines.append(_nmea(f"GNRMC,{tt},A,4005.80150,N,10508.82999,W,2.0,90.0,280825,,,R"))
    lines.insert(3, "$GNGGA,000000.00,4005.8,N,10508.8,W,1,5,1.0,1.0,M,0,M,,*00")  # bad checksum
    lines.insert(4, "garbage")
    p = tmp_path / "rx.nmea"
    p.write_text("\n".join(lines) + "\n")
    log = io.read(p)
    g = log.gnss
    assert log.format == "nmea" and log.bad_lines == 2 and "2 bad NMEA lines" in log.notes[0]
    assert len(g.t) == 5
    np.testing.assert_allclose(np.diff(g.t), 1.0)
    assert g.t[0] == calendar.timegm((2025, 8, 28, 23, 59, 58, 0, 0, 0))
    np.testing.assert_allclose(np.degrees(g.lat[0]), 40 + 5.8015 / 60)
    np.testing.assert_allclose(np.degrees(g.lon[0]), -(105 + 8.82999 / 60))
    np.testing.assert_allclose(g.h[0], 1559.0)
    np.testing.assert_allclose(g.vel_n[0, :2], [0.0, 2.0 * 1852 / 3600], atol=1e-12)
    assert (g.quality == 4).all() and g.sigma[0, 0] == pytest.approx(0.8 * 0.02)
    assert checksum_ok(lines[0]) and not checksum_ok(lines[0][:-1] + "0")
    np.testing.assert_array_equal(g.utc, g.t)  # UTC, dated by RMC
    p.write_text("\n".join(x for x in lines if "RMC" not in x) + "\n")
    assert io.read(p).gnss.utc is None  # times of day only: no date


def test_csv_streams(tmp_path):
    p = tmp_path / "imu.csv"
    p.write_text("time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,mag_x,mag_y,mag_z\n"
                 "0,0,0,0,0,0,-9.8,20,0,40\n0.01,0.1,0,0,0,0,-9.8,,,\n")
    log = io.read(p)
    assert log.streams() == ["imu", "mag"] and len(log.mag.t) == 1
    np.testing.assert_array_equal(io.mag_on_imu_times(log)[1], [np.nan] * 3)
    g = tmp_path / "gnss.csv"
    g.write_text("time,lat,lon,h\n0,40,-105,1600\n")
    assert io.read(g).streams() == ["gnss"] and io.read(g).gnss.utc is None
    g.write_text("time,lat,lon,h,utc\n0,40,-105,1600,\n1,40,-105,1600,1756402201.5\n")
    np.testing.assert_array_equal(io.read(g).gnss.utc, [np.nan, 1756402201.5])  # Unix time, empty: none
    g.write_text("time,lat,lon,h,utc\n0,40,-105,1600,2025-08-28T17:30:01Z\n")  # text: noted, not used
    log = io.read(g)
    assert log.gnss.utc is None and "utc column ignored" in log.notes[-1]
    bad = tmp_path / "x.csv"
    bad.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match=r"x\.csv: CSV columns .* match no stream"):
        io.read(bad)
    # no header row (as the walk's IMU file): said so, not "columns ['-0.0028', ...] match no stream"
    # nor "column '0.0' appears twice in the header"
    bare = tmp_path / "bare.csv"
    bare.write_text("1756402240.961,0.0006,0.0028,1.0110,-0.0028,-0.0070,-0.0170,0.0,0.0,0.0,0.0\n"
                    "1756402240.967,0.0006,0.0028,1.0110,-0.0028,-0.0070,-0.0170,0.0,0.0,0.0,0.0\n")
    for kw in ({}, {"kind": "imu"}):
        with pytest.raises(ValueError, match=r"bare\.csv(: line 1)?: no header row \(the first line holds numbers.*"
                                             r"\(time, gyro_x, gyro_y, gyro_z, accel_x"):
            io.read(bare, **kw)


def test_read_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        io.read(tmp_path / "none.pos")
    p = tmp_path / "gnss.csv"
    p.write_text("time,lat,lon,h\n0,40,-105,1600\n")
    with pytest.raises(ValueError, match=r"gnss\.csv: no IMU data in this csv \(it has: gnss\)"):
        io.read(p).require("imu")
    p = tmp_path / "bin.dat"
    p.write_bytes(b"\x00\x01\x02")
    with pytest.raises(ValueError, match="cannot tell the format"):
        io.read(p)
    # a MATLAB file (the BROAD trials, NaveGo's run) is named as such, not parsed as CSV (its header
    # has commas) into a message of binary garbage; so is other binary content with commas
    mat = tmp_path / "trial.mat"
    mat.write_bytes(b"MATLAB 5.0 MAT-file, Platform: posix, Created on: Fri May  7 12:45:59 2021"
                    + b" " * 41 + b"\x00" * 8 + b"\x00\x01IM\x0f\x00\x00\x00\xb5\xbd,\x00x\x9c")
    with pytest.raises(ValueError, match=r"trial\.mat: a MATLAB MAT-file, not a format read here .*scipy\.io\.loadmat") as e:
        io.read(mat)
    assert "\x00" not in str(e.value)
    p = tmp_path / "blob.csv"
    p.write_bytes(b"time,gyro_x\x00\x00\x9c,\x01\n")
    with pytest.raises(ValueError, match=r"blob\.csv: cannot tell the format: binary content") as e:
        io.read(p)
    assert "\x00" not in str(e.value)


def test_ulog():
    pytest.importorskip("pyulog")
    real = PX4 / "sample_appended_multiple.ulg"
    sitl = PX4 / "sample_logging_tagged_and_default_params.ulg"
    if not real.exists():
        pytest.skip(f"{PX4} absent")
    log = io.read(real)
    assert log.format == "ulog" and log.gnss is None and log.imu is not None
    with pytest.raises(ValueError, match=r"sample_appended_multiple\.ulg: no GNSS data in this ulog"):
        log.require("gnss")
    acc = log.imu.acc[:50].mean(0)
    assert acc[2] < -9 and abs(np.linalg.norm(acc) - 9.81) < 0.5  # FRD at rest: gravity on -z
    np.testing.assert_allclose(np.linalg.norm(log.reference.quat, axis=1), 1.0)
    log = io.read(sitl)
    g = log.gnss
    assert g is not None and (g.quality >= 3).all()
    assert -90 < np.degrees(g.lat).min() and np.all(np.abs(np.degrees(g.lat)) > 1e-3)
    assert log.mag.unit == "gauss" and log.baro.altitude is not None
    # the recording date: time_utc_usec of vehicle_gps_position (the SITL run of 2022-04-29) and of
    # sensor_gps alike, one UTC time per fix, on the fixes' clock
    for glog in (log, io.read(sitl, gnss_topic="sensor_gps")):
        u = glog.gnss.utc
        assert u is not None and u.shape == glog.gnss.t.shape and np.isfinite(u).all()
        assert time_mod.gmtime(u[0])[:3] == (2022, 4, 29)
        np.testing.assert_allclose(np.diff(u), np.diff(glog.gnss.t), atol=0.06)
    # a topic asked for by name: read, or a clear error (not a silently missing stream)
    assert io.read(sitl, mag_topic="sensor_mag").mag is not None
    with pytest.raises(ValueError, match=r"no topic 'nosuch' \(topics: .*sensor_combined"):
        io.read(sitl, mag_topic="nosuch")
    with pytest.raises(ValueError, match="topic 'vehicle_attitude' has no magnetometer fields"):
        io.read(sitl, mag_topic="vehicle_attitude")
    with pytest.raises(ValueError, match="no topic 'gps'"):
        io.read(sitl, gnss_topic="gps")


def test_ulog_damaged(tmp_path):
    pytest.importorskip("pyulog")
    real = PX4 / "sample_appended_multiple.ulg"
    if not real.exists():
        pytest.skip(f"{PX4} absent")
    p = tmp_path / "cut.ulg"
    p.write_bytes(real.read_bytes()[:3000])
    with pytest.raises(ValueError, match=r"cut\.ulg"):
        io.read(p).require("imu")
