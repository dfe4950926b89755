"""Vectorized quaternion helpers used by the simulator (Hamilton, [w, x, y, z], q_nb body-to-NED).

Arrays have shape (..., 4) for quaternions and (..., 3) for vectors.
"""

from __future__ import annotations

import numpy as np


def mul(p, q):
    """Hamilton product p * q."""
    p = np.asarray(p, float)
    q = np.asarray(q, float)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack([
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ], axis=-1)


def conj(q):
    q = np.asarray(q, float)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def from_rotvec(r):
    """Unit quaternion of a rotation vector (rad)."""
    r = np.asarray(r, float)
    ang = np.linalg.norm(r, axis=-1)
    half = 0.5 * ang
    small = ang < 1e-8
    k = np.where(small, 0.5 - ang**2 / 48.0, np.sin(half) / np.where(small, 1.0, ang))
    return np.concatenate([np.cos(half)[..., None], k[..., None] * r], axis=-1)


def to_rotmat(q):
    """C_nb of q_nb, shape (..., 3, 3)."""
    q = np.asarray(q, float)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([w*w + x*x - y*y - z*z, 2 * (x*y - w*z), 2 * (x*z + w*y)], -1),
        np.stack([2 * (x*y + w*z), w*w - x*x + y*y - z*z, 2 * (y*z - w*x)], -1),
        np.stack([2 * (x*z - w*y), 2 * (y*z + w*x), w*w - x*x - y*y + z*z], -1),
    ], -2)


def rotate(q, v):
    """v_n = C_nb v_b."""
    return np.einsum("...ij,...j->...i", to_rotmat(q), v)


def rotate_inv(q, v):
    """v_b = C_nb^T v_n."""
    return np.einsum("...ji,...j->...i", to_rotmat(q), v)


def from_euler(roll, pitch, yaw):
    """q_nb of ZYX Euler angles (rad): C_nb = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = np.cos(0.5 * np.asarray(roll)), np.sin(0.5 * np.asarray(roll))
    cp, sp = np.cos(0.5 * np.asarray(pitch)), np.sin(0.5 * np.asarray(pitch))
    cy, sy = np.cos(0.5 * np.asarray(yaw)), np.sin(0.5 * np.asarray(yaw))
    return np.stack([
        cy * cp * cr + sy * sp * sr,
        cy * cp * sr - sy * sp * cr,
        cy * sp * cr + sy * cp * sr,
        sy * cp * cr - cy * sp * sr,
    ], axis=-1)


def to_euler(q):
    """[roll, pitch, yaw] (rad) of q_nb, shape (..., 3)."""
    q = np.asarray(q, float)
    w, x, y, z = np.moveaxis(q, -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), w*w - x*x - y*y + z*z)
    pitch = np.arcsin(np.clip(2 * (w * y - x * z), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), w*w + x*x - y*y - z*z)
    return np.stack([roll, pitch, yaw], axis=-1)


def angle_between(a, b):
    """Rotation angle (rad) between attitudes a and b."""
    d = mul(conj(a), b)
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))
