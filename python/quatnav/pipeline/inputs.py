"""The inputs of a GNSS/INS run: IMU, GNSS, altimeter, compass, magnetometer and odometer, from
CSV files with named columns (their errors name the file, the line and the column), from any file
:func:`quatnav.io.read` knows, or from the streams of a :class:`quatnav.io.Log`; the GNSS fixes
checked as they are read (latitude and longitude in degrees, velocity and sigma triplets whole)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._command import InputError
from ..io.table import CsvError, read_table

__all__ = ["InsInputs", "read_ins_inputs", "read_csv", "mag_at_imu_rows", "IMU_COLUMNS", "IMU_INCREMENT_COLUMNS",
           "GNSS_COLUMNS", "GNSS_OPTIONAL", "BARO_COLUMNS", "COMPASS_COLUMNS", "MAG_COLUMNS", "ODOMETER_COLUMNS"]

IMU_COLUMNS = ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
IMU_INCREMENT_COLUMNS = ("time", "dtheta_x", "dtheta_y", "dtheta_z", "dvel_x", "dvel_y", "dvel_z")
MAG_COLUMNS = ("time", "mag_x", "mag_y", "mag_z")
ODOMETER_COLUMNS = ("time", "speed")
GNSS_COLUMNS = ("time", "lat", "lon", "h")
GNSS_OPTIONAL = ("v_n", "v_e", "v_d", "sigma_n", "sigma_e", "sigma_d", "sigma_vn", "sigma_ve", "sigma_vd")
BARO_COLUMNS = ("time", "h")
COMPASS_COLUMNS = ("time", "heading")


def read_csv(path, required, optional=(), what="file"):
    """Read a CSV with a header row; returns ({column: float array}, file line numbers).

    See :func:`quatnav.io.table.read_table`; raises :class:`InputError` naming the file, line, column.
    """
    try:
        tab = read_table(path, required, optional, what=what)
    except CsvError as e:
        raise InputError(str(e)) from None
    return tab.columns, tab.lines


def _columns_of(log, what):
    """The column dicts of :func:`read_ins_inputs`, from a :class:`quatnav.io.Log` stream (rows
    numbered from 1 as the 'lines' of messages)."""
    if what == "IMU":
        s = log.require("imu").imu
        d = {"time": s.t, **{f"gyro_{c}": s.gyr[:, i] for i, c in enumerate("xyz")},
             **{f"accel_{c}": s.acc[:, i] for i, c in enumerate("xyz")}}
    elif what == "GNSS":
        g = log.require("gnss").gnss
        nan = np.full((len(g.t), 3), np.nan)
        v, sg, sv = (x if x is not None else nan for x in (g.vel_n, g.sigma, g.sigma_vel))
        v = np.where(np.isnan(v).any(1, keepdims=True), np.nan, v)  # NMEA: no v_d -> no velocity
        sv = np.where(np.isnan(v).any(1, keepdims=True) | np.isnan(sv).any(1, keepdims=True), np.nan, sv)
        d = {"time": g.t, "lat": np.degrees(g.lat), "lon": np.degrees(g.lon), "h": g.h,
             **{k: v[:, i] for i, k in enumerate(("v_n", "v_e", "v_d"))},
             **{k: sg[:, i] for i, k in enumerate(("sigma_n", "sigma_e", "sigma_d"))},
             **{k: sv[:, i] for i, k in enumerate(("sigma_vn", "sigma_ve", "sigma_vd"))},
             "utc": g.utc if g.utc is not None else np.full(len(g.t), np.nan)}
        if g.quality is not None and g.quality_kind:
            # the receiver's solution kind per fix (RTKLIB Q, NMEA fix quality, PX4 fix_type):
            # GpsInsFilter.run(gps_solution=) takes each kind's sigma floor from it
            from ..filters.gpsins import gnss_solution
            d["solution"] = gnss_solution(g.quality, g.quality_kind)
    elif what == "BARO":
        b = log.require("baro").baro
        if b.altitude is None:
            raise InputError(f"{log.source}: the barometer gives pressure only, no altitude")
        d = {"time": b.t, "h": b.altitude}
    elif what == "MAG":
        m = log.require("mag").mag
        d = {"time": m.t, **{f"mag_{c}": m.values[:, i] for i, c in enumerate("xyz")}}
    else:
        c = log.require("compass").compass
        d = {"time": c.t, "heading": np.degrees(c.heading), "north": getattr(c, "north", "magnetic")}
    return d, np.arange(1, len(d["time"]) + 1)


def _reader(log, fmt):
    """A ``read_csv`` that takes any file :func:`quatnav.io.read` knows (CSV files keep the CSV
    reader and its messages); ``log`` (a Log) serves the files not given."""
    from .. import io

    def read(path, required, optional=(), what="file"):
        if path is None:
            return _columns_of(log, what)
        import os
        if not os.path.exists(path):
            kind = "csv"  # the CSV reader's message names the missing file
        else:
            kind = io.detect(path) if fmt == "auto" or log is not None else fmt
        if kind == "csv":
            return read_csv(path, required, optional, what=what)
        try:
            return _columns_of(io.read(path, format=kind), what)
        except ValueError as e:
            raise InputError(str(e)) from None
    return read


def _header_has(path, column) -> bool:
    """Whether a CSV file's header row (the first line that is not blank or a # comment) names
    ``column`` (case and surrounding spaces ignored)."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as fh:
            for line in fh:
                if line.strip() and not line.lstrip().startswith("#"):
                    import re
                    return column in [c.strip().lower() for c in re.split(r"[,;\t]", line)]
    except OSError:
        return False
    return False


