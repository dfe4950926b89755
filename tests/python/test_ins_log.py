"""``quatnav ins run`` with other inputs than CSV: a simulated walk's GNSS written as an RTKLIB
.pos file gives the run of the CSV form; ``--log`` with a CSV log; KML, GPX and the plot; and
``compare`` against the truth equals the metric of the Python API on the same arrays."""
from __future__ import annotations

import calendar
import json
import xml.etree.ElementTree as ET

import numpy as np
import pandas as pd
import pytest

from quatnav import cli

from conftest import DATA

# RTKLIB times are calendar dates: the simulated clock (0 s ...) as seconds from a date
EPOCH = calendar.timegm((2026, 1, 1, 0, 0, 0, 0, 0, 0))


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    d = tmp_path_factory.mktemp("walk")
    assert cli.main(["simulate", "paper004_walk", "--seed", "3", "--csv", str(d)]) == 0
    g = pd.read_csv(d / "gnss.csv")
    lines = ["%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)"
             "  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio  vn(m/s)  ve(m/s)  vu(m/s)  sdvn  sdve  sdvu  sdvne  sdveu  sdvun"]
    for r in g.itertuples():
        import time
        ts = time.gmtime(EPOCH + int(r.time))
        frac = r.time - int(r.time)
        lines.append(f"{ts.tm_year}/{ts.tm_mon:02d}/{ts.tm_mday:02d} {ts.tm_hour:02d}:{ts.tm_min:02d}:"
                     f"{ts.tm_sec + frac:06.3f} {r.lat:.12f} {r.lon:.12f} {r.h:.6f} 5 9 {r.sigma_n} {r.sigma_e} "
                     f"{r.sigma_d} 0 0 0 0 0 {r.v_n:.6f} {r.v_e:.6f} {-r.v_d:.6f} {r.sigma_vn} {r.sigma_ve} "
                     f"{r.sigma_vd} 0 0 0")
    (d / "gnss.pos").write_text("\n".join(lines) + "\n")
    imu = pd.read_csv(d / "imu.csv")
    imu["time"] += EPOCH
    imu.to_csv(d / "imu_abs.csv", index=False, float_format="%.17g")
    for f in ("baro", "truth", "gnss"):
        x = pd.read_csv(d / f"{f}.csv")
        x["time"] += EPOCH
        x.to_csv(d / f"{f}_abs.csv", index=False, float_format="%.17g")
    return d


def test_gnss_from_pos_equals_csv(walk, tmp_path):
    d = walk
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    # The .pos file gives each fix's solution kind, the CSV none: the filter told that the
    # simulated fixes' errors are white (gps_error_tau = 0), as it takes fixes of no kind.
    cfg = tmp_path / "config.toml"
    cfg.write_text((d / "config.toml").read_text().replace("[filter]\n", "[filter]\ngps_error_tau = 0.0\n"))
    assert "gps_error_tau" in cfg.read_text()
    # the same absolute times in both runs (times near 1.8e9 s round differently from 0 s ones)
    assert cli.main(["ins", "run", "--imu", str(d / "imu_abs.csv"), "--gnss", str(d / "gnss_abs.csv"), "--baro",
                     str(d / "baro_abs.csv"), "--config", str(cfg), "--out", str(a)]) == 0
    kml, gpx, png = tmp_path / "t.kml", tmp_path / "t.gpx", tmp_path / "t.png"
    assert cli.main(["ins", "run", "--imu", str(d / "imu_abs.csv"), "--gnss", str(d / "gnss.pos"), "--baro",
                     str(d / "baro_abs.csv"), "--config", str(cfg), "--out", str(b),
                     "--kml", str(kml), "--gpx", str(gpx), "--plot", str(png)]) == 0
    x, y = pd.read_csv(a), pd.read_csv(b)
    assert len(x) == len(y)
    np.testing.assert_array_equal(y["time"], x["time"])
    np.testing.assert_allclose(y["lat"], x["lat"], atol=1e-8)  # ~1 mm: the .pos file's 1e-12 deg and 1e-6 m
    np.testing.assert_allclose(y["h"], x["h"], atol=2e-3)
    np.testing.assert_allclose(y["yaw"], x["yaw"], atol=1e-3)
    k = ET.parse(kml).getroot()
    coords = k.find(".//{http://www.opengis.net/kml/2.2}coordinates").text.split()
    lon, lat, _ = (float(v) for v in coords[0].split(","))
    assert lat == pytest.approx(y["lat"][0], abs=1e-8) and lon == pytest.approx(y["lon"][0], abs=1e-8)
    pts = ET.parse(gpx).getroot().findall(".//{http://www.topografix.com/GPX/1/1}trkpt")
    # at the GNSS's rate (5 Hz, the IMU's 50 Hz); in UTC: the .pos file's GPST less 18 leap seconds
    assert abs(len(pts) - (5 * (y["time"].iloc[-1] - y["time"].iloc[0]) + 2)) <= 2
    import datetime
    first = pts[0].find("{http://www.topografix.com/GPX/1/1}time").text
    assert datetime.datetime.fromisoformat(first.replace("Z", "+00:00")).timestamp() == pytest.approx(
        y["time"].iloc[0] - 18.0, abs=1e-3), first
    _figure_ok(png, 1000, 800)  # the six panels of plot_nav at 12 x 10 in


