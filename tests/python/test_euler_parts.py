"""EulerEKF composes the robustness parts as QuaternionEKF does (parts/*.hpp): C++ against its
numpy twin step by step with the parts on, paper=True the plain baseline, and each part's effect
on simulated data (rest learns the gyro bias, a magnetic disturbance is flagged and does not turn
the heading, a linear-acceleration burst is rejected)."""
import numpy as np
import pytest

import quatnav
from quatnav import reference

from test_qekf_robust import heading_err_deg, simulate, tilt_err_deg, wobble

PARTS_OFF = dict(acc_adapt=0.0, acc_reject=0.0, acc_recovery_time=0.0, acc_lp_tau=0.0, acc_lp_bias_sigma=0.0,
                 mag_norm_tol=0.0, mag_dip_tol=0.0, mag_settle_time=0.0, mag_ref_tau=0.0, mag_recovery_time=0.0,
                 rest_detection=False)
ROBUST = dict(acc_lp_tau=1.0, acc_adapt=5.0, acc_reject=1.0, acc_recovery_time=0.5, mag_norm_tol=0.1,
              mag_dip_tol=0.1, mag_settle_time=0.2, mag_ref_tau=2.0, mag_recovery_time=1.0, gyro_noise=0.002)
EXTRA_BITS = quatnav.FLAGS["acc_rejected"] | quatnav.FLAGS["mag_rejected"] | quatnav.FLAGS["at_rest"]


def _scenario():
    burst = lambda k: np.array([5.0, 0.0, 0.0]) if 250 <= k < 300 else np.zeros(3)
    dist = lambda k: np.array([30.0, 0.0, 0.0]) if 320 <= k < 420 else np.zeros(3)
    rot = lambda k: np.zeros(3) if k < 230 else wobble(k)
    return simulate(n=500, rot_rate=rot, lin_acc=burst, mag_dist=dist, seed=7, bias=(0.01, 0, -0.01))


@pytest.mark.parametrize("kw", [dict(), ROBUST, dict(ROBUST, acc_lp_tau=0.0), dict(paper=True)],
                         ids=["defaults", "robust", "robust-no-lp", "paper"])
def test_cpp_matches_twin_step_by_step_with_the_parts(kw):
    quat, gyr, acc, mag, dt = _scenario()
    c = quatnav.EulerEKF(**kw).run(gyr, acc, mag, dt=dt)
    r = reference.EulerEKF(**kw).run(gyr, acc, mag, dt=dt)
    np.testing.assert_allclose(c.quat, r.quat, atol=1e-9)
    np.testing.assert_allclose(c.bias, r.bias, atol=1e-9)
    np.testing.assert_allclose(c.sigma, r.sigma, atol=1e-9)
    np.testing.assert_array_equal(c.flags & EXTRA_BITS, r.flags & EXTRA_BITS)
    if kw is ROBUST or kw.get("acc_lp_tau") == 0.0:
        assert c.flag("at_rest").any() and c.flag("mag_rejected").any()  # the scenario exercises the parts
    if kw.get("acc_lp_tau") == 0.0:
        assert c.flag("acc_rejected").any()
    if kw.get("paper"):
        assert not (c.flags & EXTRA_BITS).any()


def test_cpp_matches_twin_with_the_widened_dip_test():
    """mag_dip_sigmas (the dip test's tolerance widened by the filter's own dip sigma, from
    attitude_covariance()): C++ against the twin step by step, on a dip disturbance near the
    widened tolerance, so that the rejections differ from the fixed tolerance's."""
    from quatnav.core import quaternion as Q
    burst = lambda k: np.array([5.0, 0.0, 0.0]) if 250 <= k < 300 else np.zeros(3)
    rot = lambda k: np.zeros(3) if k < 230 else wobble(k)
    quat, gyr, acc, mag, dt = simulate(n=500, rot_rate=rot, lin_acc=burst, seed=7, bias=(0.01, 0, -0.01))
    ry = Q.from_rotvec(np.array([0.0, DIP_OFF, 0.0]))
    for k in range(320, 420):
        mag[k] = Q.rotate_inv(quat[k], Q.rotate(ry, Q.rotate(quat[k], mag[k])))
    kw = dict(mag_dip_tol=0.05, mag_dip_sigmas=3.0, acc_sigma=0.4)  # a tilt sigma of 0.6-2.4 deg
    c = quatnav.EulerEKF(**kw).run(gyr, acc, mag, dt=dt)
    r = reference.EulerEKF(**kw).run(gyr, acc, mag, dt=dt)
    np.testing.assert_allclose(c.quat, r.quat, atol=1e-9)
    np.testing.assert_allclose(c.sigma, r.sigma, atol=1e-9)
    np.testing.assert_array_equal(c.flags & EXTRA_BITS, r.flags & EXTRA_BITS)
    fixed = quatnav.EulerEKF(**dict(kw, mag_dip_sigmas=0.0)).run(gyr, acc, mag, dt=dt)
    assert (c.flag("mag_rejected") != fixed.flag("mag_rejected")).sum() > 10


