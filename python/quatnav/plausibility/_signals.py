"""Signal helpers of the checks: row norms without temporaries, running means in O(N), runs of a
condition, the window at the start of a record where a filter levels at rest."""
from __future__ import annotations

import numpy as np

__all__ = ["row_dots", "row_norms", "box_mean", "still_run", "rest_window"]


def row_dots(a, b):
    """The dot product of each row of two (n, k) arrays."""
    return np.einsum("ij,ij->i", a, b)


def row_norms(x):
    """The norm of each row of an (n, 3) array: ``np.linalg.norm(x, axis=1)`` without its
    temporaries (the motion-start check runs over every IMU row)."""
    return np.sqrt(row_dots(x, x))


def box_mean(x, w):
    """The mean over ``w`` samples centred on each row, zeros outside (``np.convolve(x,
    np.ones(w) / w, mode="same")`` column by column), from cumulative sums: O(N) whatever ``w``."""
    x = np.asarray(x, float)
    n = len(x)
    c = np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, axis=0)])
    h = (w - 1) // 2 + 1  # row i's window ends before row i + h
    # rows a..b-1 have their whole window inside: slices; the edges clipped, by index
    a, b = min(n, max(0, w - h)), max(0, n - h + 1)
    a = min(a, b)
    out = np.empty_like(c[1:])
    out[a:b] = c[a + h:b + h] - c[a + h - w:b + h - w]
    edge = np.r_[0:a, b:n]
    out[edge] = c[np.minimum(edge + h, n)] - c[np.clip(edge + h - w, 0, n)]
    return out / w


def still_run(still):
    """The number of consecutive True values ending at each element (0 where it is False)."""
    idx = np.arange(len(still))
    return idx - np.maximum.accumulate(np.where(still, -1, idx))


def rest_window(t, align_time):
    """Rows in the alignment window [t0, t0 + align_time] (at least 10 when there are)."""
    n = int(np.searchsorted(t, t[0] + max(align_time, 0.0), side="right"))
    return slice(1, max(n, min(len(t), 11)))  # row 0 only fixes the start time
