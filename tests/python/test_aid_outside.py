"""An aid whose times all lie before or all after the IMU's (another clock) is named in an
AidWarning by every filter's run, with what the filter does with it; an aid that overlaps the IMU
stays quiet."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q

N, DT = 400, 0.01
T = 100.0 + DT * np.arange(1, N + 1)  # the IMU's clock: 100.01..104 s


def _imu():
    rng = np.random.default_rng(2)
    gyr = 0.01 * rng.standard_normal((N, 3))
    acc = np.tile([0.0, 0.0, -9.81], (N, 1)) + 0.02 * rng.standard_normal((N, 3))
    mag = np.tile([0.2, 0.0, 0.4], (N, 1))
    return gyr, acc, mag


def _quiet(fn):
    with warnings.catch_warnings():
        warnings.simplefilter("error", quatnav.AidWarning)
        return fn()


def test_marg_gps_vel_on_another_clock():
    gyr, acc, mag = _imu()
    v = np.zeros((20, 3))
    run = lambda at: quatnav.MargFilter().run(gyr, acc, mag, t=T, gps_vel=quatnav.Aid(at, v))
    _quiet(lambda: run(T[::20]))
    with pytest.warns(quatnav.AidWarning, match=r"MargFilter: all 20 gps_vel times \(t = 1700000100\.\.1700000104 s\) "
                                               r"are after the IMU's \(t = 100\.\.104 s\): none is used"):
        run(T[::20] + 1.7e9)
    with pytest.warns(quatnav.AidWarning, match=r"are before the IMU's .*taken at the first sample"):
        run(T[::20] - 50.0)


def test_nav13_aids_on_another_clock():
    gyr, acc, _ = _imu()
    q0 = Q.from_euler([0.0, 0.0, 0.3])

    def run(vt, yt):
        f = quatnav.NavFilter13()
        f.reset(np.zeros(3), q0, lat=0.6, lon=2.0, h=50.0)
        return f.run(gyr, acc, t=T, gps_vel=quatnav.Aid(vt, np.zeros((len(vt), 3))),
                     yaw=quatnav.Aid(yt, np.full(len(yt), 0.3)))

    _quiet(lambda: run(T[9::10], T[4::10]))
    with pytest.warns(quatnav.AidWarning, match=r"NavFilter13: all 40 yaw times .* are before the IMU's "
                                               r"\(t = 100\.\.104 s\): none is used"):
        run(T[9::10], T[4::10] - 100.0)


def test_gpsins_baro_and_compass_on_another_clock():
    gyr, acc, _ = _imu()
    f = quatnav.GpsInsFilter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", quatnav.NavigationWarning)  # no GNSS here: it does not navigate
        with pytest.warns(quatnav.AidWarning) as rec:
            f.run(gyr, acc, t=T, baro=quatnav.Aid(T[::10] + 1e6, np.full(40, 50.0)),
                  compass=quatnav.Aid(T[::10], np.full(40, 0.3)))
    msgs = [str(w.message) for w in rec if w.category is quatnav.AidWarning]
    assert len(msgs) == 1 and msgs[0].startswith("GpsInsFilter: all 40 baro times") and "after the IMU's" in msgs[0]


def test_ins_run_prints_it_as_one_line(tmp_path, capsys):
    from quatnav import cli
    rng = np.random.default_rng(0)
    n = 1500
    t = np.arange(n) * 0.01
    imu, gnss, baro = tmp_path / "imu.csv", tmp_path / "gnss.csv", tmp_path / "baro.csv"
    np.savetxt(imu, np.column_stack([t, rng.normal(0, 0.002, (n, 3)), [0, 0, -9.81] + rng.normal(0, 0.02, (n, 3))]),
               delimiter=",", comments="", header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    tg = t[::20]
    np.savetxt(gnss, np.column_stack([tg, np.full(len(tg), 47.4), np.full(len(tg), 8.5), np.full(len(tg), 400.0)]),
               delimiter=",", comments="", header="time,lat,lon,h")
    np.savetxt(baro, np.column_stack([tg + 1.7e9, np.full(len(tg), 400.0)]), delimiter=",", comments="",
               header="time,h")
    cli.main(["ins", "run", "--imu", str(imu), "--gnss", str(gnss), "--baro", str(baro), "--out", str(tmp_path / "o.csv")])
    err = capsys.readouterr().err
    assert "quatnav ins run: warning: GpsInsFilter: all 75 baro times (t = 1700000000..1700000015 s) are after" in err
    assert "AidWarning" not in err and "Traceback" not in err