def mag_at_imu_rows(t_imu, t_mag, mag):
    """The magnetometer samples as (N, 3) rows of the IMU record: each sample at the first IMU time
    at or after its own (the last one when several fall on a row); NaN rows where none."""
    out = np.full((len(t_imu), 3), np.nan)
    k = np.searchsorted(t_imu, t_mag, side="left")
    ok = (k > 0) & (k < len(t_imu))
    out[k[ok]] = mag[ok]
    return out


@dataclass(repr=False, eq=False)
class InsInputs:
    """What a GNSS/INS run reads: each stream as a dict of columns in the files' units (``lat``,
    ``lon`` and ``heading`` in degrees), None where not given.

    Attributes
    ----------
    t, gyro, accel : ndarray
        The IMU: times (N,), s; rates (N, 3), rad/s and specific force (N, 3), m/s^2 in the IMU's
        axes (or their increments, rad and m/s, where ``increments``).
    increments : bool
        Whether ``gyro`` and ``accel`` hold increments over each interval.
    imu_lines : (N,) ndarray
        The file line of each IMU row (a log's: the row number from 1), for messages.
    imu_source, gnss_source : str
        The file each was read from (for messages).
    gnss : dict
        ``time``, ``lat``, ``lon`` (deg), ``h`` (m), ``v_n v_e v_d``, ``sigma_n sigma_e sigma_d``,
        ``sigma_vn sigma_ve sigma_vd`` (NaN: not given), and ``utc`` where asked for.
    gnss_lines : ndarray
    baro, compass, mag, odometer : dict or None
        ``time`` and ``h`` (m); ``time``, ``heading`` (deg) and ``north`` ("true" for a GNSS
        heading); ``time``, ``mag_x mag_y mag_z``; ``time``, ``speed`` (m/s).
    """

    t: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    increments: bool
    imu_lines: np.ndarray
    imu_source: str
    gnss: dict
    gnss_lines: np.ndarray
    gnss_source: str
    baro: dict | None = None
    compass: dict | None = None
    mag: dict | None = None
    odometer: dict | None = None

    def __repr__(self) -> str:
        other = [k for k in ("baro", "compass", "mag", "odometer") if getattr(self, k) is not None]
        return (f"InsInputs(IMU {self.imu_source!r}: {len(self.t)} rows{' of increments' if self.increments else ''}; "
                f"GNSS {self.gnss_source!r}: {len(self.gnss['time'])} fixes"
                + (f"; {', '.join(other)}" if other else "") + ")")


