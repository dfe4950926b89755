"""Units and ranges of the sensors and the fixes: a gyro in deg/s, an accelerometer in g or mg,
a sensor clipped at its range, a magnetometer in T, G, mG or nT, latitude and longitude in
radians. The IMU checks read a sample of the rows (:data:`SAMPLE_ROWS`), so that they cost about
a nanosecond per sample on a long record."""
from __future__ import annotations

import math

import numpy as np

from ._signals import rest_window, row_norms
from .categories import SaturationWarning, UnitWarning

__all__ = ["accel_unit", "check_gyro", "gyro_unit", "check_accel", "check_saturation", "check_magnetometer", "check_latlon", "sample_rows",
           "steady", "SAMPLE_ROWS"]


def accel_unit(accel) -> tuple:
    """The unit a specific force (N, 3) appears to be in, from its median norm: ``"g"`` (0.5-2),
    ``"mg"`` (500-2000), ``"far"`` (neither those nor 6-14 m/s^2: far from gravity in any of
    them) or None (m/s^2); and that median. Non-finite rows are left out."""
    a = np.asarray(accel, float)
    with np.errstate(invalid="ignore", over="ignore"):
        n = np.sqrt(np.einsum("ij,ij->i", a, a))
    n = n[np.isfinite(n)]
    if not n.size:
        return None, float("nan")
    m = float(np.median(n))
    unit = "g" if 0.5 <= m <= 2.0 else "mg" if 500.0 <= m <= 2000.0 else None if 6.0 <= m <= 14.0 else "far"
    return unit, m


#: The most rows the unit and saturation checks read (evenly spaced over the record), besides
#: those of its first seconds: a median and a range are as plain in them as in every row.
SAMPLE_ROWS = 4096


