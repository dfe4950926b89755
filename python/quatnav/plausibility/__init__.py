"""Plausibility checks of sensor data: the mistakes a filter cannot see for itself, because the
numbers are valid, only not what the user meant.

* units (:mod:`.units`, :mod:`.times`): a gyro in deg/s, an accelerometer in g or mg, a
  magnetometer in gauss or nT, latitude/longitude in radians, times in ms, us or ns;
* axes (:mod:`.axes`): gravity not on -z of forward-right-down at rest, travel off the x axis;
* saturation (:mod:`.units`): a sensor clipped at its range;
* clocks (:mod:`.clocks`): GNSS and IMU times that do not overlap, leap seconds or the GPS epoch
  between them, the motion starting seconds apart in the two;
* rates and gaps (:mod:`.times`); aids a filter gated out in most samples (:mod:`.aids`).

:func:`check_imu` is the set every filter's ``run`` makes of its IMU input (and ``ahrs run`` of
its log); :func:`plausibility_warnings` adds the GNSS's for ``ins run``. Each check returns a
warning object of a :mod:`category <.categories>` (or None) whose message names the input, the
evidence and the fix; the callers issue them with :func:`warnings.warn`, so that a user filters
them by category (``warnings.simplefilter("ignore", quatnav.AxesWarning)``).
"""
from __future__ import annotations

import numpy as np

from .aids import check_heading_aids
from .axes import check_forward_axis, check_gravity, forward_axis
from .categories import (AxesWarning, ClockWarning, GapWarning, PlausibilityWarning, RateWarning, SaturationWarning,
                         UnitWarning)
from .clocks import check_clock, check_motion_start, check_overlap, motion_start
from .gnss import gnss_speed, gnss_velocity_ne
from .imu import check_imu, checked_by_caller, warn_imu
from .times import check_imu_times, check_steps
from .units import check_accel, check_gyro, check_latlon, check_magnetometer, check_saturation

__all__ = ["PlausibilityWarning", "UnitWarning", "AxesWarning", "ClockWarning", "RateWarning", "GapWarning",
           "SaturationWarning", "check_imu", "warn_imu", "checked_by_caller", "plausibility_warnings",
           "check_imu_times", "check_steps", "check_gyro", "check_accel", "check_saturation",
           "check_magnetometer", "check_latlon", "check_gravity", "forward_axis", "check_forward_axis",
           "check_overlap", "check_clock", "motion_start", "check_motion_start", "check_heading_aids",
           "gnss_speed", "gnss_velocity_ne"]


def plausibility_warnings(t, gyro, accel, gnss_t=(), lat_deg=(), lon_deg=(), align_time=2.0,
                          imu="IMU", gnss="GNSS", gnss_speed=None, gnss_vel=None,
                          rotation_fix="imu_rotation in [filter]") -> list:
    """The warnings of the checks of one GNSS/INS run, in the body's axes (each at most once):
    :func:`check_imu` (a navigation filter's axes; the clock is :func:`check_imu_times`'s), then
    the GNSS's units and clocks. ``gnss_vel``: (times, (K, 2) north/east velocity) of the GNSS
    (:func:`gnss_velocity_ne`) for the forward-axis check; ``rotation_fix``: how the user turns
    the IMU's axes (named by the axes warning)."""
    gnss_t = np.asarray(gnss_t)
    out = check_imu(gyro, accel, t=t, where=imu, rest_time=align_time, axes="frd",
                    rotation_fix=rotation_fix, names=("gyro_x/y/z", "accel_x/y/z"), clock=False)
    out += [check_latlon(np.asarray(lat_deg), np.asarray(lon_deg), gnss), check_overlap(t, gnss_t, gnss),
            check_clock(t, gnss_t, gnss), check_motion_start(t, gyro, gnss_t, gnss_speed, gnss, imu, accel)]
    if gnss_vel is not None:
        out.append(check_forward_axis(t, accel, gnss_vel[0], gnss_vel[1], imu))
    return [w for w in out if w is not None]
