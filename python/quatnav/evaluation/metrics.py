"""Attitude error metrics, as defined by the BROAD benchmark.

For an estimate ``q_est`` and a reference ``q_ref`` (both ``q_nb``, same navigation frame) the
error quaternion is expressed in the navigation (earth) frame,

    q_err = q_est * conj(q_ref),

and split into

* total error        ``2 acos(|w|)``                 (the whole rotation angle),
* heading error      ``2 atan(|z / w|)``              (the part about the vertical axis),
* inclination error  ``2 acos(sqrt(w^2 + z^2))``      (the part about horizontal axes).

The three are the same in NED and ENU (the frames share the vertical axis up to its sign).
A trial's figure is the RMSE of each over the samples of the movement phases (samples with a
NaN reference are ignored); an algorithm's figure is the mean of its trial RMSEs. No heading
alignment is applied: BROAD's earth frame is aligned with the magnetic field.

Angles are in radians except in functions whose names end in ``_deg``.
"""
from __future__ import annotations

import numpy as np

from ..core import quaternion as Q

__all__ = ["error_quat", "total_error", "heading_error", "inclination_error", "rmse",
           "attitude_rmse_deg", "body_error_rotvec", "sigma_consistency"]


def _quats(q, name):
    q = np.asarray(q, dtype=float)
    if q.shape[-1] != 4:
        raise ValueError(f"{name}: expected shape (N, 4) or (4,), got {q.shape}")
    return q


def error_quat(q_est, q_ref) -> np.ndarray:
    """Navigation-frame error quaternion ``q_est * conj(q_ref)``, normalized, shape like inputs."""
    q_est, q_ref = _quats(q_est, "q_est"), _quats(q_ref, "q_ref")
    e = Q.mul(q_est / np.linalg.norm(q_est, axis=-1, keepdims=True),
              Q.conj(q_ref / np.linalg.norm(q_ref, axis=-1, keepdims=True)))
    return e / np.linalg.norm(e, axis=-1, keepdims=True)


def total_error(q_err) -> np.ndarray:
    """Rotation angle of the error quaternion, rad: ``2 acos(|w|)``."""
    q = _quats(q_err, "q_err")
    return 2.0 * np.arccos(np.clip(np.abs(q[..., 0]), 0.0, 1.0))


def heading_error(q_err) -> np.ndarray:
    """Heading part of a navigation-frame error quaternion, rad: ``2 atan(|z / w|)``."""
    q = _quats(q_err, "q_err")
    with np.errstate(divide="ignore", invalid="ignore"):
        return 2.0 * np.arctan(np.abs(q[..., 3] / q[..., 0]))


def inclination_error(q_err) -> np.ndarray:
    """Inclination part of a navigation-frame error quaternion, rad: ``2 acos(sqrt(w^2 + z^2))``."""
    q = _quats(q_err, "q_err")
    return 2.0 * np.arccos(np.clip(np.sqrt(q[..., 0] ** 2 + q[..., 3] ** 2), 0.0, 1.0))


def rmse(x, mask=None) -> float:
    """Root mean square of ``x`` over ``mask`` (all samples if None), ignoring NaN; NaN if empty."""
    x = np.asarray(x, dtype=float)
    if mask is not None:
        x = x[np.asarray(mask, dtype=bool)]
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(x**2))) if x.size else float("nan")


def attitude_rmse_deg(q_est, q_ref, mask=None) -> dict:
    """BROAD's figures for one trial: total, heading and inclination RMSE over ``mask``, degrees.

    Parameters
    ----------
    q_est, q_ref : (N, 4) array_like
        ``q_nb`` [w, x, y, z] estimated and reference (NaN reference rows are ignored).
    mask : (N,) bool array_like, optional
        Samples to include (BROAD: the movement phases).

    Returns
    -------
    dict
        ``{"total": ..., "heading": ..., "inclination": ...}`` in degrees.
    """
    e = error_quat(q_est, q_ref)
    return {"total": np.degrees(rmse(total_error(e), mask)),
            "heading": np.degrees(rmse(heading_error(e), mask)),
            "inclination": np.degrees(rmse(inclination_error(e), mask))}


def body_error_rotvec(q_est, q_ref) -> np.ndarray:
    """Body-frame rotation vector ``dtheta`` with ``q_ref = q_est * exp(dtheta)``, rad, (N, 3).

    This is the error whose covariance the attitude filters report (``att_sigma``).
    """
    return Q.to_rotvec(Q.mul(Q.conj(_quats(q_est, "q_est")), _quats(q_ref, "q_ref")))


def sigma_consistency(q_est, q_ref, att_sigma, mask=None, k: float = 3.0) -> float:
    """Fraction of (sample, axis) pairs whose attitude error lies within ``k`` one-sigmas.

    Parameters
    ----------
    q_est, q_ref : (N, 4) array_like
        Estimate and reference ``q_nb``.
    att_sigma : (N, 3) array_like
        The filter's own one-sigma of the body-frame rotation-vector error, rad.
    mask : (N,) bool array_like, optional
        Samples to include; NaN references are ignored.
    k : float
        Number of sigmas (3: a consistent Gaussian filter gives about 0.997).
    """
    d = body_error_rotvec(q_est, q_ref)
    s = np.asarray(att_sigma, dtype=float)
    ok = np.all(np.isfinite(d), axis=1) & np.all(np.isfinite(s), axis=1)
    if mask is not None:
        ok &= np.asarray(mask, dtype=bool)
    if not ok.any():
        return float("nan")
    return float(np.mean(np.abs(d[ok]) <= k * s[ok]))
