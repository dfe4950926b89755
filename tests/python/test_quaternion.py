"""quatnav.core.quaternion (numpy) and the C++ helpers against scipy's Rotation."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from quatnav import _core
from quatnav.core import quaternion as Q

rng = np.random.default_rng(7)
QS = Q.normalize(rng.standard_normal((50, 4)))


def test_scipy_conversion_round_trip_and_order():
    q = np.array([0.9, 0.1, -0.2, 0.3])
    q /= np.linalg.norm(q)
    xyzw = Q.to_scipy(q)
    assert xyzw[3] == q[0]
    np.testing.assert_allclose(Q.from_scipy(xyzw), q)
    np.testing.assert_allclose(Rotation.from_quat(Q.to_scipy(QS)).as_matrix(), Q.to_rotmat(QS), atol=1e-14)


@pytest.mark.parametrize("impl", ["numpy", "cpp"])
def test_against_scipy(impl):
    for q in QS:
        r = Rotation.from_quat(Q.to_scipy(q))
        v = rng.standard_normal(3)
        if impl == "numpy":
            rot, mat, eul, rv = Q.rotate(q, v), Q.to_rotmat(q), Q.to_euler(q), Q.to_rotvec(q)
            back = Q.from_rotmat(mat)
        else:
            rot, mat, eul, rv = _core.quat.rotate(q, v), _core.quat.to_rotmat(q), _core.quat.to_euler(q), _core.quat.to_rotvec(q)
            back = _core.quat.from_rotmat(mat)
        np.testing.assert_allclose(rot, r.apply(v), atol=1e-13)
        np.testing.assert_allclose(mat, r.as_matrix(), atol=1e-14)
        # scipy's intrinsic "ZYX" gives [yaw, pitch, roll].
        np.testing.assert_allclose(eul, r.as_euler("ZYX")[::-1], atol=1e-10)
        np.testing.assert_allclose(Q.canonical(back), Q.canonical(q), atol=1e-12)
        np.testing.assert_allclose(rv, r.as_rotvec(), atol=1e-12)


def test_product_and_exp_against_scipy():
    for a, b in zip(QS[:-1], QS[1:]):
        ab = (Rotation.from_quat(Q.to_scipy(a)) * Rotation.from_quat(Q.to_scipy(b))).as_quat()
        np.testing.assert_allclose(Q.canonical(Q.mul(a, b)), Q.canonical(Q.from_scipy(ab)), atol=1e-14)
        np.testing.assert_allclose(_core.quat.mul(a, b), Q.mul(a, b), atol=1e-15)
    for rv in [np.zeros(3), np.array([1e-9, 0, 0]), np.array([0.3, -1.0, 2.0])]:
        expect = Q.from_scipy(Rotation.from_rotvec(rv).as_quat())
        np.testing.assert_allclose(Q.canonical(Q.from_rotvec(rv)), Q.canonical(expect), atol=1e-14)
        np.testing.assert_allclose(_core.quat.from_rotvec(rv), Q.from_rotvec(rv), atol=1e-15)
        np.testing.assert_allclose(_core.quat.from_rotvec_jacobian(rv), Q.from_rotvec_jacobian(rv), atol=1e-15)


def test_from_euler_inverse_of_to_euler():
    rpy = np.column_stack([rng.uniform(-3, 3, 30), rng.uniform(-1.5, 1.5, 30), rng.uniform(-3, 3, 30)])
    np.testing.assert_allclose(Q.to_euler(Q.from_euler(rpy)), rpy, atol=1e-12)
    for e in rpy[:5]:
        np.testing.assert_allclose(_core.quat.from_euler(*e), Q.from_euler(e), atol=1e-15)


def test_enu_ned_helper():
    # A body whose x axis points east, y north, z up: q_enu_b = identity.
    q_ned = Q.enu_to_ned(Q.identity())
    np.testing.assert_allclose(Q.rotate(q_ned, [1, 0, 0]), [0, 1, 0], atol=1e-15)  # east in NED
    np.testing.assert_allclose(Q.rotate(q_ned, [0, 0, 1]), [0, 0, -1], atol=1e-15)  # up in NED
    np.testing.assert_allclose(Q.ned_to_enu(q_ned), Q.identity(), atol=1e-15)
    np.testing.assert_allclose(_core.quat.enu_to_ned(QS[0]), Q.enu_to_ned(QS[0]), atol=1e-15)
    # Heading: a body facing north (ENU yaw 90 deg) has NED yaw 0.
    q_enu = Q.from_euler([0, 0, np.pi / 2])
    v_b = np.array([1.0, 0, 0])
    np.testing.assert_allclose(Q.rotate(Q.enu_to_ned(q_enu), v_b), [1, 0, 0], atol=1e-12)


def test_wrap_pi():
    a = np.array([-np.pi, np.pi, 3 * np.pi, -0.5, 7.0])
    w = Q.wrap_pi(a)
    assert np.all(w > -np.pi) and np.all(w <= np.pi)
    np.testing.assert_allclose(np.cos(w), np.cos(a), atol=1e-12)
    assert _core.quat.wrap_pi(-np.pi) == pytest.approx(np.pi)
