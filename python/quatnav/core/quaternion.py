"""Quaternion and rotation helpers (numpy, vectorized over leading axes).

Conventions used everywhere in quatnav (the same text is in README.md and
``cpp/include/quatnav/core/types.hpp``):

* Quaternions are Hamilton, scalar first: ``q = [w, x, y, z]``.
* ``q_nb`` rotates body-frame vectors into the navigation frame:
  ``v_n = q_nb * v_b * conj(q_nb) = C_nb @ v_b``.
* The navigation frame is NED (north, east, down) unless a function says otherwise;
  the body frame is forward-right-down.
* SI units and radians. Euler angles are ZYX: ``C_nb = Rz(yaw) Ry(pitch) Rx(roll)``,
  returned as ``[roll, pitch, yaw]``.

scipy's ``Rotation.as_quat()`` is scalar *last*; use :func:`to_scipy` /
:func:`from_scipy` to convert.
"""
from __future__ import annotations

import numpy as np

__all__ = [
    "identity", "mul", "conj", "normalize", "canonical", "rotate", "rotate_inv",
    "to_rotmat", "from_rotmat", "to_euler", "from_euler", "from_rotvec", "to_rotvec",
    "from_rotvec_jacobian", "skew", "left", "right", "omega", "xi", "angle_between",
    "enu_to_ned", "ned_to_enu", "Q_NED_ENU", "wrap_pi", "to_scipy", "from_scipy",
]


def identity(n: int | None = None) -> np.ndarray:
    """``[1, 0, 0, 0]``, or ``n`` of them stacked as (n, 4)."""
    q = np.zeros(4 if n is None else (n, 4))
    q[..., 0] = 1.0
    return q


def mul(p, q) -> np.ndarray:
    """Hamilton product ``p * q`` (broadcasting over leading axes)."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack([
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ], axis=-1)


def conj(q) -> np.ndarray:
    q = np.array(q, dtype=float)
    q[..., 1:] *= -1.0
    return q


def normalize(q) -> np.ndarray:
    q = np.asarray(q, dtype=float)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def canonical(q) -> np.ndarray:
    """The same rotation with ``w >= 0``."""
    q = np.asarray(q, dtype=float)
    return np.where(q[..., :1] < 0, -q, q)


def skew(v) -> np.ndarray:
    """``skew(a) @ b == cross(a, b)``."""
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    return np.stack([
        np.stack([z, -v[..., 2], v[..., 1]], -1),
        np.stack([v[..., 2], z, -v[..., 0]], -1),
        np.stack([-v[..., 1], v[..., 0], z], -1),
    ], -2)


def left(p) -> np.ndarray:
    """``p * q == left(p) @ q``."""
    w, x, y, z = np.asarray(p, dtype=float)
    return np.array([[w, -x, -y, -z], [x, w, -z, y], [y, z, w, -x], [z, -y, x, w]])


def right(q) -> np.ndarray:
    """``p * q == right(q) @ p``."""
    w, x, y, z = np.asarray(q, dtype=float)
    return np.array([[w, -x, -y, -z], [x, w, z, -y], [y, -z, w, x], [z, y, -x, w]])


def omega(w) -> np.ndarray:
    """Omega(w) of paper 000 eq. (5): ``q * [0, w] == omega(w) @ q``."""
    return right(np.concatenate([[0.0], np.asarray(w, dtype=float)]))


def xi(q) -> np.ndarray:
    """4x3 matrix with ``q * [0, v] == xi(q) @ v``."""
    return left(q)[:, 1:]


def to_rotmat(q) -> np.ndarray:
    """``C_nb`` (..., 3, 3) of ``q_nb`` (exact for unit quaternions)."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def from_rotmat(c) -> np.ndarray:
    """Unit quaternion (w >= 0) of rotation matrices (..., 3, 3) (Shepperd's method)."""
    c = np.asarray(c, dtype=float)
    flat = c.reshape(-1, 3, 3)
    out = np.empty((flat.shape[0], 4))
    for i, m in enumerate(flat):
        tr = np.trace(m)
        if tr > m[0, 0] and tr > m[1, 1] and tr > m[2, 2]:
            s = np.sqrt(1.0 + tr) * 2
            q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
        elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
            s = np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2]) * 2
            q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
        elif m[1, 1] > m[2, 2]:
            s = np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2]) * 2
            q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
        else:
            s = np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1]) * 2
            q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
        out[i] = q
    out = canonical(normalize(out))
    return out.reshape(c.shape[:-2] + (4,))


def rotate(q, v) -> np.ndarray:
    """``v_n = C_nb v_b`` for ``q = q_nb`` (broadcasting)."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    u = q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + q[..., :1] * t + np.cross(u, t)


def rotate_inv(q, v) -> np.ndarray:
    """``v_b = C_nb^T v_n``."""
    return rotate(conj(q), v)


def to_euler(q) -> np.ndarray:
    """ZYX Euler angles ``[roll, pitch, yaw]`` (rad) of ``q_nb``."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = np.moveaxis(q, -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - x * z), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yaw], -1)


