"""QuaternionEKF's declination: heading against true north, like the navigation filters."""
import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q
from quatnav import reference
from quatnav.demo import rotation_scenario

DECL = np.radians(-8.5)


@pytest.fixture(scope="module")
def rot():
    return rotation_scenario(n=4000, rate=100.0, seed=5)


def _yaw_turn(q, angle):
    """Rz(angle) * q: the same attitude seen from a frame turned by `angle` about down."""
    return Q.mul(Q.from_rotvec([0.0, 0.0, angle]), q)


@pytest.mark.parametrize("params", [{}, {"paper": True}, {"mag_heading_only": False}])
def test_declination_turns_the_whole_estimate_about_down(rot, params):
    """The filter is equivariant under a constant yaw of the navigation frame: with a
    declination d its estimate is Rz(d) times the magnetic-frame estimate, sample by sample;
    the bias and its sigma are the same."""
    d = rot
    r0 = quatnav.QuaternionEKF(**params).run(d.gyr, d.acc, d.mag, dt=d.dt)
    r1 = quatnav.QuaternionEKF(declination=DECL, **params).run(d.gyr, d.acc, d.mag, dt=d.dt)
    dq = np.max(np.abs(Q.canonical(r1.quat) - Q.canonical(_yaw_turn(r0.quat, DECL))))
    assert dq < 1e-9, dq
    np.testing.assert_allclose(r1.bias, r0.bias, atol=1e-10)
    np.testing.assert_allclose(r1.att_sigma, r0.att_sigma, rtol=1e-7, atol=1e-12)
    assert np.array_equal(r1.flags, r0.flags)


@pytest.mark.parametrize("heading_only", [True, False])
def test_cpp_matches_reference_with_declination(rot, heading_only):
    d = rot
    kw = dict(declination=DECL, mag_heading_only=heading_only)
    r_cpp = quatnav.QuaternionEKF(**kw).run(d.gyr, d.acc, d.mag, dt=d.dt)
    r_ref = reference.QuaternionEKF(**kw).run(d.gyr, d.acc, d.mag, dt=d.dt)
    dq = np.max(np.abs(Q.canonical(r_cpp.quat) - Q.canonical(r_ref.quat)))
    ds = np.max(np.abs(r_cpp.sigma - r_ref.sigma))
    assert dq < 1e-9 and ds < 1e-9, (dq, ds)


def test_joint_update_with_declination_matches_reference(rot):
    d = rot
    f = quatnav.QuaternionEKF(paper=True, declination=DECL)
    g = reference.QuaternionEKF(paper=True, declination=DECL)
    f.initialize(d.acc[0], d.mag[0])
    g.initialize(d.acc[0], d.mag[0])
    np.testing.assert_allclose(f.quat, g.q, atol=1e-14)
    for k in range(1, 400):
        f.predict(d.gyr[k], d.dt)
        g.predict(d.gyr[k], d.dt)
        a, b = f.update_acc_mag(d.acc[k], d.mag[k]), g.update_acc_mag(d.acc[k], d.mag[k])
        assert a.status == b.status == "ok"
        assert abs(a.nis - b.nis) < 1e-9
    np.testing.assert_allclose(f.covariance, g.P, atol=1e-12)
    np.testing.assert_allclose(f.quat, g.q, atol=1e-12)


def test_initialize_adds_the_declination_to_the_magnetic_heading(rot):
    d = rot
    f0, f1 = quatnav.QuaternionEKF(), quatnav.QuaternionEKF(declination=DECL)
    f0.initialize(d.acc[0], d.mag[0])
    f1.initialize(d.acc[0], d.mag[0])
    dyaw = Q.wrap_pi(Q.to_euler(f1.quat)[2] - Q.to_euler(f0.quat)[2])
    assert abs(dyaw - DECL) < 1e-12
    f2, f3 = quatnav.QuaternionEKF(declination=DECL), quatnav.QuaternionEKF()
    f2.initialize(d.acc[0])  # no magnetometer: no heading, nothing to add
    f3.initialize(d.acc[0])
    np.testing.assert_array_equal(f2.quat, f3.quat)


def test_reference_jacobian_of_the_turned_field_against_finite_differences():
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = Q.normalize(rng.standard_normal(4))
        rx, rz, ry = rng.standard_normal(3)
        H = reference.QuaternionEKF.H(q, rx, rz, ry)
        eps = 1e-7
        num = np.column_stack([(reference.QuaternionEKF.h(q + eps * e, rx, rz, ry)
                                - reference.QuaternionEKF.h(q - eps * e, rx, rz, ry)) / (2 * eps)
                               for e in np.eye(4)])
        np.testing.assert_allclose(H, num, atol=1e-7)
        # on the unit sphere the model is C_bn(q) r
        np.testing.assert_allclose(reference.QuaternionEKF.h(q, rx, rz, ry), Q.rotate_inv(q, [rx, ry, rz]),
                                   atol=1e-12)


def test_handheld_marg_nine_axis_heading_is_true_north_with_the_declination():
    """The simulated hand-held MARG run has a field with -8.5 deg declination: in 9D the yaw
    is a magnetic heading unless the filter is told the declination."""
    sim = pytest.importorskip("quatnav.sim")
    scn = sim.make_scenario("handheld_marg", seed=0, duration=30.0)
    dec = np.radians(scn.params["mag"]["declination_deg"])
    imu, mag = scn.imu, scn.mag
    m = np.full_like(imu.gyro, np.nan)
    m[np.searchsorted(imu.t, mag.t)] = mag.mag
    q_true = scn.truth.q_nb[imu.index]
    late = imu.t >= imu.t[0] + 10.0

    def yaw_rmse(**kw):
        r = quatnav.QuaternionEKF(**kw).run(imu.gyro, imu.accel, m, t=imu.t)
        e = Q.wrap_pi(Q.to_euler(r.quat)[:, 2] - Q.to_euler(q_true)[:, 2])
        return np.degrees(np.sqrt(np.mean(e[late] ** 2)))

    magnetic, true_north = yaw_rmse(), yaw_rmse(declination=dec)
    assert magnetic > 6.0          # off by about the declination
    assert true_north < 3.0, true_north
    assert true_north < magnetic / 3


@pytest.mark.parametrize("value", [8.5, -181.0, np.inf, np.nan])
def test_declination_in_degrees_or_not_finite_is_refused(value):
    with pytest.raises(ValueError, match="declination"):
        quatnav.QuaternionEKF(declination=value)
    with pytest.raises(TypeError, match="declination"):
        quatnav.QuaternionEKF(declination="8.5")


def test_declination_hint_names_np_radians():
    with pytest.raises(ValueError, match=r"np\.radians"):
        quatnav.QuaternionEKF(declination=8.5)
