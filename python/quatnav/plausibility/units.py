"""Units of the sensors and the fixes: a gyro in deg/s, an accelerometer in g or mg, a
magnetometer in T, G, mG or nT, latitude and longitude in radians."""
from __future__ import annotations

import math

import numpy as np

from ..filters._base import accel_unit
from ._signals import rest_window, row_norms
from .categories import UnitWarning

__all__ = ["check_gyro", "check_accel", "check_magnetometer", "check_latlon"]


def check_gyro(gyro, t, align_time, where="IMU"):
    """A warning when the rates look like deg/s (or None)."""
    w = row_norms(np.asarray(gyro, float))
    mx = float(np.max(np.abs(gyro)))
    rest = float(np.median(w[rest_window(t, align_time)]))
    med = float(np.median(w))
    if mx > 40.0 or med > 1.5 or rest > 0.1:
        why = (f"max |gyro| {mx:.4g} rad/s is beyond any MEMS gyro's range" if mx > 40.0 else
               f"median |gyro| {med:.4g} rad/s is implausibly fast" if med > 1.5 else
               f"median |gyro| {rest:.4g} over the first {align_time:g} s, where the filter levels at rest: as rad/s "
               f"that is {math.degrees(rest):.3g} deg/s, far above a gyro bias")
        return UnitWarning(f"{where}: gyro_x/y/z look like deg/s, not rad/s ({why}); multiply by pi/180"
                           + ("" if mx > 40.0 or med > 1.5 else ", or start the log at rest"))
    return None


def check_accel(accel, where="IMU"):
    """A warning when the specific force looks like g or mg, or is far from gravity (or None)."""
    unit, m = accel_unit(accel)
    if unit == "g":
        return UnitWarning(f"{where}: accel_x/y/z look like g, not m/s^2 (median |accel| {m:.4g}, expected ~9.8); "
                           "multiply by 9.80665")
    if unit == "mg":
        return UnitWarning(
            f"{where}: accel_x/y/z look like milli-g, not m/s^2 (median |accel| {m:.4g}, expected ~9.8); "
            "multiply by 0.00980665")
    if unit == "far":
        return UnitWarning(
            f"{where}: median |accel| {m:.4g} m/s^2, far from gravity (~9.8): check the unit of accel_x/y/z")
    return None


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
