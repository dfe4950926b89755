"""NavFilter13's Rauch-Tung-Striebel smoother (nav/nav13_smoother.hpp, docs/SMOOTHING.md): the C++
smoothed run against the numpy twin step by step for every time update, a refused time update
kept, the error-state sigmas never above the forward ones, the result's API and float32. The NEES
of the smoothed estimates: test_nav13_consistency.py."""
from __future__ import annotations

import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q
from quatnav.filters.nav13 import initial_covariance
from quatnav.reference import nav13 as R

from _consistency import chi2_interval

LAT, LON, H = np.radians(36.37), np.radians(127.36), 50.0
POLICIES = ("ekf", "second_order", "ukf")


# ---- NavFilter13: C++ against the twin ------------------------------------------------------------
def _start():
    q0 = Q.from_euler(np.radians([8.0, -6.0, 50.0]))
    P = initial_covariance(q0, 0.3, np.radians([10.0, 10.0, 20.0]), 0.02, np.radians(2.0) / 3600)
    return np.array([1.7, 1.0, 0.05]), q0, np.zeros(3), np.zeros(3), P


def _imu(rng, n, dt=0.01):
    t = np.arange(1, n + 1) * dt
    f = np.column_stack([0.3 * np.sin(0.7 * t), 0.2 * np.cos(0.5 * t), -9.80 + 0.1 * np.sin(t)])
    w = np.column_stack([0.05 * np.sin(0.3 * t), 0.04 * np.cos(0.2 * t), 0.3 * np.ones(n)])
    return t, f + 1e-3 * rng.standard_normal((n, 3)), w + 1e-4 * rng.standard_normal((n, 3))


def _aids(rng, t, every_v=7, every_y=11):
    kv = np.arange(every_v - 1, len(t), every_v)
    ky = np.arange(every_y - 1, len(t), every_y)
    vel = np.array([1.8, 0.9, 0.0]) + 0.03 * rng.standard_normal((len(kv), 3))
    yaw = np.radians(45.0) + 0.03 * rng.standard_normal(len(ky))
    return kv, vel, ky, yaw


def _twin_smoothed(tu, start, t, f, w, kv, vel, ky, yaw, **params):
    """The twin's smoothed run (reference.NavFilter13.run(smooth=True)): ``(x, P, att_sigma)``."""
    ref = R.NavFilter13(tu, **params)
    ref.reset(*start, LAT, LON, H)
    r = ref.run(w, f, t=t, gps_vel=quatnav.Aid(t[kv], vel), yaw=quatnav.Aid(t[ky], yaw), return_covariance=True,
                smooth=True)
    return r.x, r.P, r.att_sigma


@pytest.mark.parametrize("tu", POLICIES)
def test_cpp_smoother_matches_reference_step_by_step(tu):
    rng = np.random.default_rng(5)
    start = _start()
    t, f, w = _imu(rng, 150)
    kv, vel, ky, yaw = _aids(rng, t)
    cpp = quatnav.NavFilter13(time_update=tu)
    cpp.reset(*start, lat=LAT, lon=LON, h=H)
    r = cpp.run(w, f, t=t, gps_vel=quatnav.Aid(t[kv], vel), yaw=quatnav.Aid(t[ky], yaw), return_covariance=True,
                smooth=True)
    xs, Ps, att_sigma = _twin_smoothed(tu, start, t, f, w, kv, vel, ky, yaw)
    np.testing.assert_allclose(r.x, xs, atol=1e-9, rtol=0)
    np.testing.assert_allclose(r.P, Ps, atol=1e-9 * np.abs(Ps).max(), rtol=0)
    np.testing.assert_allclose(r.att_sigma, att_sigma, atol=1e-10, rtol=0)
    # The forward result is the plain run's, and the smoother moved the estimates.
    plain = quatnav.NavFilter13(time_update=tu)
    plain.reset(*start, lat=LAT, lon=LON, h=H)
    rf = plain.run(w, f, t=t, gps_vel=quatnav.Aid(t[kv], vel), yaw=quatnav.Aid(t[ky], yaw))
    np.testing.assert_array_equal(r.forward.x, rf.x)
    np.testing.assert_array_equal(r.x[-1], rf.x[-1])
    assert np.abs(r.x[:100] - rf.x[:100]).max() > 1e-4
    _sigmas_not_above(r, rf)


def _sigmas_not_above(r, rf):
    """The smoothed one-sigma values of the error state (velocity, attitude, biases) are at most
    the forward ones (to rounding). Not the quaternion components' (``sigma`` columns q0..q3):
    those of the 13-state form depend on the quaternion itself, and the smoothed quaternion is
    another one."""
    err = np.r_[0:3, 7:13]
    assert np.all(r.sigma[:, err] <= rf.sigma[:, err] * (1 + 1e-9) + 1e-15)
    assert np.all(r.att_sigma <= rf.att_sigma * (1 + 1e-9) + 1e-15)


