"""The robustness parts of the attitude filters (cpp/include/quatnav/attitude/parts/): their
numpy twins (quatnav.reference.parts) on their own, and the declaration of their parameters,
which every filter composing a part lists under the part's names (the C++ twins of these tests:
tests/cpp/test_parts.cpp; the parts inside the filters, C++ against the twins step by step:
test_qekf_robust.py)."""
from types import SimpleNamespace

import numpy as np
import pytest

from quatnav.core import quaternion as Q
from quatnav.filters._base import core
from quatnav.filters.tables import PARAM_TABLES
from quatnav.reference.parts import AccFilter, MagDisturbance, MagRef, Rest

PARTS = {"RestParams": Rest, "AccFilterParams": AccFilter, "MagDisturbanceParams": MagDisturbance}
#: The filters composing each part (a table row of a part's field is the part's declaration).
COMPOSED = {"QuaternionEKF": ("QuaternionEKFParams", tuple(PARTS)), "EulerEKF": ("EulerEKFParams", tuple(PARTS)),
            "MargFilter": ("MargFilterParams", tuple(PARTS))}


def _params(struct: str, **kw) -> SimpleNamespace:
    """The C++ defaults of a part's parameters, as the twins read them."""
    d = {n: v for n, v, _, _ in getattr(core(), struct + "_f64").fields()}
    d.update(kw)
    return SimpleNamespace(**d)


@pytest.mark.parametrize("name", sorted(COMPOSED))
def test_filters_list_the_parts_fields_as_the_parts_declare_them(name):
    params, parts = COMPOSED[name]
    filt = {n: (u, doc) for n, _, u, doc in getattr(core(), params + "_f64").fields()}
    table = {p.name: p for p in PARAM_TABLES[name]}
    for part in parts:
        for n, _, unit, doc in getattr(core(), part + "_f64").fields():
            assert filt[n] == (unit, doc), (name, n)
            assert (table[n].unit, table[n].doc) == (unit, doc), (name, n)


def wobble(k, a):
    return a * np.array([np.sin(0.37 * k), np.sin(0.91 * k + 1.0), np.sin(1.73 * k + 2.0)])


# ------------------------------------------------------------------------------------------ rest
def test_rest_is_declared_after_rest_time_and_not_while_turning():
    p = _params("RestParams")
    r = Rest(p)
    bias, g_b, dt = np.array([0.01, -0.02, 0.005]), np.array([0.1, -0.2, -9.8]), 0.01
    seen = []
    for k in range(300):
        r.predict(bias + wobble(k, 0.002), dt)
        seen.append(r.update(g_b + wobble(k + 5, 0.05), bias, dt))
        assert seen[-1] == r.at_rest()
    assert abs(seen.index(True) - 150) <= 1  # rest_time 1.5 s after the first sample
    for rate in ([0.0, 0.0, 0.2], [0.05, 0.0, 0.0]):  # a turn, or a bias estimate 0.05 rad/s off
        r = Rest(p)
        for _ in range(500):
            r.predict(np.array(rate), dt)
            assert not r.update([0.0, 0.0, -9.81], np.zeros(3), dt)
    assert r.zero_rate_variance(0.01, 0.01) == pytest.approx(0.01 + p.rest_rate_noise**2)
    off = Rest(_params("RestParams", rest_detection=False))
    off.predict([1.0, 0.0, 0.0], dt)
    assert not off.update([0.0, 0.0, -9.81], np.zeros(3), dt) and not off.rest_lp_init


# ---------------------------------------------------------------------------- accelerometer part
def test_acc_low_pass_follows_rotation_and_averages_out_a_burst():
    a = AccFilter(_params("AccFilterParams", acc_lp_bias_sigma=0.0))
    dt, w = 0.01, np.array([0.3, -0.2, 0.5])
    dq = Q.from_rotvec(w * dt)
    q = Q.from_euler([0.2, -0.1, 0.4])
    still, burst = [], []
    for k in range(1000):
        if k:
            a.predict(dq)
            q = Q.normalize(Q.mul(q, dq))
        f_b = Q.rotate_inv(q, [0.0, 0.0, 9.81])
        extra = np.array([4.0, 0.0, 0.0]) if 500 <= k < 550 else np.zeros(3)
        s = a.screen(f_b + extra, dt, 0.0)
        (still if k < 500 else burst).append(np.linalg.norm(s.acc - f_b))
    assert max(still) < 1e-9  # gravity is constant in the gyro-carried frame
    assert 0.4 < max(burst) < 0.65  # 4 m/s^2 for 0.5 s, averaged over tau = 3 s


