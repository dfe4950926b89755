"""Online magnetometer hard-iron estimate: the offset refined while samples stream.

The field seen by a magnetometer with a hard-iron offset ``b`` lies on a sphere about ``b``:
``|m - b|^2 = r^2``, i.e. ``m.m = 2 m.b + c`` with ``c = r^2 - b.b``: linear in
``theta = [b, c]``. Recursive least squares with exponential forgetting (weight ``lam**age``)
keeps the normal equations ``H theta = g`` of all samples so far,

    H_k = lam H_(k-1) + phi_k phi_k^T,   g_k = lam g_(k-1) + phi_k (m_k . m_k),   phi = [2 m, 1],

started from a weak prior (offset 0, radius the first sample's norm) that holds the estimate
until the samples span enough directions. :func:`hard_iron_track` does this over an array,
vectorized (the sums are first-order recursions, run by ``scipy.signal.lfilter``);
:class:`OnlineHardIron` does it one sample at a time (a filter loop, a firmware port). Both give
the same numbers. Samples are scaled by the first one's norm inside, so any unit works and the
results come back in the input's unit.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["OnlineHardIron", "hard_iron_track"]

_IU = np.triu_indices(4)


def _phi(m_n: np.ndarray) -> np.ndarray:
    """(N, 4) regressors [2 m, 1] of scaled samples (N, 3)."""
    return np.column_stack([2.0 * m_n, np.ones(len(m_n))])


def _prior(prior_weight: float):
    """(H0 (4, 4), g0 (4,)) in scaled units: offset 0, radius 1 (c = 1)."""
    H0 = np.diag([prior_weight] * 3 + [prior_weight])
    g0 = H0 @ np.array([0.0, 0.0, 0.0, 1.0])
    return H0, g0


def _solve(H: np.ndarray, g: np.ndarray):
    """theta of (..., 4, 4) H and (..., 4) g: offset (..., 3), radius (...,)."""
    th = np.linalg.solve(H, g[..., None])[..., 0]
    b = th[..., :3]
    r2 = th[..., 3] + np.sum(b * b, axis=-1)
    return b, np.sqrt(np.maximum(r2, 0.0))


def _check(mag, name="mag") -> np.ndarray:
    m = np.asarray(mag, dtype=float)
    if m.ndim != 2 or m.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (N, 3), got {m.shape}")
    return m


def hard_iron_track(mag: ArrayLike, forgetting: float = 0.9995,
                    prior_weight: float = 10.0) -> tuple[np.ndarray, np.ndarray]:
    """Hard-iron offset after every sample of ``mag``.

    Parameters
    ----------
    mag : (N, 3) array_like
        Magnetometer samples (any unit). Rows with a NaN are skipped (the estimate holds).
    forgetting : float
        Weight per sample of the older samples, in (0, 1]: a memory of about
        ``1 / (1 - forgetting)`` samples (0.9995: 2000, 10 s at 200 Hz); 1 keeps them all.
    prior_weight : float
        Weight of the prior (offset 0, field the first sample's norm), in samples' worth of a
        unit field: it holds the estimate until the samples span several directions.

    Returns
    -------
    offset : (N, 3) ndarray
        The estimate after each sample (row k uses samples 0..k), in the unit of ``mag``.
    field : (N,) ndarray
        The radius of the fitted sphere (the field strength).
    """
    from .._optional import require
    lfilter = require("scipy.signal", "quatnav.calibration.hard_iron_track").lfilter
    m = _check(mag)
    if not 0 < forgetting <= 1:
        raise ValueError(f"forgetting: expected 0 < forgetting <= 1, got {forgetting!r}")
    ok = np.isfinite(m).all(axis=1)
    if not ok.any():
        raise ValueError("mag: no finite sample")
    scale = float(np.linalg.norm(m[np.argmax(ok)]))
    if not scale > 0:
        raise ValueError("mag: the first finite sample is zero")
    mn = np.where(ok[:, None], m / scale, 0.0)
    phi = _phi(mn) * ok[:, None]
    y = np.sum(mn * mn, axis=1)
    # the 10 distinct entries of phi phi^T and the 4 of phi y, each an exponentially weighted sum
    outer = (phi[:, :, None] * phi[:, None, :])[:, _IU[0], _IU[1]]
    lam = float(forgetting)
    H0, g0 = _prior(prior_weight)
    zi_h = (lam * H0[_IU])[None, :]
    zi_g = (lam * g0)[None, :]
    Hs = lfilter([1.0], [1.0, -lam], outer, axis=0, zi=zi_h)[0]
    gs = lfilter([1.0], [1.0, -lam], phi * y[:, None], axis=0, zi=zi_g)[0]
    H = np.empty((len(m), 4, 4))
    H[:, _IU[0], _IU[1]] = Hs
    H[:, _IU[1], _IU[0]] = Hs
    b, r = _solve(H, gs)
    return b * scale, r * scale


class OnlineHardIron:
    """The hard-iron estimate of :func:`hard_iron_track`, one sample at a time.

    >>> est = OnlineHardIron()
    >>> for m in mag:                      # as the samples arrive
    ...     est.update(m)
    ...     m_cal = m - est.offset         # the sample corrected with the estimate so far
    """

    def __init__(self, forgetting: float = 0.9995, prior_weight: float = 10.0):
        if not 0 < forgetting <= 1:
            raise ValueError(f"forgetting: expected 0 < forgetting <= 1, got {forgetting!r}")
        self.forgetting = float(forgetting)
        self.prior_weight = float(prior_weight)
        self.scale = None
        self.H, self.g = _prior(self.prior_weight)
        self.offset = np.zeros(3)
        self.field = np.nan
        self.samples = 0

    def update(self, m: ArrayLike) -> np.ndarray:
        """Take one sample (3,); returns the offset estimate after it (a NaN sample is skipped)."""
        m = np.asarray(m, dtype=float)
        if m.shape != (3,) and m.shape != (1, 3):
            raise ValueError(f"m: expected one sample of shape (3,), got shape {m.shape} "
                             "(hard_iron_track takes (N, 3))")
        m = m.reshape(3)
        if not np.isfinite(m).all():
            return self.offset
        if self.scale is None:
            self.scale = float(np.linalg.norm(m))
            if not self.scale > 0:
                self.scale = None
                return self.offset
        mn = m / self.scale
        phi = _phi(mn[None, :])[0]
        lam = self.forgetting
        self.H = lam * self.H + np.outer(phi, phi)
        self.g = lam * self.g + phi * float(mn @ mn)
        b, r = _solve(self.H, self.g)
        self.offset, self.field = b * self.scale, float(r) * self.scale
        self.samples += 1
        return self.offset