def from_euler(rpy) -> np.ndarray:
    """``q_nb`` of ZYX Euler angles ``[roll, pitch, yaw]`` (..., 3), rad."""
    rpy = np.asarray(rpy, dtype=float)
    cr, sr = np.cos(rpy[..., 0] / 2), np.sin(rpy[..., 0] / 2)
    cp, sp = np.cos(rpy[..., 1] / 2), np.sin(rpy[..., 1] / 2)
    cy, sy = np.cos(rpy[..., 2] / 2), np.sin(rpy[..., 2] / 2)
    return np.stack([
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ], -1)


def from_rotvec(r) -> np.ndarray:
    """Exponential map: unit quaternion of rotation vectors (..., 3), rad."""
    r = np.asarray(r, dtype=float)
    a = np.linalg.norm(r, axis=-1, keepdims=True)
    h2 = (a / 2) ** 2
    small = h2 < np.sqrt(np.finfo(float).eps)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.where(small, 1 - h2 / 2 + h2 * h2 / 24, np.cos(a / 2))
        s = np.where(small, 0.5 * (1 - h2 / 6 + h2 * h2 / 120), np.sin(a / 2) / np.where(a > 0, a, 1.0))
    return np.concatenate([c, s * r], axis=-1)


def from_rotvec_jacobian(r) -> np.ndarray:
    """4x3 Jacobian of :func:`from_rotvec` at one rotation vector."""
    r = np.asarray(r, dtype=float)
    a2 = r @ r
    h2 = a2 / 4
    if h2 < np.cbrt(np.finfo(float).eps):
        s = 0.5 * (1 - h2 / 6 + h2 * h2 / 120)
        ds = -1.0 / 24 + a2 / 960
        c_over = -0.5 * s
    else:
        a = np.sqrt(a2)
        s = np.sin(a / 2) / a
        ds = (a / 2 * np.cos(a / 2) - np.sin(a / 2)) / (a2 * a)
        c_over = -np.sin(a / 2) / (2 * a)
    j = np.empty((4, 3))
    j[0] = c_over * r
    j[1:] = s * np.eye(3) + ds * np.outer(r, r)
    return j


def to_rotvec(q) -> np.ndarray:
    """Logarithm map: rotation vectors (angle in [0, pi]) of unit quaternions."""
    q = canonical(q)
    v = q[..., 1:]
    sn = np.linalg.norm(v, axis=-1, keepdims=True)
    w = q[..., :1]
    small = sn < np.sqrt(np.finfo(float).eps)
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(small, (2 / w) * (1 - sn**2 / (3 * w * w)), 2 * np.arctan2(sn, w) / np.where(small, 1.0, sn))
    return k * v


def angle_between(a, b) -> np.ndarray:
    """Rotation angle (rad, in [0, pi]) between attitudes ``a`` and ``b``."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    d = np.abs(np.sum(a * b, axis=-1)) / (np.linalg.norm(a, axis=-1) * np.linalg.norm(b, axis=-1))
    return 2 * np.arccos(np.clip(d, 0.0, 1.0))


#: ``q_{NED<-ENU}``: rotates ENU-frame vectors into NED (x_n = y_e, y_n = x_e, z_n = -z_e).
Q_NED_ENU = np.array([0.0, np.sqrt(0.5), np.sqrt(0.5), 0.0])


def enu_to_ned(q_enu_b) -> np.ndarray:
    """Attitude w.r.t. NED from attitude w.r.t. ENU (same body frame), ``q_ned_b = q_ned_enu * q_enu_b``."""
    return mul(Q_NED_ENU, q_enu_b)


def ned_to_enu(q_ned_b) -> np.ndarray:
    """Attitude w.r.t. ENU from attitude w.r.t. NED (same body frame)."""
    return mul(conj(Q_NED_ENU), q_ned_b)


def wrap_pi(a):
    """Wrap angles to (-pi, pi]."""
    a = np.asarray(a, dtype=float)
    r = np.mod(a + np.pi, 2 * np.pi)
    r = np.where(r <= 0, r + 2 * np.pi, r)
    return r - np.pi


def to_scipy(q) -> np.ndarray:
    """quatnav ``[w, x, y, z]`` to scipy's scalar-last ``[x, y, z, w]``."""
    q = np.asarray(q, dtype=float)
    return np.concatenate([q[..., 1:], q[..., :1]], axis=-1)


def from_scipy(q_xyzw) -> np.ndarray:
    """scipy's scalar-last ``[x, y, z, w]`` to quatnav ``[w, x, y, z]``."""
    q = np.asarray(q_xyzw, dtype=float)
    return np.concatenate([q[..., 3:], q[..., :3]], axis=-1)
