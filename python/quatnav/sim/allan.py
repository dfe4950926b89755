"""Overlapping Allan deviation and the usual noise read-outs (IEEE Std 952-1997, annex C).

* angle / velocity random walk ``N``: the -1/2 slope line read at tau = 1 s,
  ``N = sigma(tau) sqrt(tau)`` averaged over the short-tau region where the slope is near -1/2;
* bias instability ``B``: ``sigma / 0.664`` at the flat part of the curve, where the log-log
  slope crosses zero. For flicker noise that is the minimum; a first-order Gauss-Markov bias
  (as simulated by :mod:`quatnav.sim.sensors`) shows a hump instead, and the read-out takes
  the hump's top, the first zero-slope point at which the curve stops rising.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["allan_deviation", "AllanReadout", "allan_readout"]


def allan_deviation(x, rate_hz, taus=None, points_per_decade=10):
    """Overlapping Allan deviation of a rate signal.

    Parameters
    ----------
    x : array_like, shape (N,) or (N, k)
        Rate samples (e.g. rad/s or m/s^2), uniformly spaced.
    rate_hz : float
        Sample rate (Hz).
    taus : array_like, optional
        Averaging times (s); default log-spaced from 1/rate to N/(10 rate).
    points_per_decade : int
        Density of the default taus.

    Returns
    -------
    taus : ndarray, shape (M,)
        Averaging times actually used (s, whole numbers of samples).
    adev : ndarray, shape (M,) or (M, k)
        Allan deviation, in the unit of ``x``.
    """
    x = np.asarray(x, float)
    one = x.ndim == 1
    if one:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] < 8:
        raise ValueError(f"x must have shape (N,) or (N, k) with N >= 8, got {x.shape}")
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"rate_hz must be positive, got {rate_hz!r}")
    n = x.shape[0]
    dt = 1.0 / rate_hz
    if taus is None:
        mmax = max(1, n // 10)
        ms = np.unique(np.round(np.logspace(0, np.log10(mmax), int(
            points_per_decade * np.log10(mmax)) + 1)).astype(int))
    else:
        ms = np.unique(np.maximum(1, np.round(np.asarray(taus, float) * rate_hz)).astype(int))
        ms = ms[ms <= (n - 1) // 2]
    theta = np.concatenate([np.zeros((1, x.shape[1])), np.cumsum(x, axis=0) * dt])
    adev = np.empty((len(ms), x.shape[1]))
    for i, m in enumerate(ms):
        d = theta[2 * m:] - 2 * theta[m:-m] + theta[:-2 * m]
        adev[i] = np.sqrt(np.mean(d**2, axis=0) / (2.0 * (m * dt) ** 2))
    taus_out = ms * dt
    return taus_out, adev[:, 0] if one else adev


@dataclass
class AllanReadout:
    """Read-outs of one Allan-deviation curve, in the unit of the signal:
    ``random_walk`` per sqrt(Hz) (white-noise density, ARW or VRW) and ``bias_instability``
    (and the tau at which it was read)."""

    random_walk: float
    bias_instability: float
    tau_bias_instability: float


def allan_readout(taus, adev, white_tau_max=None):
    """ARW/VRW and bias instability from one Allan-deviation curve (see the module doc).

    Parameters
    ----------
    taus, adev : array_like, shape (M,)
        From :func:`allan_deviation`.
    white_tau_max : float, optional
        The random walk is read on taus up to this value (s); default: the first tenth of the
        tau decades, never beyond the first zero-slope point.

    Returns
    -------
    AllanReadout
    """
    taus = np.asarray(taus, float)
    adev = np.asarray(adev, float)
    if taus.shape != adev.shape or taus.ndim != 1 or len(taus) < 5:
        raise ValueError("taus and adev must be 1-D arrays of the same length (>= 5)")
    lt, la = np.log(taus), np.log(adev)
    slope = np.gradient(la, lt)
    # smooth the slope a little: the long-tau end is noisy
    k = np.ones(3) / 3.0
    slope_s = np.convolve(np.pad(slope, 1, mode="edge"), k, mode="valid")
    # first point where the curve stops falling (a minimum or the start of a flat region)
    i_min = int(np.argmax(slope_s >= 0)) if np.any(slope_s >= 0) else len(taus) - 1
    # then the first point after it where it stops rising (top of a Gauss-Markov hump)
    after = np.nonzero(slope_s[i_min:] <= 0)[0]
    if len(after) and i_min + after[0] < len(taus) - 1:
        j = i_min + after[0]
        j = max(range(max(i_min, j - 2), min(len(taus), j + 3)), key=lambda i: adev[i])
        i_b = j if adev[j] > adev[i_min] else i_min
    else:
        i_b = i_min
    if white_tau_max is None:
        white_tau_max = min(taus[0] * 10 ** (0.3 * (lt[-1] - lt[0]) / np.log(10)), taus[i_min])
    sel = taus <= max(white_tau_max, taus[0])
    rw = float(np.median(adev[sel] * np.sqrt(taus[sel])))
    return AllanReadout(random_walk=rw, bias_instability=float(adev[i_b] / 0.664),
                        tau_bias_instability=float(taus[i_b]))
