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
NaN reference are ignored); an algorithm's figure is the mean of its trial RMSEs.

BROAD's own figures apply no alignment (its earth frame is aligned with the magnetic field).
:func:`fit_alignment` fits, per estimate, the constant rotations that a reference system leaves
open: a heading offset between the earth frames (always open in 6D, and a magnetic versus a
motion-capture north in 9D) and the rotation between the sensor's and the reference's body
frames (the markers' frame); :func:`aligned_errors_deg` scores an estimate after them.

Angles are in radians except in functions whose names end in ``_deg``.
"""
from __future__ import annotations

import numpy as np

from ..core import quaternion as Q

__all__ = ["error_quat", "total_error", "heading_error", "inclination_error", "rmse",
           "attitude_rmse_deg", "body_error_rotvec", "sigma_consistency", "fit_alignment", "aligned_errors_deg",
           "ALIGNMENTS"]

#: The alignments of :func:`fit_alignment`: ``"none"`` (BROAD's own figures), ``"heading"`` (a
#: heading offset between the earth frames), ``"both"`` (that and a constant rotation between the
#: body frames).
ALIGNMENTS = ("none", "heading", "both")


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


def _top_eigvec(M):
    w, v = np.linalg.eigh(M)
    return v[:, -1]


def fit_alignment(q_est, q_ref, mask=None, align: str = "both", iterations: int = 20):
    """The constant rotations that best map the reference onto an estimate.

    Finds ``q_e`` (a rotation about the vertical: the heading offset between the earth frames)
    and ``q_b`` (any rotation: between the body frames of the sensor and the reference) that
    maximize ``sum_k (q_est_k . (q_e * q_ref_k * q_b))^2`` over the samples of ``mask`` with a
    reference, i.e. minimize the chordal distance ``sum_k sin^2(angle_k / 2)``, which for small
    errors is the sum of squared error angles / 4. For a fixed ``q_e`` the best ``q_b`` is the
    principal eigenvector of ``sum_k d_k d_k^T`` with ``d_k = conj(q_e q_ref_k) q_est_k``; for a
    fixed ``q_b`` the best heading is that of the 2x2 problem in the ``(w, z)`` components of
    ``e_k = q_est_k conj(q_ref_k q_b)``; the two steps alternate (each never increases the cost;
    ``iterations`` of them, from the heading-only fit).

    Parameters
    ----------
    q_est, q_ref : (N, 4) array_like
        ``q_nb`` [w, x, y, z] of the estimate and of the reference (the same earth frame up to a
        heading; NaN rows of the reference are left out).
    mask : (N,) bool array_like, optional
        Samples used (default: all).
    align : {"none", "heading", "both"}
        What is fitted (:data:`ALIGNMENTS`).

    Returns
    -------
    q_e, q_b : (4,) ndarray
        Earth-side (about the vertical) and body-side rotations; the aligned reference is
        ``q_e * q_ref * q_b``. Identity for ``"none"`` or without any usable sample.
    """
    if align not in ALIGNMENTS:
        raise ValueError(f"align: expected one of {', '.join(ALIGNMENTS)}, got {align!r}")
    q_est, q_ref = _quats(q_est, "q_est"), _quats(q_ref, "q_ref")
    ok = np.all(np.isfinite(q_ref), axis=1) & np.all(np.isfinite(q_est), axis=1)
    if mask is not None:
        ok &= np.asarray(mask, dtype=bool)
    q_e, q_b = Q.identity(), Q.identity()
    if align == "none" or not ok.any():
        return q_e, q_b
    est = Q.normalize(q_est[ok])
    ref = Q.normalize(q_ref[ok])
    for _ in range(iterations if align == "both" else 1):
        e = Q.mul(est, Q.conj(Q.mul(ref, q_b)))  # q_est conj(q_ref q_b): q_e wanted
        wz = e[:, [0, 3]]
        c, s = _top_eigvec(wz.T @ wz)
        q_e = Q.normalize(np.array([c, 0.0, 0.0, s]))
        if align == "heading":
            break
        d = Q.mul(Q.conj(Q.mul(q_e, ref)), est)  # conj(q_e q_ref) q_est: q_b wanted
        q_b_new = Q.normalize(_top_eigvec(d.T @ d))
        if abs(abs(float(q_b_new @ q_b)) - 1.0) < 1e-15:
            q_b = q_b_new
            break
        q_b = q_b_new
    return Q.canonical(q_e), Q.canonical(q_b)


def aligned_errors_deg(q_est, q_ref, mask=None, align: str = "both") -> dict:
    """Total, heading and inclination RMSE (degrees, over ``mask``) after :func:`fit_alignment`,
    with the fitted rotations' angles: ``{"total", "heading", "inclination", "align_heading_deg",
    "align_body_deg"}``. The same fit for every estimator: it is fitted on the samples scored."""
    q_e, q_b = fit_alignment(q_est, q_ref, mask, align)
    ref = Q.mul(Q.mul(q_e, _quats(q_ref, "q_ref")), q_b)
    out = attitude_rmse_deg(q_est, ref, mask)
    out["align_heading_deg"] = float(np.degrees(2.0 * np.arctan2(q_e[3], q_e[0])))
    out["align_body_deg"] = float(np.degrees(2.0 * np.arccos(np.clip(abs(q_b[0]), 0.0, 1.0))))
    return out
