"""The time offset between the GNSS receiver's clock and the IMU's, estimated from a log.

A receiver stamps its fixes late (on delivery, by its latency) or on another clock; the GPS/INS
filter then compares the INS with fixes from another moment, and a vehicle at speed ``v`` and
acceleration ``a`` sees position innovations ``v * dt`` and velocity innovations ``a * dt``.
:func:`gps_time_offset` finds the ``gps_time_offset`` parameter of
:class:`quatnav.GpsInsFilter` that makes those innovations smallest, by running the filter on
the log over a grid of offsets (a coarse grid, then a finer grid around the best point)::

    est = quatnav.calibration.gps_time_offset(quatnav.GpsInsFilter(lever_arm_b=(0.1, 0, -0.3)),
                                              gyr, acc, t=t, gps_pos=Aid(tg, llh), gps_vel=Aid(tg, v_n))
    f = quatnav.GpsInsFilter(lever_arm_b=(0.1, 0, -0.3), gps_time_offset=est.offset)

The criterion is the sum of the GNSS fixes' normalized innovation squared (NIS). For a filter
whose model is right, the innovations are white and that sum is, up to a constant, minus twice
the log-likelihood of the fixes (the prediction error decomposition); its minimum over the
offset is the maximum-likelihood offset. Two choices keep the criterion smooth and honest:

* **The offset's own uncertainty is in the innovation covariance.** The filter adds
  ``gps_time_sigma`` (the speed and acceleration times that sigma) to the covariance of every
  fix. At each grid, it is set to half the grid's step (never below the filter's own value),
  so that a coarse grid does not gate out the fixes of every offset but the right one, and the
  fine grid sees the innovations at its resolution.
* **The same fixes at every offset of a grid.** Fixes whose NIS exists at every offset of a
  grid are summed (a shifted fix can fall before the alignment or after the IMU's end).

The innovation-based process-noise adaptation is switched off (``adapt_q_max = 1``) during the
search: it inflates the covariance of a filter that sees large innovations and would flatten
the criterion around a wrong offset. Everything else is the given filter, its parameters and
its initial state (:meth:`~quatnav.GpsInsFilter.set_initial`).

The offset is identifiable only while the vehicle moves or accelerates: a log at rest gives a
flat criterion (``sigma`` is then large or ``inf``). The grids' runs are independent and go
through any :class:`concurrent.futures.Executor` (a process pool, ``dask.distributed``'s
``client.get_executor()``); by default they run one after another.
"""
from __future__ import annotations

import math
import warnings
from concurrent.futures import Executor
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..filters._base import Aid
from ..filters.gpsins import GpsInsFilter

__all__ = ["gps_time_offset", "TimeOffsetEstimate"]


@dataclass
class TimeOffsetEstimate:
    """The outcome of :func:`gps_time_offset`.

    Attributes
    ----------
    offset : float
        The ``gps_time_offset`` to give :class:`quatnav.GpsInsFilter`, s (added to the GNSS
        times; a receiver latency ``L`` gives ``-L``).
    sigma : float
        One-sigma of ``offset``, s, from the curvature of the summed NIS at the finest grid
        (``sqrt(2 / J'')``): as honest as the filter's noise parameters (over-stated noise
        over-states it). ``inf`` when the criterion is flat there (no motion).
    at_bound : bool
        The minimum lies at an end of ``bounds``: the offset may lie outside them.
    bounds : (float, float)
        The searched interval, s.
    grids : list of (offsets, criterion, n_fixes)
        Every grid evaluated, coarse first: the offsets (s), the summed NIS at each, and the
        number of fixes in that sum.
    runs : int
        Filter runs made.
    """

    offset: float
    sigma: float
    at_bound: bool
    bounds: tuple
    grids: list = field(default_factory=list, repr=False)
    runs: int = 0

    def __str__(self) -> str:
        s = "inf" if not math.isfinite(self.sigma) else f"{self.sigma:.4f}"
        text = f"gps_time_offset = {self.offset:+.4f} s (one-sigma {s} s, {self.runs} runs)"
        if self.at_bound:
            text += f"; at the end of the searched {self.bounds[0]:+g} .. {self.bounds[1]:+g} s: widen the bounds"
        return text


def _nis(params, dtype, state, args, kwargs, offset, time_sigma):
    """The per-fix NIS of the GNSS position and velocity updates of one run (NaN: no NIS)."""
    from ..filters.gpsins import GpsInsFilter, NavigationWarning
    p = dict(params)
    p.update(gps_time_offset=float(offset), gps_time_sigma=float(time_sigma), adapt_q_max=1.0)
    f = GpsInsFilter(**p, dtype=dtype)
    if state is not None:
        f.set_state(state)
    with warnings.catch_warnings():  # a run without navigation has no NIS: the estimate says so
        warnings.simplefilter("ignore", NavigationWarning)
        r = f.run(*args, **kwargs)
    return np.concatenate([np.asarray(r.aids[k].nis, float) for k in ("gps_pos", "gps_vel") if k in r.aids])


