"""The IMU's axes against the body's forward-right-down: gravity on -z at rest, the direction of
travel along x."""
from __future__ import annotations

import numpy as np

from ._signals import rest_window, row_dots
from .categories import AxesWarning

__all__ = ["check_gravity", "gravity_axes", "forward_axis", "check_forward_axis"]


def check_gravity(accel, t, align_time, where="IMU", mode="frd", fix="imu_rotation in [filter]"):
    """An AxesWarning when gravity at rest is not on -z of the forward-right-down body frame (or
    None).

    At rest a forward-right-down IMU measures the specific force (0, 0, -g). ``mode="frd"`` (a
    navigation filter, which levels at rest): a mean over the first ``align_time`` s more than 60
    deg away from -z names the axis it appears on. ``mode="up"`` (an attitude filter, which may
    start in any orientation): only a mean within 45 deg of +z, a z axis that points up
    (forward-left-up, as many IMUs and datasets give it; the roll then reads +-180 deg). ``fix``
    names how the user turns the axes (``imu_rotation in [filter]``, a parameter, or None: the
    samples themselves).
    """
    win = rest_window(t, align_time)
    return gravity_axes(np.asarray(accel[slice(win.start, min(win.stop, win.start + 4096))], dtype=np.float64),
                        align_time, where, mode, fix)


def gravity_axes(head, align_time, where="IMU", mode="frd", fix="imu_rotation in [filter]"):
    """:func:`check_gravity` on the specific force of the first ``align_time`` s."""
    f = np.mean(head, axis=0) if len(head) else np.full(3, np.nan)
    n = float(np.linalg.norm(f))
    if not n > 0.5 or not np.isfinite(n):
        return None
    at = f"mean specific force over the first {align_time:g} s ({f[0]:.2f}, {f[1]:.2f}, {f[2]:.2f}) m/s^2"
    if mode == "up":
        if f[2] / n < np.cos(np.radians(45.0)):
            return None
        return AxesWarning(
            f"{where}: gravity appears on +z ({at}; forward-right-down at rest sees (0, 0, -9.8)): the IMU's z axis "
            "points up (forward-left-up), so the roll reads +-180 deg; for forward-right-down negate y and z of the "
            "gyro, accelerometer and magnetometer ([x, -y, -z]), or, if the IMU is mounted upside down on purpose, "
            "ignore this (warnings.simplefilter('ignore', quatnav.AxesWarning))")
    if -f[2] / n >= 0.5:  # within 60 deg of -z
        return None
    ax = int(np.argmax(np.abs(f)))
    sign = "+" if f[ax] > 0 else "-"
    turn = (f"set {fix} (e.g. [3.141593, 0, 0], a roll of 180 deg)" if fix else
            "turn the samples into forward-right-down ([x, -y, -z] for a roll of 180 deg)")
    if ax == 2:
        return AxesWarning(
            f"{where}: gravity appears on +z ({at}; forward-right-down at rest sees (0, 0, -9.8)): is the IMU "
            f"upside down, its z axis up (forward-left-up)? {turn}; or the accelerometer gives gravity instead of "
            "specific force (negate all three)")
    return AxesWarning(
        f"{where}: gravity appears on {sign}{'xyz'[ax]} ({at}; forward-right-down at rest sees (0, 0, -9.8)): "
        "the IMU axes are not forward-right-down: "
        + (f"set {fix} (the rotation from the IMU axes to forward-right-down)" if fix else
           "turn the samples into forward-right-down")
        + ", or it is not level at rest")