def sample_rows(x, rows: int = SAMPLE_ROWS) -> np.ndarray:
    """At most ``rows`` evenly spaced rows of ``x`` (every row of a shorter record), float64."""
    x = np.asarray(x)
    return np.asarray(x[::max(1, -(-len(x) // rows))], dtype=np.float64)


def steady(accel, rel: float = 0.02) -> bool:
    """Whether a specific force (n, 3) is steady, as at rest: at least 10 finite rows whose vector
    varies (the norm of the per-axis standard deviations) by less than ``rel`` of its median norm,
    in any unit. A rotation turns the vector (not about the vertical: a level turntable looks
    still); BROAD's IMU at rest varies by 0.9 %."""
    a = np.asarray(accel, dtype=np.float64)
    a = a[np.isfinite(a).all(axis=1)] if a.ndim == 2 else a
    if a.ndim != 2 or len(a) < 10:
        return False
    return bool(np.linalg.norm(np.std(a, axis=0)) < rel * np.median(row_norms(a)))


def check_gyro(gyro, t, align_time=2.0, where="IMU", accel=None, name="gyro_x/y/z"):
    """A UnitWarning when the rates look like deg/s (or None): beyond any MEMS gyro's range
    (40 rad/s; a hand-held IMU reaches 25, BROAD's fast rotation), or more than 0.1 rad/s about
    a horizontal axis over the first ``align_time`` s while the accelerometer ``accel`` says the
    IMU is still there (its vector steady within 2 %; without ``accel``, taken as still, and the
    whole rate counts): 0.1 rad/s is 5.7 deg/s, far above a gyro bias, and a deg/s gyro at rest
    reads its bias and noise, 0.2 to 3 deg/s on each axis. The rate about the vertical is left
    out because a level turntable or a circling car turns about it with a steady accelerometer.
    The median rate is no evidence: BROAD's fast combined motion has 5.3 rad/s."""
    win = rest_window(t, align_time)
    win = slice(win.start, min(win.stop, win.start + SAMPLE_ROWS))
    head_a = None if accel is None else np.asarray(accel[win], dtype=np.float64)
    return gyro_unit(sample_rows(gyro), np.asarray(gyro[win], dtype=np.float64), head_a, align_time, where, name)


def gyro_unit(sample, head, head_accel, align_time, where, name="gyro_x/y/z"):
    """:func:`check_gyro` on a sample of the rows and the rows of the first ``align_time`` s
    (with the accelerometer's there, or None)."""
    w = row_norms(sample)
    w = w[np.isfinite(w)]
    if not w.size:
        return None
    mx = float(w.max())
    still = head_accel is None or steady(head_accel)
    if still and head_accel is not None:
        # Only the rate about a horizontal axis must turn a steady accelerometer: a rotation about
        # the vertical (a level turntable, a car circling) keeps it steady at any rate.
        a = head_accel[np.isfinite(head_accel).all(axis=1)]
        up = a.mean(axis=0)
        up = up / np.linalg.norm(up)
        head = head - np.outer(head @ up, up)
    wr = row_norms(head)
    wr = wr[np.isfinite(wr)]
    rest = float(np.median(wr)) if still and wr.size else 0.0
    if mx > 40.0:
        why = f"max |gyro| {mx:.4g} rad/s is beyond any MEMS gyro's range"
    elif rest > 0.1:
        what = "median |gyro|" if head_accel is None else "median rate about a horizontal axis"
        why = (f"{what} {rest:.4g} over the first {align_time:g} s, where the "
               + ("accelerometer says the IMU is still" if head_accel is not None else "filter levels at rest")
               + f": as rad/s that is {math.degrees(rest):.3g} deg/s, far above a gyro bias")
    else:
        return None
    verb = "look" if "/" in name else "looks"
    return UnitWarning(f"{where}: {name} {verb} like deg/s, not rad/s ({why}); multiply by pi/180")


def check_accel(accel, where="IMU", name="accel_x/y/z"):
    """A UnitWarning when the specific force looks like g or mg, or is far from gravity (or
    None), from the median norm of a sample of the rows (:func:`quatnav.filters._base.accel_unit`)."""
    unit, m = accel_unit(sample_rows(accel))
    verb = "look" if "/" in name else "looks"
    if unit == "g":
        return UnitWarning(f"{where}: {name} {verb} like g, not m/s^2 (median |accel| {m:.4g}, expected ~9.8); "
                           "multiply by 9.80665")
    if unit == "mg":
        return UnitWarning(
            f"{where}: {name} {verb} like milli-g, not m/s^2 (median |accel| {m:.4g}, expected ~9.8); "
            "multiply by 0.00980665")
    if unit == "far":
        return UnitWarning(
            f"{where}: median |accel| {m:.4g} m/s^2, far from gravity (~9.8): check the unit of {name}")
    return None


def check_saturation(x, where="IMU", name="gyro", limit_param="gyro_range", unit="rad/s", floor=2.0):
    """A SaturationWarning (or None) when an axis holds its largest magnitude, at least
    ``floor``, in three or more of a sample of the rows: a plateau at the sensor's range (clipped
    samples), which no noisy signal makes (BROAD's IMU: once per axis). ``limit_param`` names the
    filter parameter that makes it skip them."""
    a = np.abs(sample_rows(x))
    found = []
    for k in range(3):
        col = a[:, k][np.isfinite(a[:, k])]
        if col.size:
            m = float(col.max())
            hits = int(np.count_nonzero(col == m))
            if m >= floor and hits >= 3:
                found.append((hits, k, m, col.size))
    if not found:
        return None
    hits, k, m, n = max(found)
    axes = "/".join("xyz"[f[1]] for f in sorted(found, key=lambda f: f[1]))
    return SaturationWarning(
        f"{where}: the {name} saturates: axis {'xyz'[k]} holds its largest magnitude {m:.6g} {unit} in {hits} of "
        f"{n} sampled rows (a plateau at the sensor's range; axes {axes}); set {limit_param} = {m:.6g} so that the "
        "filter skips the clipped samples instead of using them")


def check_magnetometer(mag, where="magnetometer"):
    """A warning when a magnetometer (N, 3) is not in uT: T, G, mG or nT are named (or None).

    The Earth's field is 22-67 uT at the surface.
    """
    m = float(np.median(np.linalg.norm(np.asarray(mag, float), axis=1)))
    for lo, hi, unit, factor in ((5e-6, 2e-4, "tesla", "1e6"), (0.1, 1.0, "gauss", "100"),
                                 (100.0, 1000.0, "milligauss", "0.1"), (5e3, 2e5, "nanotesla", "0.001")):
        if lo <= m <= hi:
            return UnitWarning(f"{where}: median |mag| {m:.4g} looks like {unit}, not uT; multiply by {factor}")
    if not 5.0 <= m <= 200.0:
        return UnitWarning(f"{where}: median |mag| {m:.4g}, expected 22-67 uT for the Earth's field: check the unit")
    return None


def check_latlon(lat_deg, lon_deg, where="GNSS"):
    """A warning when every fix lies within +-pi/2, +-pi "degrees" of (0, 0): radians (or None)."""
    if len(lat_deg) and np.all(np.abs(lat_deg) <= math.pi / 2) and np.all(np.abs(lon_deg) <= math.pi) \
            and np.max(np.abs(np.concatenate([lat_deg, lon_deg]))) > 1e-3:
        return UnitWarning(f"{where}: every lat/lon is within +-1.571/+-3.142, i.e. they look like radians "
                           f"(lat {np.median(lat_deg):.4f}, lon {np.median(lon_deg):.4f}); the columns are degrees")
    return None
