"""What ``quatnav ins run`` and ``ahrs run`` write besides the table: GPX times in UTC (the GNSS's
UTC times, leap seconds included, not the log's GPS clock), KML and GPX at the GNSS's rate, the
smoother's restarts in the summary; a result's repr with readable times; the magnetometer as
the filter used it."""
import calendar
import datetime
import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import quatnav
from quatnav import cli
from quatnav.sim.scenarios import make_scenario

pytest.importorskip("pandas")
#: 2026-01-01 00:00:00 UTC, and the same instant in GPS time counted from 1970 (18 leap seconds)
UTC0 = calendar.timegm((2026, 1, 1, 0, 0, 0, 0, 0, 0))
GPS0 = UTC0 + 18
GPX = "{http://www.topografix.com/GPX/1/1}"


def _write(path, header, cols, fmt="%.17g"):
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(header), comments="", fmt=fmt)
    return str(path)


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """The simulated walk on a GPS clock counted from 1970 (as the real walk's files are), its
    fixes with their UTC times; and a GNSS file whose fixes jump 40 m north after 60 s."""
    s = make_scenario("paper004_walk", seed=0)
    d = tmp_path_factory.mktemp("outs")
    g = s.gps
    imu = _write(d / "imu.csv", ["time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"],
                 [GPS0 + s.imu.t, *s.imu.gyro.T, *s.imu.accel.T])
    cols = [GPS0 + g.t_valid, np.degrees(g.lat), np.degrees(g.lon), g.h, *g.v_n.T]
    head = ["time", "lat", "lon", "h", "v_n", "v_e", "v_d"]
    gnss = _write(d / "gnss.csv", head + ["utc"], cols + [UTC0 + g.t_valid])
    jump = np.array(cols)
    jump[1, g.t_valid > 60.0] += np.degrees(40.0 / 6.37e6)
    gnss_jump = _write(d / "gnss_jump.csv", head, list(jump))
    return dict(dir=d, imu=imu, gnss=gnss, gnss_jump=gnss_jump, s=s)


def _times(gpx):
    pts = ET.parse(gpx).getroot().findall(f".//{GPX}trkpt")
    return pts, [p.find(f"{GPX}time") for p in pts]


def test_gpx_times_are_utc_and_tracks_at_the_gnss_rate(walk, tmp_path, capsys):
    out, kml, gpx = tmp_path / "o.csv", tmp_path / "t.kml", tmp_path / "t.gpx"
    assert cli.main(["ins", "run", "--imu", walk["imu"], "--gnss", walk["gnss"], "--out", str(out), "--kml", str(kml),
                     "--gpx", str(gpx)]) == 0
    text = capsys.readouterr().out
    t = np.loadtxt(out, delimiter=",", skiprows=1, usecols=0)
    pts, times = _times(gpx)
    # UTC: 18 s behind the GPS clock of the log, to the millisecond
    first = datetime.datetime.fromisoformat(times[0].text.replace("Z", "+00:00")).timestamp()
    assert first == pytest.approx(t[0] - 18.0, abs=1e-3), (times[0].text, t[0])
    assert times[0].text.endswith("Z") and "times in UTC: the IMU's clock -18.000 s" in text
    # the GNSS's 5 Hz, not the IMU's 50: one point per 0.2 s and the last row
    span = t[-1] - t[0]
    assert abs(len(pts) - (span * 5 + 2)) <= 2 and f"{len(pts)} points (5 Hz)" in text
    coords = ET.parse(kml).getroot().find(".//{http://www.opengis.net/kml/2.2}coordinates").text.split()
    assert len(coords) == len(pts)
    assert cli.main(["ins", "run", "--imu", walk["imu"], "--gnss", walk["gnss"], "--out", str(out), "--gpx",
                     str(gpx), "--track-rate", "1"]) == 0
    capsys.readouterr()
    assert abs(len(_times(gpx)[0]) - (span + 2)) <= 2


def test_gpx_without_utc_says_what_the_times_are(walk, tmp_path, capsys):
    """A GNSS file without UTC times: the clock is taken for Unix time (> 1e8 s), and the command
    says so, naming the utc column."""
    import pandas as pd
    g = pd.read_csv(walk["gnss"]).drop(columns=["utc"])
    f = tmp_path / "g.csv"
    g.to_csv(f, index=False, float_format="%.17g")
    gpx = tmp_path / "t.gpx"
    assert cli.main(["ins", "run", "--imu", walk["imu"], "--gnss", str(f), "--out", str(tmp_path / "o.csv"), "--gpx",
                     str(gpx)]) == 0
    assert "taking the IMU's clock for Unix time" in capsys.readouterr().out