def test_acc_rejection_adaptive_noise_and_recovery():
    a = AccFilter(_params("AccFilterParams", acc_lp_tau=0.0, acc_reject=1.0, acc_adapt=2.0, acc_recovery_time=0.5))
    g, dt = a.p.gravity, 0.01
    s = a.screen([0.0, 0.0, -(g + 0.5)], dt, 0.0)
    assert not s.rejected and s.sigma_add == pytest.approx(2 * 0.5 / g) and s.gate(0.0, 16.0) == 16.0
    n = 0
    while (s := a.screen([0.0, 0.0, -(g + 3.0)], dt, 0.0)).rejected:
        a.finish("rejected", dt)
        n += 1
    assert abs(n - 50) <= 1 and s.recovering and s.gate(0.0, 16.0) == 0.0
    a.finish("ok", dt)
    assert a.acc_reject_t == 0.0
    b = AccFilter(_params("AccFilterParams"))  # acc_lp_tau 3 s, acc_lp_bias_sigma 0.006 rad/s
    assert b.time_constant(0.0) == 3.0 and b.time_constant(4 * 0.006**2) == pytest.approx(0.75)
    # acc_lp_dev 1 m/s^2: the shrink fades out with the low-passed linear acceleration
    assert b.time_constant_dev(4 * 0.006**2, 0.0) == pytest.approx(0.75)
    assert b.time_constant_dev(4 * 0.006**2, 0.5) == pytest.approx(1.875)
    assert b.time_constant_dev(4 * 0.006**2, 2.0) == 3.0


# ---------------------------------------------------------------------------- magnetometer part
def _field(dip):
    return np.array([np.cos(dip), 0.0, np.sin(dip)])


def test_mag_reference_learned_and_restored_when_not_used():
    m = MagDisturbance(_params("MagDisturbanceParams", mag_ref_samples=4, mag_ref_tau=0.0))
    m.start(_field(1.0), 50.0)
    before = m.ref.copy()
    c = m.screen(50.0, _field(1.04), 0.01)
    assert c.use and m.ref.mag_ref_count == 2
    m.finish(c, "rejected", lambda: _field(1.04), 0.01)  # the filter's gate refused it
    assert m.ref.mag_ref_count == 1 and np.array_equal(m.ref.mag_ref, before.mag_ref)
    r = MagRef()
    r.fix(0.5)
    r.learn(_field(1.0), 100)
    assert np.array_equal(r.mag_ref, _field(0.5))


def test_mag_disturbance_settling_recovery_and_learning():
    m = MagDisturbance(_params("MagDisturbanceParams", mag_ref_samples=1, mag_ref_tau=0.0, mag_settle_time=0.2,
                               mag_recovery_time=1.0))
    dip, dt = 1.0, 0.01
    m.start(_field(dip), 50.0)

    def step(norm, d):
        c = m.screen(norm, _field(d), dt)
        if c.use:
            m.finish(c, "ok", lambda: _field(d), dt)
        return c.use

    assert step(50.5, dip) and not step(56.0, dip) and not step(50.0, dip + 0.1)
    settle = 0
    while not step(50.0, dip):
        settle += 1
    assert abs(settle - 20) <= 1
    n = 0
    while not step(70.0, dip + 0.2):
        n += 1
    assert abs(n - 100) <= 1 and m.mag_norm_ref == 70.0
    assert np.arcsin(m.ref.mag_ref[2]) == pytest.approx(dip + 0.2)
    # mag_ref_tau: the reference norm and dip follow accepted samples.
    m = MagDisturbance(_params("MagDisturbanceParams", mag_ref_samples=1, mag_ref_tau=1.0, mag_norm_tol=0.0,
                               mag_dip_tol=0.0))
    m.start(_field(1.0), 50.0)
    for _ in range(100):
        c = m.screen(60.0, _field(1.1), dt)
        m.finish(c, "ok", lambda: _field(1.1), dt)
    a = 1 - (1 - dt / (1 + dt)) ** 100
    assert m.mag_norm_ref == pytest.approx(50 + 10 * a) and np.arcsin(m.ref.mag_ref[2]) == pytest.approx(1 + 0.1 * a)
