"""The checks of an IMU record that every filter's ``run`` and every command make: the units (a
gyro in deg/s, an accelerometer in g or mg), the axes (gravity off the body's -z at rest),
saturation (a plateau at the sensor's range) and the clock (a rate below 10 Hz, gaps of many
sample periods). They read a sample of the rows and the first seconds, so that they cost about a
nanosecond per sample on a long record (``quatnav bench`` measures the Python layer's overhead).

:func:`check_imu` returns the warnings, :func:`warn_imu` issues them to the caller of ``run``;
inside :func:`checked_by_caller` (the pipelines of ``quatnav ins run`` and ``ahrs run``, which
check their inputs themselves, with the names of their files) the filters leave them out.
"""
from __future__ import annotations

import contextlib

import numpy as np

from ._signals import rest_window
from .axes import gravity_axes
from .categories import issue
from .times import check_steps
from .units import SAMPLE_ROWS, check_accel, check_saturation, gyro_unit, sample_rows

__all__ = ["check_imu", "warn_imu", "checked_by_caller"]

_quiet = [0]
#: The rows of the start of a record whose times the rest window is looked for in.
_HEAD = 200_000


@contextlib.contextmanager
def checked_by_caller():
    """Inside, :func:`warn_imu` issues nothing: the caller checks the inputs itself. Process-wide
    (not per thread), as a pipeline's filter runs may be on other threads."""
    _quiet[0] += 1
    try:
        yield
    finally:
        _quiet[0] -= 1


def check_imu(gyr, acc, *, t=None, steps=None, where: str = "IMU", rest_time: float = 2.0, axes: str = "up",
              rotation_fix: str | None = None, names=("gyr", "acc"), gyro_range: float = 0.0, acc_range: float = 0.0,
              max_dt: float | None = None, clock: bool = True, rotation=None, increments: bool = False) -> list:
    """The plausibility warnings of an IMU record, in order: unit of the gyro and the
    accelerometer (:class:`UnitWarning`), the axes (:class:`AxesWarning`), saturation
    (:class:`SaturationWarning`), the rate and the gaps (:class:`RateWarning`,
    :class:`GapWarning`).

    Parameters
    ----------
    gyr, acc : (N, 3) array_like
        Angular rate, rad/s, and specific force, m/s^2 (or their increments over each step, rad
        and m/s, with ``increments``), in the body's axes (or the IMU's, with ``rotation``).
    t : (N,) array_like, optional
        The times, s; or
    steps : float or (N,) array_like, optional
        The time steps, s (the first is that of row 0).
    where : str
        What the messages name first (``"QuaternionEKF.run"``, ``"IMU imu.csv"``).
    rest_time : float
        The first seconds, where an IMU that starts at rest shows its gyro's unit and gravity.
    axes : {"up", "frd", "none"}
        ``"up"``: only gravity on +z is named (a z axis that points up; an attitude filter may
        start in any orientation); ``"frd"``: gravity at rest more than 60 deg from -z is named
        (a navigation filter levels at rest); ``"none"``: no axes check.
    rotation_fix : str, optional
        With ``"frd"``: how the user turns the axes (``"imu_rotation in [filter]"``, a parameter);
        None: the samples themselves.
    names : (str, str)
        How the messages call the gyro and the accelerometer (``("gyro_x/y/z", "accel_x/y/z")``
        for a file's columns).
    gyro_range, acc_range : float
        The ranges the filter skips samples at (0: unlimited; then the saturation check names
        the range a clipped sensor shows).
    max_dt : float, optional
        Longer steps are the filter's to refuse or coast: no GapWarning for them.
    clock : bool
        Whether to check the rate and the gaps (a command that checks them with the file's
        lines leaves them out here).
    rotation : (3, 3) array_like, optional
        Turns the IMU's axes into the body's (``imu_rotation``), before the axes check.
    """
    g, a = np.asarray(gyr), np.asarray(acc)
    n = len(g)
    if n < 2 or g.ndim != 2 or a.shape != g.shape:
        return []
    s = None if steps is None else np.asarray(steps, dtype=np.float64)
    if t is not None:
        head_t = np.asarray(t[:_HEAD], dtype=np.float64)
    elif s is not None and s.ndim:
        head_t = np.concatenate([[0.0], np.cumsum(s[1:_HEAD])])
    else:
        head_t = np.arange(min(n, _HEAD)) * (float(s) if s is not None else 0.01)
    win = rest_window(head_t, rest_time)
    head = slice(win.start, min(win.stop, win.start + SAMPLE_ROWS))
    stride = max(1, -(-n // SAMPLE_ROWS))
    g_h, a_h = np.asarray(g[head], np.float64), np.asarray(a[head], np.float64)
    g_s, a_s = sample_rows(g), sample_rows(a)
    if increments:  # rates and specific force of each step (row 0 only fixes the start time)
        if t is not None:
            tt = np.asarray(t, dtype=np.float64)
            d_h, d_s = tt[head] - tt[head.start - 1:head.stop - 1], np.diff(tt)[stride - 1::stride]  # rows stride, 2 stride..
            m = min(len(g_s) - 1, len(d_s))
            g_s, a_s, d_s = g_s[1:m + 1], a_s[1:m + 1], d_s[:m]
        else:
            d_h = d_s = float(s) if s is not None and not s.ndim else 1.0
        g_h, a_h = g_h / np.reshape(d_h, (-1, 1)), a_h / np.reshape(d_h, (-1, 1))
        g_s, a_s = g_s / np.reshape(d_s, (-1, 1)), a_s / np.reshape(d_s, (-1, 1))
    if rotation is not None and not np.array_equal(np.asarray(rotation, float), np.eye(3)):
        r = np.asarray(rotation, dtype=np.float64)
        g_h, a_h, g_s, a_s = g_h @ r.T, a_h @ r.T, g_s @ r.T, a_s @ r.T
    gy, ac = names
    out = [gyro_unit(g_s, g_h, a_h, rest_time, where, gy), check_accel(a_s, where, name=ac)]
    if axes in ("up", "frd"):
        out.append(gravity_axes(a_h, rest_time, where, mode=axes, fix=rotation_fix))
    if not gyro_range and not increments:
        out.append(check_saturation(g_s, where, "gyro", "gyro_range", "rad/s", 2.0))
    if not acc_range and not increments:
        out.append(check_saturation(a_s, where, "accelerometer", "acc_range", "m/s^2", 15.0))
    if clock:
        if t is not None:
            tt = np.asarray(t, dtype=np.float64)
            s = np.concatenate([tt[1:2] - tt[:1], np.diff(tt)])
        if s is not None and s.ndim:
            out += check_steps(s, where, max_dt=max_dt)
    return [w for w in out if w is not None]


def warn_imu(gyr, acc, **kw) -> None:
    """:func:`check_imu`, its warnings issued to the first caller outside quatnav; nothing inside
    :func:`checked_by_caller`."""
    if _quiet[0]:
        return
    issue(check_imu(gyr, acc, **kw))