DIP_OFF = 0.06  # rad: 100 samples rejected with the fixed tolerance, 78 widened


def test_paper_switches_every_part_off():
    quat, gyr, acc, mag, dt = _scenario()
    p = quatnav.EulerEKF(paper=True).params
    # and the paper's optimal gain of the accelerometer and its one Euler step per sample
    off = dict(PARTS_OFF, acc_tilt_only=False, exact_propagation=False)
    assert all(p[k] == v for k, v in off.items())
    assert p["gyro_noise"] == 0.005 and p["acc_sigma"] == 0.05  # the paper's noise values either way
    a = quatnav.EulerEKF(paper=True).run(gyr, acc, mag, dt=dt)
    b = quatnav.EulerEKF(**off).run(gyr, acc, mag, dt=dt)
    np.testing.assert_array_equal(a.quat, b.quat)
    np.testing.assert_array_equal(a.sigma, b.sigma)


def test_rest_learns_the_gyro_bias():
    bias = (0.01, -0.02, 0.015)
    quat, gyr, acc, mag, dt = simulate(n=3000, bias=bias, seed=5)
    off = quatnav.EulerEKF(paper=True).run(gyr, acc, None, dt=dt)
    on = quatnav.EulerEKF(paper=True, rest_detection=True).run(gyr, acc, None, dt=dt)
    dflt = quatnav.EulerEKF().run(gyr, acc, None, dt=dt)
    assert on.flag("at_rest")[500:].all() and dflt.flag("at_rest")[500:].all()
    assert not on.flag("at_rest")[:100].any() and not off.flag("at_rest").any()
    # Without a magnetometer the z bias is only observable at rest.
    assert on.sigma[-1, 5] < 0.2 * off.sigma[-1, 5]
    for r in (on, dflt):
        assert abs(r.bias[-1, 2] - bias[2]) < 3 * r.sigma[-1, 5] + 1e-4
        assert abs(r.bias[-1, 2] - bias[2]) < 0.3 * abs(off.bias[-1, 2] - bias[2])
    f = quatnav.EulerEKF()
    f.run(gyr, acc, None, dt=dt)
    assert f.at_rest


def test_magnetic_disturbance_is_flagged_and_does_not_turn_the_heading():
    dist = lambda k: np.array([25.0, -20.0, 10.0]) if 1000 <= k < 1600 else np.zeros(3)
    quat, gyr, acc, mag, dt = simulate(n=2000, rot_rate=wobble, mag_dist=dist, seed=2)
    win = slice(1000, 1700)
    plain = quatnav.EulerEKF(paper=True, gyro_noise=0.002).run(gyr, acc, mag, dt=dt)
    rob = quatnav.EulerEKF(gyro_noise=0.002).run(gyr, acc, mag, dt=dt)  # the defaults' tolerances
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
    plain = quatnav.EulerEKF(paper=True).run(gyr, acc, mag, dt=dt)
    rej = quatnav.EulerEKF(paper=True, acc_reject=1.0).run(gyr, acc, mag, dt=dt)
    lp = quatnav.EulerEKF().run(gyr, acc, mag, dt=dt)  # the default low-pass
    e = {k: np.sqrt(np.mean(tilt_err_deg(r.quat, quat)[win] ** 2)) for k, r in (("plain", plain), ("rej", rej), ("lp", lp))}
    assert rej.flag("acc_rejected")[1000:1600].mean() > 0.9
    assert not rej.flag("acc_rejected")[200:900].any()
    assert e["rej"] < 0.5 * e["plain"]
    assert e["lp"] < 0.5 * e["plain"]


def test_split_run_and_float32_with_the_parts():
    quat, gyr, acc, mag, dt = simulate(n=1500, rot_rate=lambda k: np.zeros(3) if k < 300 else wobble(k), seed=9)
    full = quatnav.EulerEKF(**ROBUST).run(gyr, acc, mag, dt=dt)
    a = quatnav.EulerEKF(**ROBUST)
    a.run(gyr[:350], acc[:350], mag[:350], dt=dt)
    b = quatnav.EulerEKF(**ROBUST)
    b.set_state(a.get_state())
    second = b.run(gyr[350:], acc[350:], mag[350:], dt=dt)
    np.testing.assert_array_equal(second.quat, full.quat[350:])
    np.testing.assert_array_equal(second.flags, full.flags[350:])
    r64 = quatnav.EulerEKF().run(gyr, acc, mag, dt=dt)
    r32 = quatnav.EulerEKF(dtype=np.float32).run(gyr, acc, mag, dt=dt)
    m = quatnav.evaluation.metrics
    assert np.degrees(m.total_error(m.error_quat(r32.quat, r64.quat))).max() < 0.05
