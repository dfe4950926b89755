"""The GNSS fixes' speed and horizontal velocity (the velocity given with the fixes, else the
position differences), which the clock and axes checks compare with the IMU. The fixes are a dict
of columns as ``quatnav ins run`` reads them: ``time`` (s), ``lat``, ``lon`` (deg), ``h`` (m),
optional ``v_n``, ``v_e`` (m/s)."""
from __future__ import annotations

import numpy as np

__all__ = ["gnss_speed", "gnss_velocity_ne"]


def gnss_speed(d_g):
    """Horizontal GNSS speed per fix (m/s): the given velocity, else the position differences."""
    if "v_n" in d_g and np.isfinite(d_g["v_n"]).all():
        return np.hypot(d_g["v_n"], d_g["v_e"])
    r = gnss_velocity_ne(d_g)
    return None if r is None else np.r_[0.0, np.hypot(r[1][:, 0], r[1][:, 1])]  # each on the later fix


def gnss_velocity_ne(d_g):
    """(times, (K, 2) north/east velocity) of the fixes: the given velocity, else the position
    differences at the midpoints; None for fewer than 2 fixes."""
    t = np.asarray(d_g["time"], float)
    if len(t) < 2:
        return None
    if "v_n" in d_g and np.isfinite(d_g["v_n"]).all() and np.isfinite(d_g["v_e"]).all():
        return t, np.column_stack([d_g["v_n"], d_g["v_e"]]).astype(float)
    from ..core.earth import radii
    lat, lon, h = np.radians(d_g["lat"]), np.radians(d_g["lon"]), np.asarray(d_g["h"], float)
    dt = np.diff(t)
    R_M, R_N = radii(lat[1:])
    return 0.5 * (t[1:] + t[:-1]), np.column_stack([np.diff(lat) * (R_M + h[1:]) / dt,
                                                    np.diff(lon) * (R_N + h[1:]) * np.cos(lat[1:]) / dt])
