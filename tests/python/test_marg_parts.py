"""MargFilter composes the robustness parts (parts/*.hpp; marg_filter.hpp): C++ against its numpy
twin step by step with the parts on, paper=True the plain filter of paper 001, and each part's
effect on simulated data (at rest the low-passed gyro becomes the bias, a magnetic disturbance is
flagged and leaves the heading alone, a linear-acceleration burst is rejected)."""
import numpy as np
import pytest

import quatnav
from quatnav import reference

from test_euler_parts import EXTRA_BITS, PARTS_OFF, _scenario
from test_qekf_robust import heading_err_deg, simulate, tilt_err_deg, wobble

ROBUST = dict(acc_lp_tau=1.0, acc_adapt=5.0, acc_reject=1.0, acc_recovery_time=0.5, mag_norm_tol=0.1,
              mag_dip_tol=0.1, mag_settle_time=0.2, mag_ref_tau=2.0, mag_recovery_time=1.0, gravity=9.81)


@pytest.mark.parametrize("kw", [dict(), ROBUST, dict(ROBUST, acc_lp_tau=0.0), dict(bias_gain=0.05), dict(paper=True)],
                         ids=["defaults", "robust", "robust-no-lp", "bias-gain", "paper"])
def test_cpp_matches_twin_step_by_step_with_the_parts(kw):
    quat, gyr, acc, mag, dt = _scenario()
    c = quatnav.MargFilter(**kw).run(gyr, acc, mag, dt=dt)
    r = reference.MargFilter(**kw).run(gyr, acc, mag, dt=dt)
    np.testing.assert_allclose(c.quat, r.quat, atol=1e-9)
    np.testing.assert_allclose(c.bias, r.bias, atol=1e-9)
    np.testing.assert_array_equal(c.flags & EXTRA_BITS, r.flags & EXTRA_BITS)
    if kw is ROBUST or kw.get("acc_lp_tau") == 0.0:
        assert c.flag("at_rest").any() and c.flag("mag_rejected").any()  # the scenario exercises the parts
    if kw.get("acc_lp_tau") == 0.0:
        assert c.flag("acc_rejected").any()
    if kw.get("paper"):
        assert not (c.flags & EXTRA_BITS).any()


def test_paper_switches_every_part_off():
    quat, gyr, acc, mag, dt = _scenario()
    p = quatnav.MargFilter(paper=True).params
    assert all(p[k] == v for k, v in PARTS_OFF.items())
    assert p["gravity"] == 9.80665  # the g of eq. (7) either way
    a = quatnav.MargFilter(paper=True).run(gyr, acc, mag, dt=dt)
    b = quatnav.MargFilter(**PARTS_OFF).run(gyr, acc, mag, dt=dt)
    np.testing.assert_array_equal(a.quat, b.quat)


def test_at_rest_the_low_passed_gyro_is_the_bias():
    bias = (0.01, -0.02, 0.015)
    quat, gyr, acc, mag, dt = simulate(n=1500, bias=bias, seed=5)
    off = quatnav.MargFilter(paper=True).run(gyr, acc, mag, dt=dt)
    on = quatnav.MargFilter().run(gyr, acc, mag, dt=dt)
    assert on.flag("at_rest")[300:].all() and not on.flag("at_rest")[:100].any()
    assert not off.flag("at_rest").any()
    np.testing.assert_array_equal(off.bias, 0.0)  # bias_gain 0: the plain filter has no bias estimate
    assert np.abs(on.bias[-1] - bias).max() < 1e-3
    # With the bias taken, the heading no longer drifts with the z bias (0.015 rad/s).
    assert np.abs(heading_err_deg(on.quat, quat)[-500:]).max() < 0.5 * np.abs(heading_err_deg(off.quat, quat)[-500:]).max()


def test_magnetic_disturbance_is_flagged_and_does_not_turn_the_heading():
    dist = lambda k: np.array([25.0, -20.0, 10.0]) if 1000 <= k < 1600 else np.zeros(3)
    quat, gyr, acc, mag, dt = simulate(n=2000, rot_rate=wobble, mag_dist=dist, seed=2)
    win = slice(1000, 1700)
    plain = quatnav.MargFilter(paper=True).run(gyr, acc, mag, dt=dt)
    rob = quatnav.MargFilter().run(gyr, acc, mag, dt=dt)
    assert rob.flag("mag_rejected")[1000:1600].mean() > 0.9
    assert rob.flag("mag_rejected")[300:900].mean() < 0.05
    h_plain = np.sqrt(np.mean(heading_err_deg(plain.quat, quat)[win] ** 2))
    h_rob = np.sqrt(np.mean(heading_err_deg(rob.quat, quat)[win] ** 2))
    assert h_rob < 0.3 * h_plain
    assert h_rob < 3.0


def test_linear_acceleration_burst_is_rejected():
    burst = lambda k: np.array([6.0 * np.sign(np.sin(0.05 * k + 0.1)), 0.0, 0.0]) if 1000 <= k < 1600 else np.zeros(3)
    quat, gyr, acc, mag, dt = simulate(n=2000, rot_rate=wobble, lin_acc=burst)
    win = slice(1000, 1700)
    plain = quatnav.MargFilter(paper=True).run(gyr, acc, mag, dt=dt)
    rej = quatnav.MargFilter(paper=True, acc_reject=1.0, gravity=9.81).run(gyr, acc, mag, dt=dt)
    lp = quatnav.MargFilter().run(gyr, acc, mag, dt=dt)  # the default low-pass
    e = {k: np.sqrt(np.mean(tilt_err_deg(r.quat, quat)[win] ** 2)) for k, r in (("plain", plain), ("rej", rej), ("lp", lp))}
    assert rej.flag("acc_rejected")[1000:1600].mean() > 0.9
    assert not rej.flag("acc_rejected")[200:900].any()
    assert e["rej"] < 0.5 * e["plain"]
    assert e["lp"] < 0.5 * e["plain"]


def test_split_run_and_float32_with_the_parts():
    quat, gyr, acc, mag, dt = simulate(n=1500, rot_rate=lambda k: np.zeros(3) if k < 300 else wobble(k), seed=9)
    full = quatnav.MargFilter(**ROBUST).run(gyr, acc, mag, dt=dt)
    a = quatnav.MargFilter(**ROBUST)
    a.run(gyr[:350], acc[:350], mag[:350], dt=dt)
    b = quatnav.MargFilter(**ROBUST)
    b.set_state(a.get_state())
    second = b.run(gyr[350:], acc[350:], mag[350:], dt=dt)
    np.testing.assert_array_equal(second.quat, full.quat[350:])
    np.testing.assert_array_equal(second.flags, full.flags[350:])
    r64 = quatnav.MargFilter().run(gyr, acc, mag, dt=dt)
    r32 = quatnav.MargFilter(dtype=np.float32).run(gyr, acc, mag, dt=dt)
    m = quatnav.evaluation.metrics
    assert np.degrees(m.total_error(m.error_quat(r32.quat, r64.quat))).max() < 0.05
