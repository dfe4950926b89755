"""Gaps in the IMU record longer than the filter's ``max_dt``: coasted across in equal steps with
the sample that ends each gap (by the files' convention the mean over the gap)."""
from __future__ import annotations

import math

import numpy as np

from .._command import InputError

__all__ = ["coast_gaps", "MAX_COAST_STEPS"]

#: The most coasting steps inserted into one run (a longer gap is refused, not coasted).
MAX_COAST_STEPS = 5_000_000


def coast_gaps(t, gyro, accel, gaps, max_dt, lines=None, where="IMU"):
    """Insert coasting steps into gaps longer than ``max_dt``.

    Each gap (t[k-1], t[k]] is split into ``ceil(step / max_dt)`` equal steps, all with row k's
    rate and specific force (row k is the mean over the gap by the file's convention). ``lines``
    (file line of each row) and ``where`` only serve the message when the gaps are too long.

    Returns
    -------
    t, gyro, accel : ndarray
        The expanded record.
    original : (M,) bool ndarray
        True at the rows of the input (False at inserted steps).
    """
    if not gaps:
        return t, gyro, accel, np.ones(len(t), bool)
    reps = np.ones(len(t), dtype=np.int64)
    for k, step in gaps:
        reps[k] = int(math.ceil(step / (max_dt * (1 - 1e-9))))  # every sub-step strictly below max_dt
    total = int(reps.sum()) - len(t)
    if total > MAX_COAST_STEPS:
        k, step = max(gaps, key=lambda g: g[1])
        at = f"lines {lines[k - 1]}-{lines[k]}" if lines is not None else f"rows {k - 1}-{k}"
        raise InputError(f"{where}: gaps would need {total} coasting steps of max_dt = {max_dt:g} s (longest "
                         f"{step:g} s, {at}); split the log at the gap or raise max_dt")
    idx = np.repeat(np.arange(len(t)), reps)
    original = np.ones(len(idx), bool)
    tt = t[idx].copy()
    pos = np.cumsum(reps) - 1  # position of each original row in the expanded record
    for k, _ in gaps:
        m = reps[k]
        j = pos[k] - m + 1  # first inserted step
        frac = np.arange(1, m) / m
        tt[j:j + m - 1] = t[k - 1] + frac * (t[k] - t[k - 1])
        original[j:j + m - 1] = False
    return tt, gyro[idx], accel[idx], original