def forward_axis(t, accel, gnss_t, vel_ne, span=1.0, min_speed=3.0):
    """The direction of travel in the IMU's horizontal plane, from the accelerations: over each
    ``span`` s between fixes while moving faster than ``min_speed`` (the course defined), the GNSS
    velocity change gives the acceleration along and across the track (forward, right), the mean
    specific force over the same interval, with the gravity direction (the log's mean specific
    force) taken off, the same acceleration in the IMU axes. The least-squares rotation about the
    down axis between the two is the angle of the direction of travel from the IMU's x axis
    (positive towards y, i.e. to the right in forward-right-down).

    Returns ``(angle_rad, intervals, agreement)`` (agreement: the fitted rotation's correlation,
    1 for a perfect fit) or None when fewer than 10 intervals accelerate by 0.5 m/s^2 or more."""
    t = np.asarray(t, float)
    f = np.asarray(accel, float)
    g = f.mean(axis=0)
    if len(t) < 10 or not np.linalg.norm(g) > 5.0:
        return None
    down = -g / np.linalg.norm(g)
    e1 = np.array([1.0, 0.0, 0.0]) - down[0] * down
    if not np.linalg.norm(e1) > 0.3:  # x near vertical: no angle from it
        return None
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(down, e1)  # e1, e2, down right-handed (x, y, z in forward-right-down)
    tg = np.asarray(gnss_t, float)
    v = np.asarray(vel_ne, float)
    m = max(1, int(round(span / float(np.median(np.diff(tg))))))
    i0, i1 = np.arange(len(tg) - m), np.arange(m, len(tg))
    dtg = tg[i1] - tg[i0]
    vm = 0.5 * (v[i0] + v[i1])
    speed = np.hypot(vm[:, 0], vm[:, 1])
    ok = ((np.hypot(v[i0, 0], v[i0, 1]) > min_speed) & (np.hypot(v[i1, 0], v[i1, 1]) > min_speed)
          & (dtg < 1.5 * span + 1e-9) & (tg[i0] >= t[0]) & (tg[i1] <= t[-1]) & np.isfinite(vm).all(axis=1))
    if ok.sum() < 10:
        return None
    i0, i1, dtg, vm, speed = i0[ok], i1[ok], dtg[ok], vm[ok], speed[ok]
    a = (v[i1] - v[i0]) / dtg[:, None]
    u = vm / speed[:, None]
    q = np.column_stack([row_dots(a, u), a[:, 1] * u[:, 0] - a[:, 0] * u[:, 1]])  # along, right of the track
    c = np.vstack([np.zeros(3), np.cumsum(f, axis=0)])
    k0, k1 = np.searchsorted(t, tg[i0]), np.searchsorted(t, tg[i1])
    good = k1 > k0
    fm = (c[k1[good]] - c[k0[good]]) / (k1[good] - k0[good])[:, None]
    p = np.column_stack([fm @ e1, fm @ e2])
    q = q[good]
    strong = np.hypot(q[:, 0], q[:, 1]) >= 0.5
    if strong.sum() < 10:
        return None
    cross = float(np.sum(q[:, 0] * p[:, 1] - q[:, 1] * p[:, 0]))
    dot = float(np.sum(q[:, 0] * p[:, 0] + q[:, 1] * p[:, 1]))
    agreement = float(np.hypot(cross, dot) / np.sqrt(np.sum(p * p) * np.sum(q * q)))
    return float(np.arctan2(cross, dot)), int(len(q)), agreement


def check_forward_axis(t, accel, gnss_t, vel_ne, where="IMU", limit_deg=20.0):
    """A warning when the direction of travel (:func:`forward_axis`, agreement 0.7 or more) is more
    than ``limit_deg`` from the body's x axis, naming the yaw of ``imu_rotation`` that would turn
    it there (or None)."""
    if vel_ne is None:
        return None
    r = forward_axis(t, accel, gnss_t, vel_ne)
    if r is None:
        return None
    ang, n, agree = r
    if agree < 0.7 or abs(np.degrees(ang)) <= limit_deg:
        return None
    return AxesWarning(
        f"{where}: the vehicle travels at {np.degrees(ang):+.0f} deg from the body x axis about down (from the "
        f"accelerations of {n} one-second intervals against the GNSS velocity, agreement {agree:.2f}); the "
        "alignment in motion, the odometer and the non-holonomic constraint take x as forward: if the IMU is "
        f"mounted so, add a yaw of {-ang:.4f} rad to imu_rotation in [filter] (e.g. imu_rotation = "
        f"[0, 0, {-ang:.4f}] for IMU axes otherwise forward-right-down)")