def test_log_and_compare_equal_api(walk, tmp_path):
    d = walk
    log = tmp_path / "log.csv"
    imu, g = pd.read_csv(d / "imu.csv"), pd.read_csv(d / "gnss.csv")
    # one CSV log cannot hold both streams on different rows; --log gives the IMU, --gnss the fixes
    imu.to_csv(log, index=False, float_format="%.17g")
    out, js = tmp_path / "o.csv", tmp_path / "c.json"
    assert cli.main(["ins", "run", "--log", str(log), "--gnss", str(d / "gnss.csv"), "--config",
                     str(d / "config.toml"), "--out", str(out)]) == 0
    assert cli.main(["compare", str(out), str(d / "truth.csv"), "--json", str(js)]) == 0
    got = json.loads(js.read_text())
    from quatnav.evaluation.track_difference import compare_tracks as compare
    from quatnav import io
    ref = compare(io.read(out, kind="reference"), io.read(d / "truth.csv", kind="reference"))
    for k in ("attitude_heading_deg", "attitude_inclination_deg", "position_horizontal_m", "velocity_horizontal_m_s"):
        assert got[k]["rms"] == pytest.approx(ref[k]["rms"], rel=1e-9)
    assert got["position_horizontal_m"]["rms"] < 5.0


def test_ins_needs_gnss(tmp_path, walk):
    pytest.importorskip("pyulog")
    f = DATA / "px4" / "sample_appended_multiple.ulg"
    if not f.exists():
        pytest.skip("px4 data absent")
    assert cli.main(["ins", "run", "--log", str(f), "--out", str(tmp_path / "o.csv")]) == 2


def test_ulog_magnetometer_gives_the_heading(tmp_path, data_dir):
    """A PX4 log at rest (SITL, GNSS from 9.5 s): `--log` uses the log's magnetometer for the
    heading, so navigation starts at the first fix; the attitude agrees with PX4's own estimate
    within the magnetic declination (no declination is given here) and `--no-mag` drops it."""
    pytest.importorskip("pyulog")
    f = data_dir / "px4" / "sample_logging_tagged_and_default_params.ulg"
    if not f.exists():
        pytest.skip("px4 data absent")
    out, js, cj = tmp_path / "o.csv", tmp_path / "s.json", tmp_path / "c.json"
    assert cli.main(["ins", "run", "--log", str(f), "--out", str(out), "--json", str(js)]) == 0
    s = json.loads(js.read_text())
    assert s["alignment"]["heading"] == "magnetometer" and s["rows"] > 200
    assert s["decisions"]["mag"].get("accepted", 0) > 10
    assert cli.main(["compare", str(out), str(f), "--json", str(cj)]) == 0
    c = json.loads(cj.read_text())
    assert c["attitude_inclination_deg"]["rms"] < 0.5
    assert c["attitude_heading_deg"]["rms"] < 6.0  # the declination: PX4 gives true north
    assert cli.main(["ins", "run", "--log", str(f), "--out", str(tmp_path / "n.csv"), "--json", str(js),
                     "--no-mag"]) == 1
    assert json.loads(js.read_text())["alignment"]["heading"] == "none"


