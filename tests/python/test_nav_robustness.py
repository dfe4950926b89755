"""Arbitrary input through the Python API of the navigation filters (NavFilter13, GpsInsFilter):
every call either raises ValueError/TypeError naming the argument (and, for batch input, the
row), or returns finite estimates; a refused single step leaves get_state() unchanged; with
on_invalid="skip" the unusable rows are reported in skipped_rows.
"""
from __future__ import annotations

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

import quatnav  # noqa: E402
from quatnav.filters.gpsins import GPSINS_FLAGS  # noqa: E402
from quatnav.filters.nav13 import NAV13_FLAGS, initial_covariance  # noqa: E402

from _aids import as_aids  # noqa: E402

SETTINGS = settings(max_examples=25, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

NASTY = [np.nan, np.inf, -np.inf, 0.0, -0.0, 1e300, -1e300, 1e-300, 5e-324, 3.4e38, 1e-45]
LAT, LON, H = 0.6, 0.2, 100.0


def _column(n, typical, draw):
    base = np.tile(np.asarray(typical, float), (n, 1))
    noise = draw(hnp.arrays(np.float64, (n, 3), elements=st.floats(-1, 1)))
    a = base + noise * np.linalg.norm(typical) * 0.05
    for _ in range(draw(st.integers(0, 3))):
        a[draw(st.integers(0, n - 1)), draw(st.integers(0, 2))] = draw(st.sampled_from(NASTY))
    if draw(st.booleans()):
        a[draw(st.integers(0, n - 1))] = draw(st.sampled_from([np.nan, 0.0]))
    return a


def _times(n, draw, dt=0.01, start=0.0):
    t = start + np.cumsum(np.full(n, dt))
    if n > 1 and draw(st.booleans()):
        i = draw(st.integers(1, n - 1))
        t[i] = t[i - 1] + draw(st.sampled_from([0.0, -dt, np.nan, 10.0]))  # repeated, decreasing, NaN, gap
    return t


def _arg(msg):
    return msg.split(":")[0].split("[")[0].split(",")[0].strip()


# --- NavFilter13 ----------------------------------------------------------------------------
@st.composite
def nav13_logs(draw):
    n = draw(st.integers(2, 30))
    fb = _column(n, [0.3, -0.2, -9.8], draw)
    wb = _column(n, [0.01, -0.02, 0.03], draw)
    t = _times(n, draw)
    k = draw(st.integers(0, 5))
    vel_t = np.sort(draw(hnp.arrays(np.float64, k, elements=st.floats(0, 0.3))))
    vel = _column(k, [0.1, 0.0, 0.0], draw) if k else np.zeros((0, 3))
    if k and draw(st.booleans()):
        vel_t[draw(st.integers(0, k - 1))] = draw(st.sampled_from([np.nan, -1.0]))
    m = draw(st.integers(0, 5))
    yaw_t = np.sort(draw(hnp.arrays(np.float64, m, elements=st.floats(0, 0.3))))
    yaw = draw(hnp.arrays(np.float64, m, elements=st.sampled_from(NASTY + [0.1, -3.0, 3.1])))
    return fb, wb, t, (vel_t, vel) if k else (None, None), (yaw_t, yaw) if m else (None, None)


def _nav13(time_update, dtype):
    f = quatnav.NavFilter13(time_update=time_update, dtype=dtype, gyro_range=20.0, acc_range=150.0, acc_noise=1e-3,
                            gyro_noise=1e-4)
    q = quatnav.core.quaternion.from_euler([0.1, 0.2, 0.3])
    f.reset([0.1, 0.0, 0.0], q, P=initial_covariance(q, 0.1, [0.01, 0.01, 0.02], 0.01, 1e-3),
            lat=LAT, lon=LON, h=H)
    return f


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("time_update", ["ekf", "second_order", "ukf"])
@pytest.mark.parametrize("on_invalid", ["raise", "skip"])
@SETTINGS
@given(log=nav13_logs())
def test_nav13_run_raises_or_stays_finite(time_update, dtype, on_invalid, log):
    fb, wb, t, (vel_t, vel), (yaw_t, yaw) = log
    f = _nav13(time_update, dtype)
    try:
        res = f.run(wb, fb, t=t, gps_vel=None if vel_t is None else quatnav.Aid(vel_t, vel),
                    yaw=None if yaw_t is None else quatnav.Aid(yaw_t, yaw), on_invalid=on_invalid)
    except (ValueError, TypeError) as exc:
        assert _arg(str(exc)) in {"acc", "gyr", "t", "gps_vel.t", "gps_vel.value", "yaw.t", "yaw.value"}, str(exc)
        if on_invalid == "skip":  # only the timestamps may raise in skip mode
            assert _arg(str(exc)) in {"t", "gps_vel.t", "yaw.t"}, str(exc)
        return
    assert np.isfinite(res.x).all() and np.isfinite(res.sigma).all()
    assert np.all(np.abs(np.linalg.norm(res.x[:, 3:7], axis=1) - 1) < 1e-3)
    with np.errstate(over="ignore"):
        fb, wb = fb.astype(dtype), wb.astype(dtype)  # 1e300 is inf in float32
    bad = ~np.isfinite(fb).all(axis=1) | ~np.isfinite(wb).all(axis=1)
    sat = np.isfinite(wb).all(axis=1) & (np.abs(wb).max(axis=1) >= 20.0) | \
        np.isfinite(fb).all(axis=1) & (np.abs(fb).max(axis=1) >= 150.0)
    assert np.all(res.flags[bad | sat] & NAV13_FLAGS["predict_skipped"])
    assert np.all(res.flags[sat & ~bad] & NAV13_FLAGS["saturated"])
    if on_invalid == "skip":
        np.testing.assert_array_equal(res.skipped_rows.get("predict_skipped", []), np.flatnonzero(bad | sat))


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("time_update", ["ekf", "ukf"])
@SETTINGS
@given(ops=st.lists(st.tuples(st.sampled_from(["predict", "update_velocity", "update_yaw", "update_velocity_yaw"]),
                              st.lists(st.sampled_from(NASTY + [0.1, -9.8, 0.3, 25.0]), min_size=3, max_size=3),
                              st.sampled_from([0.01, 0.0, -1.0, np.nan, 1e9, 0.3, np.inf])),
                    min_size=1, max_size=20))
def test_nav13_steps_refuse_or_keep_state_finite(time_update, dtype, ops):
    f = _nav13(time_update, dtype)
    for op, v, s in ops:
        before = f.get_state()
        try:
            if op == "predict":
                status = f.predict(v, [0.3, -0.2, -9.8] if np.isfinite(v).all() else v, s)
            elif op == "update_velocity":
                status = f.update_velocity(v).status
            elif op == "update_yaw":
                status = f.update_yaw(s).status
            else:
                status = f.update_velocity_yaw(v, s).status
        except (ValueError, TypeError) as exc:
            assert _arg(str(exc)) in {"gyr", "acc", "dt", "v_n", "yaw"}, str(exc)
            status = "raised"
        after = f.get_state()
        if status not in ("ok", "rejected"):
            for key, value in before.items():
                np.testing.assert_array_equal(np.asarray(after[key]), np.asarray(value), err_msg=key)
        for key, value in after.items():
            assert np.all(np.isfinite(np.asarray(value, dtype=float))), key
        assert abs(np.linalg.norm(f.quat) - 1) < 1e-3


# --- GpsInsFilter ---------------------------------------------------------------------------
@st.composite
def gpsins_logs(draw):
    n = draw(st.integers(2, 40))
    gyro = _column(n, [0.01, -0.02, 0.03], draw)
    accel = _column(n, [0.3, -0.2, -9.8], draw)
    t = _times(n, draw)
    k = draw(st.integers(0, 4))
    gps_t = np.arange(1, k + 1) * 0.05
    llh = np.tile([LAT, LON, H], (k, 1)) + draw(hnp.arrays(np.float64, (k, 3), elements=st.floats(-1e-6, 1e-6)))
    vel = _column(k, [1.0, 0.0, 0.0], draw) if k else np.zeros((0, 3))
    if k and draw(st.booleans()):
        llh[draw(st.integers(0, k - 1)), draw(st.integers(0, 2))] = draw(st.sampled_from(NASTY))
    b = draw(st.integers(0, 4))
    baro_t = np.arange(1, b + 1) * 0.04
    baro_h = draw(hnp.arrays(np.float64, b, elements=st.sampled_from(NASTY + [100.0, 101.0])))
    c = draw(st.integers(0, 4))
    compass_t = np.arange(1, c + 1) * 0.03
    compass = draw(hnp.arrays(np.float64, c, elements=st.sampled_from(NASTY + [0.3, -3.0])))
    return gyro, accel, t, dict(gps_t=gps_t if k else None, gps_llh=llh if k else None, gps_vel=vel if k else None,
                                baro_t=baro_t if b else None, baro_h=baro_h if b else None,
                                compass_t=compass_t if c else None, compass_yaw=compass if c else None)


def _gpsins(dtype):
    f = quatnav.GpsInsFilter(dtype=dtype, align_time=0.05, gyro_range=20.0, acc_range=150.0)
    return f


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("on_invalid", ["raise", "skip"])
@SETTINGS
@given(log=gpsins_logs())
def test_gpsins_run_raises_or_stays_finite(dtype, on_invalid, log):
    gyro, accel, t, aids = log
    f = _gpsins(dtype)
    try:
        res = f.run(gyro, accel, t=t, on_invalid=on_invalid, **as_aids(aids))
    except (ValueError, TypeError) as exc:
        assert _arg(str(exc)) in {"t", "gyr", "acc", "gps_pos.t", "gps_pos.value", "gps_vel.value", "baro.t",
                                  "baro.value", "compass.t", "compass.value"}, str(exc)
        if on_invalid == "skip":
            assert _arg(str(exc)) in {"t", "gps_pos.t", "baro.t", "compass.t"}, str(exc)
        return
    nav = res.navigating
    assert np.isfinite(res.position[nav]).all() and np.isfinite(res.velocity[nav]).all()
    assert np.isfinite(res.sigma[nav]).all()
    lev = np.isfinite(res.quat[:, 0])
    assert np.isfinite(res.quat[lev]).all()
    assert np.all(np.abs(np.linalg.norm(res.quat[lev], axis=1) - 1) < 1e-3)
    assert np.isfinite(res.acc_bias).all() and np.isfinite(res.bias).all()
    bad = ~np.isfinite(gyro).all(axis=1) | ~np.isfinite(accel).all(axis=1)
    bad[0] = False
    assert np.all(res.flags[bad] & GPSINS_FLAGS["predict_skipped"])
    if on_invalid == "skip" and bad.any():
        assert set(np.flatnonzero(bad)) <= set(res.skipped_rows["predict_skipped"])


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@SETTINGS
@given(ops=st.lists(st.tuples(st.sampled_from(["predict", "update_gps", "update_baro", "update_compass"]),
                              st.lists(st.sampled_from(NASTY + [0.01, -9.8, 0.3, 1.0]), min_size=3, max_size=3),
                              st.sampled_from([0.01, 0.0, -1.0, np.nan, 1e9, np.inf, 100.0])),
                    min_size=1, max_size=25))
def test_gpsins_steps_refuse_or_keep_state_finite(dtype, ops):
    f = _gpsins(dtype)
    f._f.reset(quatnav.core.quaternion.from_euler([0.1, 0.2, 0.3]).astype(dtype), np.zeros(3, dtype), LAT, LON, H,
                    np.zeros(3, dtype), np.zeros(3, dtype), np.diag(np.full(16, 1e-2)).astype(dtype))
    for op, v, s in ops:
        before = f.get_state()
        try:
            if op == "predict":
                status = f.predict(v, [0.3, -0.2, -9.8], s)
            elif op == "update_gps":
                pr, vr = f.update_gps(LAT + 1e-7 * (s if np.isfinite(s) else 0), LON, s, v_n=v)
                status = "ok" if "ok" in (pr.status, vr.status) else pr.status
            elif op == "update_baro":
                status = f.update_baro(s)[0].status
            else:
                status = f.update_compass(s).status
        except (ValueError, TypeError) as exc:
            assert _arg(str(exc)) in {"gyr", "acc", "dt", "lat", "lon", "h", "v_n", "heading"}, str(exc)
            status = "raised"
        after = f.get_state()
        if status not in ("ok", "rejected"):
            for key in before:
                if key in ("accepted", "rejected", "skipped", "inflated", "resets"):  # the counters count refusals too
                    continue
                np.testing.assert_equal(after[key], before[key], err_msg=key)
        assert np.isfinite(f.quat).all() and abs(np.linalg.norm(f.quat) - 1) < 1e-3
        assert np.isfinite(f.covariance).all() and np.isfinite(f.v_n).all() and np.isfinite(f.llh).all()