def _grid(submit, offsets, time_sigma):
    """Summed NIS at each offset over the fixes that have one at every offset."""
    nis = np.vstack(list(submit(offsets, time_sigma)))
    common = np.isfinite(nis).all(axis=0)
    return nis[:, common].sum(axis=1), int(common.sum())


def _parabola(x, y, half: int = 4):
    """Vertex and second derivative of the least-squares parabola through the minimum of y and
    ``half`` points on either side (fewer at the ends): the criterion jitters on the scale of an
    IMU step, as a fix moves from one sample to the next, and a fit over several points
    averages that out."""
    i = int(np.argmin(y))
    a, b = max(i - half, 0), min(i + half + 1, len(x))
    if b - a < 3:
        return float(x[i]), 0.0
    c2, c1, _ = np.polyfit(x[a:b] - x[i], y[a:b], 2)
    if not c2 > 0:
        return float(x[i]), 0.0
    v = x[i] - c1 / (2 * c2)
    return float(np.clip(v, x[a], x[b - 1])), float(2 * c2)


def gps_time_offset(filter: GpsInsFilter, gyr: ArrayLike, acc: ArrayLike, mag: ArrayLike | None = None, *,
                    t: ArrayLike | None = None, dt: "float | ArrayLike | None" = None, gps_pos: Aid | None = None,
                    gps_vel: Aid | None = None, bounds: "tuple[float, float]" = (-0.5, 0.5), points: int = 21,
                    executor: Executor | None = None, **aids: object) -> TimeOffsetEstimate:
    """Estimate the ``gps_time_offset`` of a GPS/INS log (see the module's description).

    Parameters
    ----------
    filter : GpsInsFilter
        The filter as it will be run (parameters, dtype, an initial state from ``set_initial``);
        it is not changed. Its ``gps_time_offset`` is ignored.
    gyr, acc, mag, t, dt, gps_pos, gps_vel, **aids
        As :meth:`quatnav.GpsInsFilter.run` (``baro``, ``compass``, ``odometer``, ``imu_input``,
        ``on_invalid``, ``outages``); ``gps_pos`` or ``gps_vel`` is required.
    bounds : (float, float)
        The interval searched, s (default -0.5 .. 0.5).
    points : int
        Offsets of the coarse grid (at least 5; default 21: a step of 50 ms over the default
        bounds). The fine grid has 17 offsets, one coarse step either side of the coarse grid's
        best, with a step 8 times finer (6.25 ms by default); the estimate is the vertex of a
        least-squares parabola through the fine grid's 9 points about its minimum.
    executor : concurrent.futures.Executor, optional
        Runs each grid's filter runs (``executor.map``); default: one after another.

    Returns
    -------
    TimeOffsetEstimate
    """
    if not isinstance(filter, GpsInsFilter):
        raise TypeError(f"filter: expected a quatnav.GpsInsFilter, got {type(filter).__name__}")
    if gps_pos is None and gps_vel is None:
        raise ValueError("gps_pos, gps_vel: give at least one GNSS aid")
    try:
        lo, hi = (float(b) for b in bounds)
    except (TypeError, ValueError):
        raise TypeError(f"bounds: expected (low, high) in seconds, got {bounds!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"bounds: expected finite low < high, got {bounds!r}")
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or points < 5:
        raise ValueError(f"points: expected an integer of at least 5, got {points!r}")
    if executor is not None and not hasattr(executor, "map"):
        raise TypeError(f"executor: expected a concurrent.futures.Executor, got {type(executor).__name__}")

    params = filter.params
    sigma0 = float(params["gps_time_sigma"])
    state = filter.get_state()
    args = (gyr, acc) if mag is None else (gyr, acc, mag)
    kwargs = dict(aids, t=t, dt=dt, gps_pos=gps_pos, gps_vel=gps_vel)
    runs = [0]

    def submit(offsets, time_sigma):
        runs[0] += len(offsets)
        jobs = [(params, filter.dtype, state, args, kwargs, float(o), time_sigma) for o in offsets]
        mapper = map if executor is None else executor.map
        return mapper(_nis, *zip(*jobs))

    x = np.linspace(lo, hi, int(points))
    step = x[1] - x[0]
    y, n = _grid(submit, x, max(sigma0, step / 2))
    grids = [(x, y, n)]
    i0 = int(np.argmin(y))
    fine = step / 8
    x = np.unique(np.clip(x[i0] + fine * np.arange(-8, 9), lo, hi))
    y, n = _grid(submit, x, max(sigma0, fine / 2))
    grids.append((x, y, n))
    offset, curvature = _parabola(x, y)
    sigma = math.sqrt(2.0 / curvature) if curvature > 0 else math.inf
    at_bound = i0 in (0, len(grids[0][0]) - 1) or offset <= lo + fine / 2 or offset >= hi - fine / 2
    return TimeOffsetEstimate(offset=offset, sigma=sigma, at_bound=bool(at_bound), bounds=(lo, hi), grids=grids,
                              runs=runs[0])