def test_declination_auto_turns_the_heading_to_true_north(tmp_path, data_dir):
    """`--declination auto` takes the World Magnetic Model's declination at the first fix: on the
    SITL log (Zurich, about +3.7 deg) the heading of `ins run` and `ahrs run` comes within a
    degree of PX4's own (true-north) estimate, from 3 deg without it; a log without GNSS is a
    user's mistake (exit 2), as is a declination that is neither degrees nor auto."""
    pytest.importorskip("pyulog")
    pytest.importorskip("ahrs")
    f = data_dir / "px4" / "sample_logging_tagged_and_default_params.ulg"
    real = data_dir / "px4" / "sample_appended_multiple.ulg"
    if not f.exists():
        pytest.skip("px4 data absent")
    out, js, cj = tmp_path / "o.csv", tmp_path / "s.json", tmp_path / "c.json"
    assert cli.main(["ins", "run", "--log", str(f), "--out", str(out), "--json", str(js), "--declination", "auto"]) == 0
    s = json.loads(js.read_text())
    assert 2.0 < np.degrees(s["declination_rad"]) < 5.5 and "World Magnetic Model" in s["declination_note"]
    assert cli.main(["compare", str(out), str(f), "--json", str(cj)]) == 0
    assert json.loads(cj.read_text())["attitude_heading_deg"]["rms"] < 1.0
    a = tmp_path / "a.csv"
    assert cli.main(["ahrs", "run", "--log", str(f), "--out", str(a), "--declination", "auto"]) == 0
    assert cli.main(["compare", str(a), str(f), "--json", str(cj)]) == 0
    assert json.loads(cj.read_text())["attitude_heading_deg"]["rms"] < 1.0
    assert cli.main(["ahrs", "run", "--log", str(real), "--out", str(a), "--declination", "auto"]) == 2
    with pytest.raises(SystemExit) as e:  # argparse's one line, exit status 2
        cli.main(["ins", "run", "--log", str(f), "--out", str(out), "--declination", "east"])
    assert e.value.code == 2


def _wmm_deg(lat_deg, lon_deg, h_m, year):
    """The declination of ahrs.utils.WMM itself, deg."""
    from ahrs.utils import WMM
    return float(WMM(latitude=lat_deg, longitude=lon_deg, height=h_m / 1000.0, date=year).D)


