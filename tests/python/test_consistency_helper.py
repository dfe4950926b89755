"""The consistency tests' shared helper (_consistency.py): which parameters it scales, that
scaling Q, R and P0 by c leaves an EKF's estimates and multiplies its covariance by c (so the
NEES by 1/c), and the chi-square interval and its power."""
from __future__ import annotations

import math

import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q
from quatnav.filters.nav13 import initial_covariance
from quatnav.filters.tables import PARAM_TABLES

import _consistency as C


def test_every_noise_parameter_of_every_filter_is_scaled_and_nothing_else():
    for name, table in PARAM_TABLES.items():
        noise = set(C.noise_params(name))
        for p in table:
            looks = "noise" in p.name or "sigma" in p.name
            assert (p.name in noise) == (looks and p.name not in C.NOT_NOISE), (name, p.name)
        kw = C.scaled(name, c=2.25)
        defaults = {p.name: p.default for p in table}
        assert set(kw) == noise
        for k in noise:
            assert kw[k] == pytest.approx(1.5 * defaults[k], rel=1e-15, abs=0), (name, k)
        getattr(quatnav, name)(**kw)  # accepted by the filter
    assert C.scaled("NavFilter13", c=4.0, acc_noise=1e-3, time_update="ukf") == {
        **C.scaled("NavFilter13", c=4.0), "acc_noise": 2e-3, "time_update": "ukf"}
    with pytest.raises(TypeError, match="acc_nois"):
        C.scaled("NavFilter13", acc_nois=1.0)


def test_the_factor_comes_from_the_environment(monkeypatch):
    monkeypatch.delenv(C.VARIANCE_SCALE_ENV, raising=False)
    assert C.variance_scale() == 1.0
    monkeypatch.setenv(C.VARIANCE_SCALE_ENV, "0.6666666666666666")
    assert C.variance_scale() == pytest.approx(1 / 1.5)
    assert C.scaled_sigma(2.0) == pytest.approx(2.0 / math.sqrt(1.5))
    np.testing.assert_allclose(C.scaled_covariance(np.eye(2)), np.eye(2) / 1.5)
    assert C.scaled("NavFilter13")["gps_vel_sigma"] == pytest.approx(0.03048 / math.sqrt(1.5))
    monkeypatch.setenv(C.VARIANCE_SCALE_ENV, "-1")
    with pytest.raises(ValueError, match=C.VARIANCE_SCALE_ENV):
        C.variance_scale()


def test_scaling_q_r_and_p0_by_c_scales_the_ekf_covariance_by_c_and_keeps_its_estimates():
    """The property the power checks rest on: NavFilter13's EKF (a linearized filter, the gains
    invariant) with Q, R and P0 times 1.5 gives the same estimates and 1.5 times the covariance."""
    rng = np.random.default_rng(4)
    q0 = Q.from_euler(np.radians([3.0, -2.0, 40.0]))
    P0 = initial_covariance(q0, 0.3, np.radians([5.0, 5.0, 10.0]), 0.02, np.radians(2.0) / 3600)
    n = 600
    t = np.arange(1, n + 1) * 0.01
    f = np.column_stack([0.2 * np.sin(t), 0.1 * np.cos(t), -9.8 + 0.0 * t]) + 1e-3 * rng.standard_normal((n, 3))
    w = np.column_stack([0.02 * np.sin(t), 0.0 * t, 0.1 + 0.0 * t]) + 1e-4 * rng.standard_normal((n, 3))
    vel = quatnav.Aid(t[9::10], np.array([1.0, 0.5, 0.0]) + 0.03 * rng.standard_normal((n // 10, 3)))
    yaw = quatnav.Aid(t[9::10], np.radians(40.0) + 0.03 * rng.standard_normal(n // 10))
    out = {}
    for c in (1.0, 1.5):
        flt = quatnav.NavFilter13(**C.scaled("NavFilter13", c=c, acc_noise=1e-3, gyro_noise=1e-4,
                                             acc_bias_noise=1e-5, gyro_bias_noise=1e-6))
        flt.reset([1.0, 0.5, 0.0], q0, np.zeros(3), np.zeros(3), C.scaled_covariance(P0, c), lat=0.6, lon=0.2, h=10.0)
        out[c] = flt.run(w, f, t=t, gps_vel=vel, yaw=yaw, return_covariance=True)
    np.testing.assert_allclose(out[1.5].x, out[1.0].x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(out[1.5].P, 1.5 * out[1.0].P, rtol=1e-7, atol=1e-7 * np.abs(out[1.0].P).max())
    np.testing.assert_allclose(out[1.5].aids["gps_vel"].nis, out[1.0].aids["gps_vel"].nis / 1.5, rtol=1e-7)


def test_chi2_interval_and_power():
    """The interval of a mean NEES per dof over n dof, two-sided 99 %: n = 296 is the fewest with
    99 % power against a covariance off by 1.5 either way (the mean of 1.5 X is above the upper
    bound, of X / 1.5 below the lower bound, each with probability >= 99 %); 8 runs of a 12-state
    NEES at one time (96 dof) have about 52 %."""
    chi2 = pytest.importorskip("scipy.stats").chi2
    lo, hi = C.chi2_interval(296)
    assert chi2.cdf(lo * 296, 296) == pytest.approx(0.005) and chi2.sf(hi * 296, 296) == pytest.approx(0.005)
    assert C.required_dof(1.5) == 296
    assert C.power(295) < 0.99 <= C.power(296)
    assert 0.5 < C.power(96) < 0.55
    rng = np.random.default_rng(0)  # the rejection rates it promises, by simulation
    x = rng.chisquare(296, size=20000) / 296
    assert np.mean((x < lo) | (x > hi)) == pytest.approx(0.01, abs=0.003)
    assert np.mean((1.5 * x > lo) & (1.5 * x < hi)) < 0.012  # 1 % at most, +3 standard errors
    assert np.mean((x / 1.5 > lo) & (x / 1.5 < hi)) < 0.012
    # the C++ tests' Wilson-Hilferty form (tests/cpp/consistency.hpp) agrees
    wh = lambda n, z: (1 - 2 / (9 * n) + z * math.sqrt(2 / (9 * n))) ** 3  # noqa: E731
    assert wh(296, -2.5758293035489) == pytest.approx(lo, rel=1e-3)
    assert wh(296, 2.5758293035489) == pytest.approx(hi, rel=1e-3)


def test_check_mean_nees_refuses_a_design_without_power():
    rng = np.random.default_rng(1)
    nees = rng.chisquare(12, size=(30, 5))
    assert C.check_mean_nees(nees, 12, m_eff=1.0) == pytest.approx(np.mean(nees) / 12)
    with pytest.raises(AssertionError, match="power"):
        C.check_mean_nees(nees[:8], 12, m_eff=1.0)
    with pytest.raises(AssertionError, match="outside"):
        C.check_mean_nees(1.5 * nees, 12, m_eff=1.0)
