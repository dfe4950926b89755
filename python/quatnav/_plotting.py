"""Small helpers shared by the package's figures (matplotlib is imported only when one is made).

The figures are drawn on :class:`matplotlib.figure.Figure` objects without pyplot, so writing one
neither needs a display nor switches the backend of an interactive session.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np


def figure(figsize, **kw):
    """A new figure with constrained layout (legends placed outside the axes are kept in)."""
    from ._optional import require
    require("matplotlib", "plotting")
    from matplotlib.figure import Figure
    return Figure(figsize=figsize, layout="constrained", **kw)


def legend_right(ax, handles=None, labels=None, **kw):
    """A legend to the right of ``ax``, outside the data."""
    kw = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0, "fontsize": 8,
          "frameon": False, **kw}
    if handles is not None:
        return ax.legend(handles, labels, **kw)
    return ax.legend(**kw)


def save(fig, path, dpi: int = 110) -> Path:
    """Write ``fig`` to ``path`` (its folder is created if needed); returns the path."""
    path = Path(path)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path


def moving_rms(x, n: int) -> np.ndarray:
    """Root mean square of ``x`` over a centred window of ``n`` samples along axis 0 (same
    length; the window is shortened at the ends; NaN samples are left out)."""
    x = np.asarray(x, float)
    if n <= 1:
        return np.abs(x)
    sq = np.where(np.isfinite(x), x * x, 0.0)
    cnt = np.isfinite(x).astype(float)
    c = np.cumsum(np.concatenate([np.zeros((1,) + x.shape[1:]), sq]), axis=0)
    k = np.cumsum(np.concatenate([np.zeros((1,) + x.shape[1:]), cnt]), axis=0)
    i = np.arange(len(x))
    lo = np.clip(i - n // 2, 0, len(x))
    hi = np.clip(i - n // 2 + n, 0, len(x))
    num = c[hi] - c[lo]
    den = k[hi] - k[lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.sqrt(np.where(den > 0, num / np.maximum(den, 1), np.nan))


def unwrap_deg(angle_rad) -> np.ndarray:
    """An angle series (rad) unwrapped and in degrees, so a heading through +/-180 deg draws no
    vertical jump."""
    a = np.asarray(angle_rad, float)
    return np.degrees(np.unwrap(a))


def robust_limits(y, lo_pct: float = 0.5, hi_pct: float = 99.5, pad: float = 0.15):
    """(low, high) axis limits that hold the central part of ``y`` (percentiles of the finite
    values), padded by ``pad`` of the range; symmetric about zero when ``y`` straddles it."""
    v = np.asarray(y, float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return None
    lo, hi = np.percentile(v, [lo_pct, hi_pct])
    if lo < 0 < hi:
        m = max(-lo, hi) * (1 + pad)
        return -m, m
    span = (hi - lo) or max(abs(hi), 1e-12)
    return lo - pad * span, hi + pad * span


def time_axis(t, t0=None):
    """Times for a figure's x axis, and its label: seconds since the first time when the times
    are absolute (a GPS or Unix epoch, beyond 10^5 s, which an axis would print as an offset
    like "+1.756402e9"), with that time in the label; else the times as they are."""
    t = np.asarray(t, float)
    if t0 is None:
        finite = t[np.isfinite(t)]
        t0 = float(finite[0]) if finite.size else 0.0
    if abs(t0) < 1e5:
        return t, "time [s]"
    return t - t0, f"time since t = {t0:.3f} s [s]"


def wrapped_nan(angle_deg, period=360.0):
    """An angle series (deg, within +-period/2) with NaN put where it wraps, so that a line plot
    draws no vertical stroke across the axis at +-180 deg."""
    a = np.asarray(angle_deg, float).copy()
    jumps = np.flatnonzero(np.abs(np.diff(a)) > period / 2) + 1
    return np.insert(a, jumps, np.nan), jumps
