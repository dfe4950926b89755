"""The IMU's clock: times in seconds (not ms, us, ns), a plausible rate, the gaps a filter must
coast across (:func:`check_imu_times`, for a file whose lines the messages name) and the gaps of
many sample periods within a filter's ``max_dt`` (:func:`check_steps`, for a filter's run)."""
from __future__ import annotations

import numpy as np

from .._command import InputError
from .categories import GapWarning, RateWarning

__all__ = ["check_imu_times", "check_steps"]


_UNITS = (("milliseconds", 1e-3), ("microseconds", 1e-6), ("nanoseconds", 1e-9))


def _lines_text(pairs, limit=3) -> str:
    shown = ", ".join(pairs[:limit])
    return shown + (f" and {len(pairs) - limit} more" if len(pairs) > limit else "")


def check_imu_times(t, lines, max_dt, where="IMU"):
    """Refuse IMU times in the wrong unit; return the gaps longer than ``max_dt``.

    Returns
    -------
    gaps : list of (k, step)
        Rows k (0-based) whose step ``t[k] - t[k-1]`` exceeds ``max_dt``.
    warnings : list of RateWarning
        A slow rate (:class:`RateWarning`), the gaps (:class:`GapWarning`).

    Raises
    ------
    InputError
        When the median step exceeds ``max_dt`` (the record would be all gaps): the message
        names the unit the times look like (ms, us, ns) when the step fits one.
    """
    d = np.diff(t)
    med = float(np.median(d))
    warnings = []

    def guess(step):
        for name, f in _UNITS:
            if 1e-5 <= step * f <= 0.25:
                return name, 1.0 / (step * f)
        return None, None
    if med > max_dt:
        unit, rate = guess(med)
        hint = (f"the times look like {unit} (a {rate:.4g} Hz IMU): convert them to seconds" if unit
                else "times must be in seconds")
        raise InputError(f"{where}: median time step {med:g} s exceeds max_dt = {max_dt:g} s, implausible for an "
                         f"IMU; {hint}")
    if med > 0.1:
        unit, rate = guess(med)
        warnings.append(RateWarning(
            f"{where}: median time step {med:g} s ({1 / med:.3g} Hz) is slow for an IMU"
            + (f"; if the times are in {unit} ({rate:.4g} Hz), convert them to seconds" if unit else "")))
    big = np.flatnonzero(d > max_dt)
    gaps = [(int(k) + 1, float(d[k])) for k in big]
    if gaps:
        pairs = [f"lines {lines[k - 1]}-{lines[k]}: {step:g} s" for k, step in gaps]
        warnings.append(GapWarning(
            f"{where}: {len(gaps)} gap{'s' if len(gaps) > 1 else ''} longer than max_dt = {max_dt:g} s "
            f"({_lines_text(pairs)}): coasted across in steps of at most max_dt with the sample that "
            "ends each gap; the error grows there"))
    return gaps, warnings


def check_steps(steps, where="IMU", max_dt=None) -> list:
    """A RateWarning for a median time step over 0.1 s (slower than 10 Hz: times in ms?), and a
    GapWarning for steps longer than ten median steps (samples missing; up to ``max_dt``, where
    given: a filter refuses or coasts longer ones itself). The median is taken over at most 4,096
    evenly spaced steps; the gaps over every step (one comparison per sample)."""
    s = np.asarray(steps, dtype=np.float64)
    if s.ndim != 1 or s.size < 3:
        return []
    med = float(np.median(s[1::max(1, -(-(s.size - 1) // 4096))]))
    out = []
    if med > 0.1:
        out.append(RateWarning(f"{where}: the median time step {med:g} s ({1 / med:.3g} Hz) is slow for an IMU: are "
                               "the times in seconds (not ms)?"))
    big = s[1:] > 10.0 * med
    if max_dt is not None:
        big &= s[1:] <= max_dt
    rows = np.flatnonzero(big) + 1
    if rows.size:
        k = int(rows[np.argmax(s[rows])])
        out.append(GapWarning(f"{where}: {rows.size} time step{'s' if rows.size > 1 else ''} longer than ten median "
                              f"steps ({10 * med:.3g} s; the longest {float(s[k]):.3g} s, at row {k}): samples are "
                              "missing, and the filter takes each gap in one step"))
    return out
