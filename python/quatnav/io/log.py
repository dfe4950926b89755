"""The in-memory log every reader of :mod:`quatnav.io` returns: one :class:`Log` of streams, each
with its own times (seconds on the log's clock), in quatnav's conventions: body frame
forward-right-down, navigation frame NED, quaternions [w, x, y, z] ``q_nb``, SI units, radians."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Imu", "Mag", "Gnss", "Baro", "Compass", "Reference", "Log"]


@dataclass
class Imu:
    """``t`` (N,) s; ``gyr`` (N, 3) rad/s; ``acc`` (N, 3) m/s^2 (specific force), body FRD."""
    t: np.ndarray
    gyr: np.ndarray
    acc: np.ndarray


@dataclass
class Mag:
    """``t`` (M,) s; ``values`` (M, 3) magnetic field in the body frame FRD, in ``unit``."""
    t: np.ndarray
    values: np.ndarray
    unit: str = "unknown"


@dataclass
class Gnss:
    """GNSS fixes. ``lat``, ``lon`` rad, ``h`` m (ellipsoidal, antenna); optional ``vel_n``
    (K, 3) NED m/s, ``sigma`` (K, 3) position one-sigma north/east/down m, ``sigma_vel`` (K, 3)
    m/s, ``quality`` (K,) int (the format's fix quality code, see ``quality_kind``), ``weight``
    (K,) in [0, 1] (1 = the best fix kind of the format, 0 = no fix), ``utc`` (K,) the UTC time
    of each fix, s since 1970-01-01 (Unix time; NaN where the receiver gave none; None: the
    format carries no date), which dates the recording (the epoch of the World Magnetic Model)."""
    t: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    h: np.ndarray
    vel_n: np.ndarray | None = None
    sigma: np.ndarray | None = None
    sigma_vel: np.ndarray | None = None
    quality: np.ndarray | None = None
    weight: np.ndarray | None = None
    quality_kind: str = ""
    utc: np.ndarray | None = None


@dataclass
class Baro:
    """``t`` (B,) s; ``altitude`` (B,) m, or ``pressure`` (B,) Pa (at least one given)."""
    t: np.ndarray
    altitude: np.ndarray | None = None
    pressure: np.ndarray | None = None


@dataclass
class Compass:
    """``t`` (C,) s; ``heading`` (C,) rad, clockwise from north; ``north`` says from which:
    ``"magnetic"`` (a compass, a magnetometer's heading) or ``"true"`` (a GNSS heading: NMEA
    HDT/THS, PX4's GPS yaw from two antennas)."""
    t: np.ndarray
    heading: np.ndarray
    north: str = "magnetic"


@dataclass
class Reference:
    """A track to compare with (truth or the log's own estimate): ``t`` (R,) s, ``quat`` (R, 4)
    q_nb [w, x, y, z] or None; optional ``lat lon`` rad, ``h`` m, ``p_n`` (R, 3) NED m (from
    the log's own origin), ``vel_n`` (R, 3) NED m/s."""
    t: np.ndarray
    quat: np.ndarray | None = None
    lat: np.ndarray | None = None
    lon: np.ndarray | None = None
    h: np.ndarray | None = None
    p_n: np.ndarray | None = None
    vel_n: np.ndarray | None = None
    name: str = "reference"


@dataclass
class Log:
    """Everything read from one file. Streams the file does not carry are None.

    ``source`` is the file, ``format`` the reader that read it, ``notes`` what the reader says
    about the file (conversions done, lines skipped)."""
    source: str = ""
    format: str = ""
    imu: Imu | None = None
    mag: Mag | None = None
    gnss: Gnss | None = None
    baro: Baro | None = None
    compass: Compass | None = None
    reference: Reference | None = None
    notes: list = field(default_factory=list)
    bad_lines: int = 0

    def streams(self) -> list:
        """Names of the streams present."""
        return [n for n in ("imu", "mag", "gnss", "baro", "compass", "reference") if getattr(self, n) is not None]

    def require(self, *names) -> "Log":
        """Raise ``ValueError`` naming the file and the first stream of ``names`` it lacks."""
        for n in names:
            if getattr(self, n) is None:
                have = ", ".join(self.streams()) or "nothing readable"
                raise ValueError(f"{self.source}: no {n.upper() if n in ('imu', 'gnss') else n} data in this "
                                 f"{self.format or 'file'} (it has: {have})")
        return self

    def merge(self, other: "Log") -> "Log":
        """A new Log with this one's streams, completed by ``other``'s where this has none."""
        out = Log(source=self.source, format=self.format, notes=self.notes + other.notes)
        for n in ("imu", "mag", "gnss", "baro", "compass", "reference"):
            setattr(out, n, getattr(self, n) if getattr(self, n) is not None else getattr(other, n))
        return out

    def __repr__(self) -> str:
        parts = []
        for n in self.streams():
            s = getattr(self, n)
            parts.append(f"{n}={len(s.t)}")
        return f"Log({self.format} {self.source!r}: {', '.join(parts) or 'empty'})"


def mag_on_imu_times(log: Log) -> np.ndarray | None:
    """(N, 3) magnetometer samples on the IMU rows: the latest sample since the previous IMU row,
    NaN rows where none arrived (the attitude filters' convention for sensors at other rates)."""
    if log.mag is None or log.imu is None:
        return None
    t = log.imu.t
    out = np.full((len(t), 3), np.nan)
    k = np.searchsorted(t, log.mag.t, side="left")  # mag sample goes on the first IMU row at or after it
    ok = k < len(t)
    out[k[ok]] = log.mag.values[ok]
    return out