def test_declination_auto_at_the_recording_date(tmp_path, data_dir, capsys):
    """`--declination auto` evaluates the World Magnetic Model on the day of the recording: the SITL
    log's GNSS UTC time (2022-04-29, WMM-2020) gives the model's declination at the first fix on
    that day, and PX4's own (true-north) heading within 0.3 deg; `--date` replaces the log's date
    and moves the declination by the model's secular change between the two dates, in `ins run`
    and `ahrs run` alike."""
    pytest.importorskip("pyulog")
    pytest.importorskip("ahrs")
    from quatnav import io
    from quatnav.cli.util import date_arg
    from quatnav.core.magnetic import decimal_year
    import datetime
    f = data_dir / "px4" / "sample_logging_tagged_and_default_params.ulg"
    if not f.exists():
        pytest.skip("px4 data absent")
    g = io.read(f).gnss
    lat, lon, h = np.degrees(g.lat[0]), np.degrees(g.lon[0]), g.h[0]
    day = datetime.datetime.fromtimestamp(g.utc[0], datetime.timezone.utc)
    assert (day.year, day.month, day.day) == (2022, 4, 29)
    out, js, cj = tmp_path / "o.csv", tmp_path / "s.json", tmp_path / "c.json"

    def ins(*extra):
        assert cli.main(["ins", "run", "--log", str(f), "--out", str(out), "--json", str(js), "--declination", "auto",
                         *extra]) == 0
        return json.loads(js.read_text())
    s = ins()
    assert np.degrees(s["declination_rad"]) == pytest.approx(_wmm_deg(lat, lon, h, decimal_year(day)), abs=1e-9)
    assert "on 2022-04-29" in s["declination_note"] and "WMM-2020" in s["declination_note"]
    assert "log's GNSS UTC time" in s["declination_note"]
    assert not any("no recording date" in n for n in s["notes"])
    assert cli.main(["compare", str(out), str(f), "--json", str(cj)]) == 0
    assert json.loads(cj.read_text())["attitude_heading_deg"]["rms"] < 0.3  # 0.6 with today's model
    # --date replaces the log's date: the difference is the model's own between the dates
    y0, y1 = date_arg("2025-06-01"), date_arg("2029.5")
    d0, d1 = (np.degrees(ins("--date", d)["declination_rad"]) for d in ("2025-06-01", "2029.5"))
    w0, w1 = _wmm_deg(lat, lon, h, y0), _wmm_deg(lat, lon, h, y1)
    assert d0 == pytest.approx(w0, abs=1e-9) and d1 == pytest.approx(w1, abs=1e-9)
    assert abs(w1 - w0) > 0.2  # Zurich: about +0.1 deg a year
    assert "from --date" in json.loads(js.read_text())["declination_note"]
    capsys.readouterr()
    a = tmp_path / "a.csv"
    assert cli.main(["ahrs", "run", "--log", str(f), "--out", str(a), "--declination", "auto", "--date",
                     "2025-06-01"]) == 0
    o = capsys.readouterr().out
    assert f"declination {w0:+.2f} deg" in o and "on 2025-06-01 (2025.41, from --date)" in o


@pytest.mark.parametrize("date,why", [("2022-13-01", "not a date"), ("june", "expected a date YYYY-MM-DD"),
                                      ("2012-06-01", "before 2015")])
def test_bad_date_is_one_line(tmp_path, data_dir, capsys, date, why):
    """A --date that is not a date, or one the model has no coefficients for (ahrs.utils.WMM: from
    2015), is one line on stderr and exit status 2; so is --date without --declination auto."""
    pytest.importorskip("pyulog")
    pytest.importorskip("ahrs")
    f = data_dir / "px4" / "sample_logging_tagged_and_default_params.ulg"
    if not f.exists():
        pytest.skip("px4 data absent")
    for cmd in ("ins", "ahrs"):
        try:
            rc = cli.main([cmd, "run", "--log", str(f), "--out", str(tmp_path / "o.csv"), "--declination", "auto",
                           "--date", date])
        except SystemExit as e:  # argparse: one line, exit status 2
            rc = e.code
        err = capsys.readouterr().err
        assert rc == 2 and why in err and len(err.strip().splitlines()) == 1, err
    assert cli.main(["ahrs", "run", "--log", str(f), "--out", str(tmp_path / "o.csv"), "--date", "2027-01-01"]) == 2
    assert cli.main(["ins", "run", "--log", str(f), "--out", str(tmp_path / "o.csv"), "--declination", "3",
                     "--date", "2027-01-01"]) == 2
    err = capsys.readouterr().err
    assert err.count("it goes with --declination auto") == 2 and len(err.strip().splitlines()) == 2


def test_date_after_the_model_is_a_warning(tmp_path, data_dir, capsys):
    """A date after the newest model's five years is evaluated (its secular change extrapolated)
    with one warning line."""
    pytest.importorskip("pyulog")
    pytest.importorskip("ahrs")
    f = data_dir / "px4" / "sample_logging_tagged_and_default_params.ulg"
    if not f.exists():
        pytest.skip("px4 data absent")
    assert cli.main(["ahrs", "run", "--log", str(f), "--out", str(tmp_path / "a.csv"), "--declination", "auto",
                     "--date", "2031-06-01"]) == 0
    c = capsys.readouterr()
    assert "on 2031-06-01" in c.out
    w = [x for x in c.err.splitlines() if "warning" in x]
    assert len(w) == 1 and "outside WMM-2025's validity (2025.0 to 2030.0)" in w[0]


