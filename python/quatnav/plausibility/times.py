"""The IMU's clock: times in seconds (not ms, us, ns), a plausible rate, the gaps a filter must
coast across."""
from __future__ import annotations

import numpy as np

from .._command import InputError
from .categories import GapWarning, RateWarning

__all__ = ["check_imu_times"]


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
