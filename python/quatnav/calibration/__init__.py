"""Sensor calibration (magnetometer, accelerometer, gyroscope), its TOML file, and applying it
to samples before a filter sees them.

    cal = quatnav.calibration.magnetometer(mag_log, model="full")
    quatnav.calibration.save_calibration("cal.toml", mag=cal, gyro=quatnav.calibration.gyroscope(gyr, t))
    cal = quatnav.calibration.load_calibration("cal.toml")
    gyr, acc, mag = quatnav.calibration.apply(cal, gyr=gyr, acc=acc, mag=mag)

Every model is ``calibrated = matrix @ (raw - offset)``; see ``docs/CALIBRATION.md``.
"""
from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ._toml import dumps
from .mag_attitude import MagAttitudeFit, mag_attitude_fit
from .online import OnlineHardIron, hard_iron_track
from .sensors import (STANDARD_GRAVITY, SensorCalibration, accelerometer, gyroscope, magnetometer,
                      rest_segments, sphere_coverage)
from .time_offset import TimeOffsetEstimate, gps_time_offset

__all__ = ["Calibration", "SensorCalibration", "magnetometer", "accelerometer", "gyroscope",
           "rest_segments", "sphere_coverage", "apply", "save_calibration", "load_calibration",
           "apply_calibration_args", "STANDARD_GRAVITY", "OnlineHardIron", "hard_iron_track",
           "gps_time_offset", "TimeOffsetEstimate", "mag_attitude_fit", "MagAttitudeFit"]

_SENSORS = ("gyro", "acc", "mag")


@dataclass
class Calibration:
    """The calibrations of one IMU: any of ``gyro``, ``acc``, ``mag`` (None: not calibrated)."""

    gyro: SensorCalibration | None = None
    acc: SensorCalibration | None = None
    mag: SensorCalibration | None = None

    def to_toml(self) -> str:
        doc = {s: getattr(self, s).to_dict() for s in _SENSORS if getattr(self, s) is not None}
        return dumps(doc, header="quatnav calibration: calibrated = matrix @ (raw - offset), per sensor\n"
                     "read with quatnav.calibration.load_calibration or 'quatnav ... --calibration FILE'")

    def merged(self, other: "Calibration") -> "Calibration":
        """This calibration with the sensors ``other`` has replaced."""
        return Calibration(*(getattr(other, s) or getattr(self, s) for s in _SENSORS))


def _as_calibration(cal) -> Calibration:
    if isinstance(cal, Calibration):
        return cal
    if isinstance(cal, SensorCalibration):
        return Calibration(**{cal.sensor: cal})
    if isinstance(cal, (str, Path)):
        return load_calibration(cal)
    raise TypeError(f"cal must be a Calibration, a SensorCalibration or a path, got {type(cal).__name__}")


def save_calibration(path: "str | Path", cal: "Calibration | SensorCalibration | str | Path | None" = None, *,
                     gyro: SensorCalibration | None = None, acc: SensorCalibration | None = None,
                     mag: SensorCalibration | None = None) -> Calibration:
    """Write a calibration TOML file; with an existing file, the sensors given replace theirs and
    the others are kept (so ``calibrate mag`` then ``calibrate gyro`` build one file)."""
    new = _as_calibration(cal) if cal is not None else Calibration()
    new = new.merged(Calibration(gyro, acc, mag))
    path = Path(path)
    if path.exists():
        try:
            new = load_calibration(path).merged(new)
        except ValueError:
            pass  # not a calibration file: overwrite
    path.write_text(new.to_toml())
    return new


def load_calibration(path: "str | Path") -> Calibration:
    """Read a calibration TOML file (tables ``[gyro]``, ``[acc]``, ``[mag]``, each with ``offset``
    (3 numbers) and ``matrix`` (3 rows of 3); a missing one is the identity / zero)."""
    import tomllib
    path = Path(path)
    try:
        doc = tomllib.loads(path.read_text())
    except OSError as e:
        raise FileNotFoundError(f"calibration {path}: cannot open ({e.strerror})") from None
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"calibration {path}: not TOML ({e})") from None
    unknown = sorted(set(doc) - set(_SENSORS))
    if unknown:
        raise ValueError(f"calibration {path}: unknown table [{unknown[0]}] (known: gyro, acc, mag)")
    if not doc:
        raise ValueError(f"calibration {path}: no [gyro], [acc] or [mag] table")
    try:
        return Calibration(**{s: SensorCalibration.from_dict(s, doc[s]) for s in doc})
    except ValueError as e:
        raise ValueError(f"calibration {path}: {e}") from None


def apply(cal: "Calibration | SensorCalibration | str | Path", gyr: ArrayLike | None = None,
          acc: ArrayLike | None = None, mag: ArrayLike | None = None) -> tuple:
    """Calibrated ``(gyr, acc, mag)``: each given array through its sensor's calibration
    (unchanged when ``cal`` has none for it; None stays None). ``cal``: a :class:`Calibration`,
    a :class:`SensorCalibration` or a path to a calibration file."""
    cal = _as_calibration(cal)
    out = []
    for name, x in (("gyro", gyr), ("acc", acc), ("mag", mag)):
        c = getattr(cal, name)
        out.append(None if x is None else (np.asarray(x, float) if c is None else c.apply(x)))
    return tuple(out)


def apply_calibration_args(args: argparse.Namespace, gyr: ArrayLike | None = None, acc: ArrayLike | None = None,
                           mag: ArrayLike | None = None) -> tuple:
    """For a command with a ``--calibration FILE`` option (``args.calibration``): the samples
    calibrated with the file, or unchanged without the option. A bad file raises
    :class:`quatnav._command.UsageError` (one line, exit 2)."""
    path = getattr(args, "calibration", None)
    if not path:
        return gyr, acc, mag
    from .._command import UsageError
    try:
        cal = load_calibration(path)
    except (ValueError, FileNotFoundError) as e:
        raise UsageError(str(e)) from None
    return apply(cal, gyr=gyr, acc=acc, mag=mag)


def add_calibration_argument(parser: argparse.ArgumentParser) -> None:
    """Add ``--calibration FILE`` to an argparse parser (read by :func:`apply_calibration_args`)."""
    parser.add_argument("--calibration", metavar="CAL.toml",
                        help="apply this sensor calibration (from 'quatnav calibrate') to the samples first")