def test_declination_auto_without_a_date_says_so(walk, tmp_path, capsys):
    """GNSS without a date (the simulated walk's CSV, times from 0 s): the model at today's date and
    a note that says so; a utc column (UTC s since 1970) or an RTKLIB .pos file (calendar times)
    dates it (the .pos file's GPST less the leap seconds); a utc column that is not seconds is one
    line, exit status 2."""
    pytest.importorskip("ahrs")
    d = walk
    out, js = tmp_path / "o.csv", tmp_path / "s.json"
    base = ["ins", "run", "--baro", str(d / "baro_abs.csv"), "--config", str(d / "config.toml"), "--out", str(out),
            "--json", str(js), "--declination", "auto", "--imu", str(d / "imu_abs.csv"), "--gnss"]
    assert cli.main(base + [str(d / "gnss_abs.csv")]) == 0
    o = capsys.readouterr().out
    note = [x for x in o.splitlines() if "no recording date" in x]
    assert len(note) == 1 and note[0].startswith("note: GNSS ") and "--date" in note[0]
    assert "today" in json.loads(js.read_text())["declination_note"]
    g = pd.read_csv(d / "gnss_abs.csv")
    g["utc"] = g["time"]  # the simulated times start on 2026-01-01 (EPOCH)
    g.to_csv(tmp_path / "g.csv", index=False, float_format="%.17g")
    # the .pos file's GPST times from 2026-01-01 00:00:00 are 18 s ahead of UTC: 2025-12-31 at the first fix
    for gnss, day in ((tmp_path / "g.csv", "2026-01-01"), (d / "gnss.pos", "2025-12-31")):
        assert cli.main(base + [str(gnss)]) == 0
        s = json.loads(js.read_text())
        assert f"on {day} (2026.00, from the log's GNSS UTC time)" in s["declination_note"], gnss
        assert "no recording date" not in capsys.readouterr().out
    g["utc"] = "2026-01-01T00:00:00Z"
    g.to_csv(tmp_path / "g.csv", index=False, float_format="%.17g")
    assert cli.main(base + [str(tmp_path / "g.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "column 'utc'" in err[0] and "Unix time" in err[0]
    # without --declination auto the column is not read
    assert cli.main(base[:-5] + ["--imu", str(d / "imu_abs.csv"), "--gnss", str(tmp_path / "g.csv")]) == 0


def test_wmm_declination_sign_and_size():
    """East positive, as the model's maps give it: about +3 to +5 deg in Zurich, +7 to +9 deg in
    Boulder, -10 to -14 deg in Boston, 2025-2030; a declination argument is degrees or auto."""
    pytest.importorskip("ahrs")
    import argparse
    from quatnav.cli.util import declination_arg
    from quatnav.core.magnetic import wmm_declination
    for lat, lon, lo, hi in ((47.4, 8.5, 2.5, 5.5), (40.0, -105.3, 6.5, 9.5), (42.4, -71.1, -14.5, -10.0)):
        d, note = wmm_declination(np.radians(lat), np.radians(lon), 0.0, year=2027.0)
        assert lo < np.degrees(d) < hi, (lat, lon, np.degrees(d))
        assert "2027.0" in note
    # on the equator and the prime meridian too (ahrs evaluates in its constructor only off them)
    d, note = wmm_declination(0.0, 0.0, 0.0, year=2027.0)
    assert -10.0 < np.degrees(d) < 10.0 and "on 2027-01-01" in note
    assert declination_arg("auto") is None and declination_arg(" AUTO ") is None
    assert declination_arg("-8.5") == -8.5
    for bad in ("east", "nan", "200"):
        with pytest.raises(argparse.ArgumentTypeError):
            declination_arg(bad)


def _figure_ok(path, min_w, min_h):
    """A PNG of a real figure: its size, and more than a few colours (not blank)."""
    import matplotlib.image as mpimg
    img = mpimg.imread(path)
    assert img.shape[1] >= min_w and img.shape[0] >= min_h, img.shape
    assert len(np.unique((img[..., :3] * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50, "blank figure"
