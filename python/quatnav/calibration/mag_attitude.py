"""The magnetometer against a known attitude: its hard-iron offset and the Earth field together.

Given the attitude ``q_nb`` at each magnetometer sample (from a GNSS/INS run without the
magnetometer, whose heading comes from the GNSS), every sample is

    m_k = C_nb(q_k)^T m_n + b,

linear in the six unknowns: the field in the navigation frame ``m_n`` (NED, hence the declination
``atan2(m_E, m_N)`` and the inclination) and the offset ``b`` (body axes). The least-squares
solution needs the attitude to turn: a vehicle that only yaws separates the horizontal offset
from the field, but not the vertical one from the field's down component, so a weak prior holds
the offset at zero along the directions the data leave open (a ridge of ``prior`` times the
number of samples, in units of the field). A second pass drops the samples more than three RMS
from the fit (a magnetometer disturbed for a while) and solves again.

Unlike a sphere fit of the samples alone (:func:`quatnav.calibration.magnetometer`), which needs
rotations about every axis, this works on a drive: the heading the GNSS gives is the reference.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..core import quaternion as Q

__all__ = ["MagAttitudeFit", "mag_attitude_fit"]


@dataclass
class MagAttitudeFit:
    """Result of :func:`mag_attitude_fit`, in the magnetometer's unit.

    ``offset`` (3,): the hard-iron offset in the body axes (subtract it); ``field_n`` (3,): the
    Earth field, NED; ``declination``, ``inclination`` (rad; east of true north, down positive);
    ``offset_sigma`` (3,): the offset's one-sigma from the residuals; ``residual_rms``; ``samples``
    used (after dropping outliers) of ``given``."""

    offset: np.ndarray
    field_n: np.ndarray
    declination: float
    inclination: float
    offset_sigma: np.ndarray
    residual_rms: float
    samples: int
    given: int


def _solve(C: np.ndarray, y: np.ndarray, prior: float):
    """Least squares of y_k = C_k^T m + b over the rows (C: (N, 3, 3) C_nb, y: (N, 3) scaled)."""
    n = len(y)
    S = C.sum(axis=0)  # sum C_k
    ata = np.zeros((6, 6))
    ata[:3, :3] = n * np.eye(3)  # sum C_k C_k^T
    ata[:3, 3:] = S
    ata[3:, :3] = S.T
    ata[3:, 3:] = n * (1.0 + prior) * np.eye(3)
    aty = np.concatenate([np.einsum("kij,kj->i", C, y), y.sum(axis=0)])
    x = np.linalg.solve(ata, aty)
    res = y - np.einsum("kji,j->ki", C, x[:3]) - x[3:]
    return x, res, ata


def mag_attitude_fit(q_nb: ArrayLike, mag: ArrayLike, prior: float = 1e-3,
                     min_samples: int = 100) -> MagAttitudeFit | None:
    """Fit the hard-iron offset and the Earth field to magnetometer samples ``mag`` (N, 3), body
    axes, any unit, at known attitudes ``q_nb`` (N, 4) (rows with a NaN in either are left out).
    None when fewer than ``min_samples`` rows remain."""
    q = np.asarray(q_nb, float)
    m = np.asarray(mag, float)
    if q.ndim != 2 or q.shape[1] != 4 or m.shape != (len(q), 3):
        raise ValueError(f"q_nb must be (N, 4) and mag (N, 3), got {q.shape} and {m.shape}")
    ok = np.isfinite(q).all(axis=1) & np.isfinite(m).all(axis=1)
    given = int(ok.sum())
    if given < min_samples:
        return None
    C = Q.to_rotmat(q[ok] / np.linalg.norm(q[ok], axis=1, keepdims=True))
    scale = float(np.median(np.linalg.norm(m[ok], axis=1)))
    if not scale > 0:
        return None
    y = m[ok] / scale
    x, res, ata = _solve(C, y, prior)
    r = np.linalg.norm(res, axis=1)
    keep = r <= 3.0 * np.sqrt(np.mean(r ** 2))
    if keep.sum() >= min_samples and not keep.all():
        C, y = C[keep], y[keep]
        x, res, ata = _solve(C, y, prior)
    rms = float(np.sqrt(np.mean(np.sum(res ** 2, axis=1)) / 3.0))
    cov = np.linalg.inv(ata) * rms ** 2
    m_n, b = x[:3] * scale, x[3:] * scale
    return MagAttitudeFit(offset=b, field_n=m_n, declination=float(np.arctan2(m_n[1], m_n[0])),
                          inclination=float(np.arctan2(m_n[2], np.hypot(m_n[0], m_n[1]))),
                          offset_sigma=np.sqrt(np.diag(cov)[3:]) * scale, residual_rms=rms * scale,
                          samples=int(len(y)), given=given)
