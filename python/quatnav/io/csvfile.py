"""CSV logs with a header row of named columns, read by :func:`quatnav.io.table.read_table` (the
columns of ``quatnav ins run``). One file may hold several streams on the same rows; what a file
holds is decided by its columns:

=========  ==========================================================================
stream     columns
=========  ==========================================================================
IMU        ``time gyro_x gyro_y gyro_z`` (rad/s) ``accel_x accel_y accel_z`` (m/s^2)
mag        ``mag_x mag_y mag_z`` (any unit; empty cells = no sample)
GNSS       ``time lat lon`` (deg) ``h`` (m); optional ``v_n v_e v_d``, ``sigma_n sigma_e sigma_d``,
           ``sigma_vn sigma_ve sigma_vd``, ``utc`` (UTC time of the fix, s since 1970-01-01: Unix
           time; it dates the recording; a column of other text is noted and ignored)
baro       ``time h`` (without lat/lon)
compass    ``time heading`` (deg)
reference  ``time q_w q_x q_y q_z`` (the output of ``quatnav ahrs run`` reads back as one);
           or ``lat lon h`` / ``v_n v_e v_d`` together with ``roll pitch yaw`` (deg; ``quatnav
           ins run`` output)
=========  ==========================================================================
"""
from __future__ import annotations

import numpy as np

from ..core import quaternion as Q
from .table import CsvError, no_header, numbers_only, read_table
from .log import Baro, Compass, Gnss, Imu, Log, Mag, Reference

__all__ = ["read_csv", "header_names"]

IMU = ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")


def header_names(path) -> list:
    with open(path, encoding="utf-8-sig", errors="replace") as fh:
        for line in fh:
            s = line.strip()
            if s and not s.startswith("#"):
                for sep in (",", ";", "\t"):
                    if sep in s:
                        return [c.strip().lower() for c in s.split(sep)]
                return [s.lower()]
    return []


def _v(c, names):
    return np.column_stack([c[n] for n in names])


def read_csv(path, *, kind: str | None = None) -> Log:
    """Read a CSV log; ``kind`` ("imu", "gnss", "baro", "compass", "reference") forces what the
    file is read as, else the columns decide (see the module text)."""
    h = set(header_names(path))
    log = Log(source=str(path), format="csv")
    want = {kind} if kind else set()
    if not kind:
        if set(IMU) <= h:
            want.add("imu")
        if {"time", "lat", "lon", "h"} <= h and not {"roll", "q_w"} & h:
            want.add("gnss")
        if {"time", "h"} <= h and not {"lat", "lon"} & h and "imu" not in want:
            want.add("baro")
        if {"time", "heading"} <= h:
            want.add("compass")
        if {"time", "q_w", "q_x", "q_y", "q_z"} <= h or {"time", "roll", "pitch", "yaw"} <= h:
            want.add("reference")
    if not want and numbers_only(h):
        raise ValueError(no_header(str(path), IMU))
    if not want:
        raise ValueError(f"{path}: CSV columns {sorted(h)} match no stream (IMU needs {', '.join(IMU)})")
    if "imu" in want:
        opt = ("mag_x", "mag_y", "mag_z")
        c = read_table(path, IMU, opt, what="IMU").columns
        log.imu = Imu(t=c["time"], gyr=_v(c, IMU[1:4]), acc=_v(c, IMU[4:7]))
        if {"mag_x", "mag_y", "mag_z"} <= h:
            m = _v(c, opt)
            ok = np.isfinite(m).all(1)
            log.mag = Mag(t=c["time"][ok], values=m[ok], unit="as in the file")
    if "gnss" in want:
        opt = ("v_n", "v_e", "v_d", "sigma_n", "sigma_e", "sigma_d", "sigma_vn", "sigma_ve", "sigma_vd")
        c = read_table(path, ("time", "lat", "lon", "h"), opt, what="GNSS").columns
        vel = _v(c, opt[:3])
        sig = _v(c, opt[3:6])
        sv = _v(c, opt[6:9])
        log.gnss = Gnss(t=c["time"], lat=np.radians(c["lat"]), lon=np.radians(c["lon"]), h=c["h"],
                        vel_n=vel if np.isfinite(vel).any() else None, sigma=sig if np.isfinite(sig).any() else None,
                        sigma_vel=sv if np.isfinite(sv).any() else None)
        if "utc" in h:  # read apart: a utc column of dates as text (this reader's numbers only) stays harmless
            try:
                u = read_table(path, ("time",), ("utc",), what="GNSS").columns["utc"]
                log.gnss.utc = u if np.isfinite(u).any() else None
            except CsvError as e:
                log.notes.append(f"GNSS utc column ignored (expected UTC seconds since 1970): {e}")
    if "baro" in want:
        c = read_table(path, ("time", "h"), what="BARO").columns
        log.baro = Baro(t=c["time"], altitude=c["h"])
    if "compass" in want:
        c = read_table(path, ("time", "heading"), what="COMPASS").columns
        log.compass = Compass(t=c["time"], heading=np.radians(c["heading"]))
    if "reference" in want:
        opt = ("q_w", "q_x", "q_y", "q_z", "roll", "pitch", "yaw", "lat", "lon", "h", "v_n", "v_e", "v_d")
        c = read_table(path, ("time",), opt, what="track").columns
        if {"q_w", "q_x", "q_y", "q_z"} <= h:
            q = _v(c, ("q_w", "q_x", "q_y", "q_z"))
        elif {"roll", "pitch", "yaw"} <= h:
            q = Q.from_euler(np.radians(_v(c, ("roll", "pitch", "yaw"))))
        else:
            q = None
        ref = Reference(t=c["time"], quat=q, name=str(path))
        if {"lat", "lon", "h"} <= h:
            ref.lat, ref.lon, ref.h = np.radians(c["lat"]), np.radians(c["lon"]), c["h"]
        if {"v_n", "v_e", "v_d"} <= h:
            ref.vel_n = _v(c, ("v_n", "v_e", "v_d"))
        log.reference = ref
    return log