def read_ins_inputs(log=None, *, imu=None, gnss=None, baro=None, compass=None, mag=None, odometer=None,
                    no_mag: bool = False, fmt: str = "auto", utc: bool = False) -> InsInputs:
    """Read the inputs of a GNSS/INS run.

    Parameters
    ----------
    log : quatnav.io.Log, optional
        A log whose streams serve where no file is given (its barometer where it gives an
        altitude, its compass, its magnetometer unless ``no_mag``).
    imu, gnss, baro, compass, mag, odometer : str or Path, optional
        Files that replace the log's streams: CSV with named columns (see ``quatnav ins run -h``;
        an IMU file with ``dtheta_x`` holds increments), or any file ``quatnav.io.read`` knows.
    no_mag : bool
        Leave the log's magnetometer out.
    fmt : str
        The format of the files (``"auto"``: detected; see :data:`quatnav.io.FORMATS`).
    utc : bool
        Also read the GNSS's ``utc`` column (UTC s since 1970: the date of the recording).

    Raises
    ------
    InputError
        A file that cannot be read, lacks a column or holds a value out of range: the message
        names the file, the line and the column.
    """
    if log is None and (imu is None or gnss is None):
        raise InputError("give --imu and --gnss, or --log")
    read = _reader(log, fmt)
    baro_from_log = log is not None and baro is None and log.baro is not None and log.baro.altitude is not None
    increments = imu is not None and _header_has(imu, "dtheta_x")
    d_imu, lines_i = read(imu, IMU_INCREMENT_COLUMNS if increments else IMU_COLUMNS, what="IMU")
    if increments:
        d_imu.update({f"gyro_{c}": d_imu[f"dtheta_{c}"] for c in "xyz"})
        d_imu.update({f"accel_{c}": d_imu[f"dvel_{c}"] for c in "xyz"})
    imu = imu or log.source
    if len(d_imu["time"]) < 2:
        raise InputError(f"IMU {imu}: needs at least two rows")
    try:  # utc (UTC s since 1970) dates the World Magnetic Model: read for --declination auto only
        d_g, lines_g = read(gnss, GNSS_COLUMNS, GNSS_OPTIONAL + (("utc",) if utc else ()), what="GNSS")
    except InputError as e:
        if "column 'utc'" not in str(e):
            raise
        raise InputError(f"{e} (utc: UTC seconds since 1970-01-01, Unix time; or give --date YYYY-MM-DD)") from None
    gnss = gnss or log.source
    _check_gnss(d_g, lines_g, gnss)
    out = InsInputs(t=d_imu["time"], gyro=np.column_stack([d_imu[c] for c in ("gyro_x", "gyro_y", "gyro_z")]),
                    accel=np.column_stack([d_imu[c] for c in ("accel_x", "accel_y", "accel_z")]),
                    increments=increments, imu_lines=lines_i, imu_source=str(imu), gnss=d_g, gnss_lines=lines_g,
                    gnss_source=str(gnss))
    if baro or baro_from_log:
        out.baro, _ = read(baro, BARO_COLUMNS, what="BARO")
    if compass or (log is not None and log.compass is not None):
        out.compass, _ = read(compass, COMPASS_COLUMNS, what="COMPASS")
    if odometer:
        out.odometer, _ = read(odometer, ODOMETER_COLUMNS, what="ODOMETER")
    if mag or (log is not None and log.mag is not None and not no_mag):
        out.mag, _ = read(mag, MAG_COLUMNS, what="MAG")
    return out


def _check_gnss(d_g, lines_g, gnss) -> None:
    """Refuse latitudes and longitudes beyond +-90 and +-360 deg, and velocity or sigma triplets
    given in part or sigmas that are not positive; the message names the file, line and column."""
    for c, lim in (("lat", 90.0), ("lon", 360.0)):
        bad = np.flatnonzero(np.abs(d_g[c]) > lim)
        if len(bad):
            raise InputError(f"GNSS {gnss}: line {lines_g[bad[0]]}, column {c!r}: {float(d_g[c][bad[0]])!r} is not "
                             f"a {'latitude' if c == 'lat' else 'longitude'} in degrees")
    for cols in (("v_n", "v_e", "v_d"), ("sigma_n", "sigma_e", "sigma_d"), ("sigma_vn", "sigma_ve", "sigma_vd")):
        a = np.column_stack([d_g[c] for c in cols])
        part = np.isnan(a).any(axis=1) & ~np.isnan(a).all(axis=1)
        if part.any():
            i = int(np.argmax(part))
            c = cols[int(np.argmax(np.isnan(a[i])))]
            raise InputError(f"GNSS {gnss}: line {lines_g[i]}, column {c!r}: empty while "
                             f"{', '.join(x for x in cols if x != c)} are given (give all three or none)")
        if cols[0].startswith("sigma"):
            neg = np.flatnonzero((a <= 0).any(axis=1))
            if len(neg):
                raise InputError(f"GNSS {gnss}: line {lines_g[neg[0]]}: {'/'.join(cols)} must be positive")
