"""The warning categories of the plausibility checks: one per kind of mistake, each a subclass of
:class:`PlausibilityWarning`, so that a user can silence or escalate one kind::

    import warnings, quatnav
    warnings.simplefilter("ignore", quatnav.AxesWarning)      # my IMU is mounted otherwise, I know
    warnings.simplefilter("error", quatnav.UnitWarning)       # refuse a log in the wrong units

Every message names the input, what was measured, and the fix.
"""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

__all__ = ["PlausibilityWarning", "UnitWarning", "AxesWarning", "ClockWarning", "RateWarning", "GapWarning",
           "SaturationWarning", "AidWarning", "issue"]

_PACKAGE = str(Path(__file__).resolve().parents[1])


class PlausibilityWarning(UserWarning):
    """Input that a filter accepts but that is most likely not what the user meant (a unit, the
    axes, the clocks, the rate, saturation); the message names the fix."""


class UnitWarning(PlausibilityWarning):
    """A column in another unit than the one expected: a gyro in deg/s, an accelerometer in g or
    mg, a magnetometer in gauss or nT, latitude/longitude in radians, times in ms."""


class AxesWarning(PlausibilityWarning):
    """Sensor axes that are not the body's forward-right-down (gravity not on -z at rest, the
    direction of travel off the x axis), or a reference in another frame (ENU against NED)."""


class ClockWarning(PlausibilityWarning):
    """Streams that are not on one clock: time ranges that do not overlap, an offset of leap
    seconds or of the GPS epoch, a GNSS that sees the motion start seconds before the IMU."""


class RateWarning(PlausibilityWarning):
    """An implausible sample rate (an IMU slower than 10 Hz, most often times in the wrong unit)."""


class GapWarning(RateWarning):
    """Samples missing: gaps in the IMU record longer than a filter's ``max_dt``."""


class SaturationWarning(PlausibilityWarning):
    """Samples at the sensor's range (clipped): the filter then sees less than the motion."""


class AidWarning(UserWarning):
    """An aid the filter cannot use as given: given to ``run`` with times all before or all after
    the IMU's (most often the two are on different clocks, e.g. Unix time and time since boot),
    or a heading aid the filter gated out in most samples (an uncalibrated or disturbed
    magnetometer). ``quatnav.AidWarning``; kept apart from :class:`PlausibilityWarning`, which
    judges the input alone, where this judges it against the filter's other sensors."""


def issue(messages) -> None:
    """Issue warning objects to the first caller outside quatnav, as :func:`warnings.warn` would
    from there (so that its filters and the line it names are the caller's)."""
    level, frame = 2, sys._getframe(1)  # stacklevel 2: the caller of issue
    while frame is not None and str(Path(frame.f_code.co_filename).resolve()).startswith(_PACKAGE):
        level, frame = level + 1, frame.f_back
    for m in messages:
        warnings.warn(m, stacklevel=level)
