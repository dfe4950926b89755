"""GpsInsFilter.run says why navigation did not start: ``alignment["reason"]`` names the step of
the alignment that was not reached, a NavigationWarning carries it on a record long enough to
align, and ``quatnav ins run`` prints it in its 0-row message."""
import warnings

import numpy as np
import pytest

import quatnav
from quatnav import Aid, NavigationWarning, cli
from quatnav.sim.scenarios import make_scenario

N, DT = 2000, 0.01  # 20 s: longer than align_time + align_motion_max (12 s)
LLH = np.radians([47.4, 8.5]).tolist() + [400.0]


def _still(n=N, seed=0):
    """A still IMU (forward-right-down, level): white noise on the rates and the specific force."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    gyr = rng.normal(0.0, 0.002, (n, 3))
    acc = np.array([0.0, 0.0, -9.81]) + rng.normal(0.0, 0.02, (n, 3))
    tg = t[::20]
    return t, gyr, acc, Aid(tg, np.tile(LLH, (len(tg), 1)))


def _run(gyr, acc, mag=None, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = quatnav.GpsInsFilter().run(gyr, acc, mag, **kw)
    return r, [w for w in caught if issubclass(w.category, NavigationWarning)]


def test_levelled_without_a_heading_source():
    t, gyr, acc, fixes = _still()
    r, caught = _run(gyr, acc, t=t, gps_pos=fixes)
    assert not r.navigating.any()
    assert r.alignment["method"] == "static" and r.alignment["heading"] == "none"
    reason = r.alignment["reason"]
    assert reason.startswith("levelled (static) at t = 2 s, but no heading")
    assert "no magnetometer" in reason and "no compass" in reason and "no GNSS velocity" in reason
    assert len(caught) == 1
    msg = str(caught[0].message)
    assert reason in msg and "set_initial()" in msg and "t = 0..19.99 s" in msg
    # With a GNSS velocity at rest the course never comes: the speed threshold is named.
    vel = Aid(fixes.t, np.zeros((len(fixes.t), 3)))
    r, _ = _run(gyr, acc, t=t, gps_pos=fixes, gps_vel=vel)
    assert "never reached min_speed_for_heading = 1 m/s" in r.alignment["reason"]


def test_accelerometer_in_g_is_named():
    t, gyr, acc, fixes = _still()
    r, caught = _run(gyr, acc / 9.80665, t=t, gps_pos=fixes)
    assert r.alignment["method"] == "none"
    reason = r.alignment["reason"]
    assert reason.startswith("it never levelled: acc looks like g") and "multiply by 9.80665" in reason
    assert len(caught) == 1
    # In m/s^2 but far from gravity (an accelerometer in another unit): its unit is questioned.
    r, _ = _run(gyr, acc * 3.0, t=t, gps_pos=fixes)
    assert "far from gravity" in r.alignment["reason"]


def test_no_fix_late_fixes_and_fixes_before_the_alignment():
    t, gyr, acc, fixes = _still()
    mag = np.tile([20.0, 1.0, 40.0], (N, 1))
    r, caught = _run(gyr, acc, mag, t=t)
    assert r.alignment["reason"].startswith("no GNSS position fix was given") and len(caught) == 1
    late = Aid(fixes.t + 100.0, fixes.value)
    r, _ = _run(gyr, acc, mag, t=t, gps_pos=late)
    assert "do not overlap the IMU's times" in r.alignment["reason"]
    # Fixes only before the static alignment ends (2 s): aligned with the magnetometer's heading.
    early = Aid(fixes.t[:5], fixes.value[:5])
    r, _ = _run(gyr, acc, mag, t=t, gps_pos=early)
    assert r.alignment["heading"] == "magnetometer"
    assert r.alignment["reason"].startswith("aligned (static, heading from magnetometer) at t = 2 s, but no GNSS")


def test_short_record_and_navigating_run_give_no_warning():
    t, gyr, acc, fixes = _still(n=500)  # 5 s: shorter than an alignment may take, e.g. one chunk of a stream
    r, caught = _run(gyr, acc, t=t, gps_pos=fixes)
    assert r.alignment["reason"] and not caught
    s = make_scenario("paper004_walk", seed=0)
    g = s.gps
    with warnings.catch_warnings():
        warnings.simplefilter("error", NavigationWarning)
        r = quatnav.GpsInsFilter().run(s.imu.gyro, s.imu.accel, t=s.imu.t,
                                       gps_pos=Aid(g.t_valid, np.column_stack([g.lat, g.lon, g.h])),
                                       gps_vel=Aid(g.t_valid, g.v_n), compass=Aid(s.compass.t, s.compass.yaw))
    assert r.navigating.any() and r.alignment["reason"] is None


def test_ins_run_prints_the_reason_without_a_python_warning(tmp_path, capsys):
    t, gyr, acc, fixes = _still()
    imu, gnss = tmp_path / "imu.csv", tmp_path / "gnss.csv"
    np.savetxt(imu, np.column_stack([t, gyr, acc]), delimiter=",", comments="",
               header="time,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z")
    np.savetxt(gnss, np.column_stack([fixes.t, np.full(len(fixes.t), 47.4), np.full(len(fixes.t), 8.5),
                                      np.full(len(fixes.t), 400.0)]), delimiter=",", comments="", header="time,lat,lon,h")
    with warnings.catch_warnings():
        warnings.simplefilter("error", NavigationWarning)
        code = cli.main(["ins", "run", "--imu", str(imu), "--gnss", str(gnss), "--out", str(tmp_path / "o.csv")])
    out, err = capsys.readouterr()
    assert code == 1
    assert "0 rows (navigation never started: levelled (static) at t = 2 s, but no heading" in out
    assert "give --mag or --compass" in out and "[initial] euler" in out
    assert "NavigationWarning" not in err and "Traceback" not in err


if __name__ == "__main__":
    raise SystemExit(pytest.main([__file__, "-q"]))