def test_refused_time_update_is_kept_by_the_smoother():
    """A saturated IMU sample skips its time update in the forward pass; the smoother recomputes
    it as skipped (the state did not move there), like the twin (whose run links it as "same")."""
    rng = np.random.default_rng(6)
    start = _start()
    t, f, w = _imu(rng, 80)
    kv, vel, ky, yaw = _aids(rng, t)
    w = w.copy()
    w[40] = [0.0, 0.0, 5.0]  # above gyro_range
    cpp = quatnav.NavFilter13(gyro_range=4.0)
    cpp.reset(*start, lat=LAT, lon=LON, h=H)
    r = cpp.run(w, f, t=t, gps_vel=quatnav.Aid(t[kv], vel), yaw=quatnav.Aid(t[ky], yaw), smooth=True)
    assert r.flag("saturated")[40]
    xs, _, _ = _twin_smoothed("ekf", start, t, f, w, kv, vel, ky, yaw, gyro_range=4.0)
    np.testing.assert_allclose(r.x, xs, atol=1e-9, rtol=0)
    np.testing.assert_array_equal(r.x[39], r.x[40])


def test_smoothed_result_api_and_float32():
    rng = np.random.default_rng(7)
    start = _start()
    t, f, w = _imu(rng, 300)
    kv, vel, ky, yaw = _aids(rng, t)
    out = {}
    for dtype in (np.float64, np.float32):
        flt = quatnav.NavFilter13(dtype=dtype)
        flt.reset(*start, lat=LAT, lon=LON, h=H)
        r = flt.run(w, f, t=t, gps_vel=quatnav.Aid(t[kv], vel), yaw=quatnav.Aid(t[ky], yaw), smooth=True)
        assert isinstance(r, quatnav.NavFilter13Result) and isinstance(r.forward, quatnav.NavFilter13Result)
        assert r.smoothed and not r.forward.smoothed and r.forward.forward is None
        assert "smoothed" in repr(r) and r.x.dtype == dtype
        assert r.aids["gps_vel"] is r.forward.aids["gps_vel"]
        np.testing.assert_array_equal(r.flags, r.forward.flags)
        assert r.smoother["status"] == "ok" and r.smoother["bytes"] > 0
        # records: the samples changed by an aid (the yaw and velocity epochs), a checkpoint every 256
        assert r.smoother["records"] <= len(np.union1d(kv, ky)) + 1 + len(t) // 256 + 1
        out[dtype] = r
    np.testing.assert_allclose(out[np.float32].x, out[np.float64].x, atol=2e-4)
    # Where the smoother shrinks a sigma 100-fold (the first samples: 10 deg forward, 0.12 deg
    # smoothed), P^s = P + C (P^s - P_prior) C^T cancels all but 1e-4 of the forward variance, so
    # the float32 filter's rounding of P (1e-7) shows at 1e-3 of the smoothed variance: measured
    # 1.1 % on the attitude sigma at sample 0, 1e-4 on the velocity sigma (docs/SMOOTHING.md).
    err = np.r_[0:3, 7:13]
    np.testing.assert_allclose(out[np.float32].sigma[:, err], out[np.float64].sigma[:, err], rtol=1e-3, atol=1e-9)
    np.testing.assert_allclose(out[np.float32].att_sigma, out[np.float64].att_sigma, rtol=2e-2)


def test_smoothing_experiment_cli(tmp_path, capsys):
    """``quatnav experiment smoothing --parts nav13 --runs 1``: the JSON holds each time update's
    smoothed and forward figures, the smoothed attitude errors below the forward ones (the gyro
    bias too over 8 runs, docs/SMOOTHING.md; one run is too few for it);
    an unknown part is a usage error (exit status 2, one line)."""
    from quatnav import cli
    out = tmp_path / "s.json"
    assert cli.main(["experiment", "smoothing", "--parts", "nav13", "--runs", "1", "--json", str(out)]) == 0
    import json
    d = json.loads(out.read_text())["nav13"]
    # The ANEES of one run (mean over its samples of a 12-dof NEES): its samples are correlated
    # (the bias errors persist), so the two-sided 99 % chi-square interval of one 12-dof sample,
    # 12 * [0.26, 2.36] = [3.1, 28.3]. (The experiment keeps 5x the paper's accelerometer noise and its 2000 ug
    # initial bias one-sigma, where the vertical bias is optimistic, docs/NAV13.md: measured
    # 10.6-25.1 forward and smoothed.)
    lo, hi = 12 * np.array(chi2_interval(12))
    for tu in POLICIES:
        s, f = d[tu]["smoothed"], d[tu]["forward"]
        for a in ("roll", "pitch", "yaw"):
            assert s["rpy_rmse_deg"][a] < f["rpy_rmse_deg"][a]
        assert lo < s["anees"] < hi and lo < f["anees"] < hi, (tu, s["anees"], f["anees"], lo, hi)
    capsys.readouterr()
    assert cli.main(["experiment", "smoothing", "--parts", "bogus"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--parts" in err and len(err.splitlines()) == 1