def test_smoother_restarts_in_the_summary(walk, tmp_path, capsys):
    """Fixes that jump 40 m: the filter inflates its covariance at the first one it keeps
    failing; the smoother does not cross it, and the summary says where and how far it jumps."""
    js = tmp_path / "s.json"
    assert cli.main(["ins", "run", "--imu", walk["imu"], "--gnss", walk["gnss_jump"], "--smooth", "--out",
                     str(tmp_path / "o.csv"), "--json", str(js)]) == 0
    text = capsys.readouterr().out
    got = json.loads(js.read_text())
    r = got["smoother_restarts"]
    assert len(r) == 1 and r[0]["aid"] == "gps_pos" and r[0]["decision"] == "inflated"
    assert 60.0 < r[0]["t"] - GPS0 < 61.0 and 20.0 < r[0]["position_m"] < 45.0
    assert "restarted at 1 covariance inflation or reset (gps_pos inflated at t = " in text
    assert "the smoothed solution may jump there" in text
    # without smoothing: no restarts to report
    assert cli.main(["ins", "run", "--imu", walk["imu"], "--gnss", walk["gnss_jump"], "--out",
                     str(tmp_path / "o.csv"), "--json", str(js)]) == 0
    assert "smoother_restarts" not in json.loads(js.read_text())


def test_repr_shows_absolute_times_to_the_millisecond(walk):
    s = walk["s"]
    r = quatnav.QuaternionEKF().run(s.imu.gyro[:500], s.imu.accel[:500], t=GPS0 + s.imu.t[:500])
    text = repr(r)
    assert f"t {GPS0 + s.imu.t[0]:.3f}..{GPS0 + s.imu.t[499]:.3f} s ({s.imu.t[499] - s.imu.t[0]:.6g} s)" in text, text
    assert "e+09" not in text
    assert "t 0..9.98 s" in repr(quatnav.QuaternionEKF().run(s.imu.gyro[:500], s.imu.accel[:500], t=s.imu.t[:500]))


def test_ahrs_json_says_how_much_of_the_magnetometer_was_used(tmp_path, capsys):
    """A magnetometer on every tenth row: 'magnetometer' true, and its rows and use counted (the
    other rows carry no sample; the old summary said only 'true')."""
    s = make_scenario("handheld_marg", seed=0)
    from quatnav.core import quaternion as Q
    k = s.imu.index
    m = np.array([Q.rotate_inv(q, [20.0, 0.0, 40.0]) for q in s.truth.q_nb[k]])
    m[np.arange(len(m)) % 10 != 0] = np.nan
    import pandas as pd
    f = tmp_path / "imu.csv"
    hdr = "time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,mag_x,mag_y,mag_z".split(",")
    pd.DataFrame(np.column_stack([s.imu.t, s.imu.gyro, s.imu.accel, m]), columns=hdr).to_csv(
        f, index=False, na_rep="", float_format="%.9g")  # an empty cell: no magnetometer sample
    js = tmp_path / "s.json"
    assert cli.main(["ahrs", "run", "--imu", str(f), "--out", str(tmp_path / "o.csv"), "--json", str(js)]) == 0
    text = capsys.readouterr().out
    got = json.loads(js.read_text())
    rows = got["magnetometer_rows"]
    assert rows["rows"] == int(np.isfinite(m).all(axis=1).sum())
    assert got["magnetometer"] is True and 0 < rows["used"] <= rows["rows"]
    assert rows["used"] + rows["rejected"] + rows["skipped"] == rows["rows"]
    assert f"magnetometer: {rows['used']} of {rows['rows']} rows with a sample used" in text


def test_leap_seconds():
    from quatnav.core.timescales import gps_minus_utc, gps_to_utc, utc_to_gps
    at = lambda *d: calendar.timegm((*d, 0, 0, 0))  # noqa: E731
    assert gps_minus_utc(at(1980, 1, 6, 0, 0, 0)) == 0 and gps_minus_utc(at(1999, 6, 1, 0, 0, 0)) == 13
    assert gps_minus_utc(at(2016, 12, 31, 23, 59, 59)) == 17 and gps_minus_utc(at(2017, 1, 1, 0, 0, 0)) == 18
    u = np.array([at(2012, 6, 30, 23, 59, 59), at(2012, 7, 1, 0, 0, 1), at(2025, 8, 28, 17, 30, 0)], float)
    np.testing.assert_array_equal(utc_to_gps(u) - u, [15, 16, 18])
    np.testing.assert_array_equal(gps_to_utc(utc_to_gps(u)), u)
