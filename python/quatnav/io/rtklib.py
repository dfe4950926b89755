"""RTKLIB solution files (``.pos``, written by rtkpost/rnx2rtkp/rtknavi).

Every output option of RTKLIB is read: time as calendar date and time (GPST, UTC or JST label)
or GPS week and time of week; position as latitude/longitude in degrees or in
degrees-minutes-seconds, ECEF x/y/z, or an ENU baseline (converted with the ``ref pos`` of the
header); the sigma columns (sdn/sde/sdu, sdx/sdy/sdz or sde/sdn/sdu) when present, else a sigma
by solution quality; the velocity columns (vn/ve/vu) when present.

Times are seconds on the file's own scale counted from 1970-01-01 without leap seconds (a GPST
file gives GPST seconds; week/tow files the same scale), so files on one clock line up.
``gnss.utc`` is the same time in UTC (GPST less the leap seconds of its date,
:mod:`quatnav.core.timescales`; JST less 9 h): the date of the recording, and the times of a GPX
track.
"""
from __future__ import annotations

import calendar
import math

import numpy as np

from ..core import earth as E
from ..core.timescales import gps_to_utc
from .log import Gnss, Log

__all__ = ["read_pos", "QUALITY", "ecef_to_geodetic"]

#: RTKLIB Q -> (name, default horizontal sigma m, vertical sigma m, weight) when the file has no sigma columns.
QUALITY = {1: ("fix", 0.02, 0.04, 1.0), 2: ("float", 0.3, 0.6, 0.5), 3: ("sbas", 1.5, 3.0, 0.2),
           4: ("dgps", 0.8, 1.6, 0.3), 5: ("single", 3.0, 6.0, 0.1), 6: ("ppp", 0.2, 0.4, 0.6)}
_GPS_EPOCH = calendar.timegm((1980, 1, 6, 0, 0, 0, 0, 0, 0))


def ecef_to_geodetic(xyz):
    """(K, 3) ECEF m -> lat, lon (rad), h (m) on WGS-84 (Bowring, iterated; sub-mm)."""
    x, y, z = np.asarray(xyz, float).T
    a, f = E.A, 1 / 298.257223563
    e2 = f * (2 - f)
    lon = np.arctan2(y, x)
    p = np.hypot(x, y)
    lat = np.arctan2(z, p * (1 - e2))
    for _ in range(6):
        n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
        h = p / np.cos(lat) - n
        lat = np.arctan2(z, p * (1 - e2 * n / (n + h)))
    n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    h = p / np.cos(lat) - n
    return lat, lon, h


#: time scale of the file -> its offset from UTC, s (GPST: the leap seconds of its date)
_UTC_OFFSET = {"UTC": 0.0, "JST": 9 * 3600.0}


def _time(tok0, tok1):
    if "/" in tok0:
        y, mo, d = (int(x) for x in tok0.split("/"))
        hh, mm, ss = tok1.split(":")
        return calendar.timegm((y, mo, d, int(hh), int(mm), 0, 0, 0, 0)) + float(ss)
    return _GPS_EPOCH + int(tok0) * 604800 + float(tok1)


def _dms(d, m, s):
    sign = -1.0 if d.strip().startswith("-") else 1.0
    return sign * (abs(float(d)) + float(m) / 60 + float(s) / 3600)


def looks_like_pos(head: str) -> bool:
    return any(k in head for k in ("latitude(", "x-ecef(", "e-baseline(")) and "%" in head


def read_pos(path) -> Log:
    """Read an RTKLIB ``.pos`` file into a :class:`~quatnav.io.Log` with its ``gnss`` stream.

    ``gnss.quality`` is RTKLIB's Q (1 fix, 2 float, 3 SBAS, 4 DGPS, 5 single, 6 PPP),
    ``gnss.weight`` the weight of that kind (:data:`QUALITY`), ``gnss.sigma`` the file's
    sdn/sde/sdu (or the quality's default where the file has none or gives 0).
    """
    labels, ref, rows, times, timescale = None, None, [], [], "GPST"
    with open(path, errors="replace") as fh:
        for no, line in enumerate(fh, 1):
            s = line.strip()
            if not s:
                continue
            if s.startswith("%"):
                body = s[1:].split()
                if body and body[0] in ("GPST", "UTC", "JST") and len(body) > 3:
                    labels, timescale = body, body[0]
                elif "ref pos" in s and ":" in s:
                    try:
                        ref = [float(v) for v in s.split(":", 1)[1].split()[:3]]
                    except ValueError:
                        ref = None
                continue
            if labels is None:
                raise ValueError(f"{path}: not an RTKLIB .pos file (no '%  GPST latitude(deg) ...' header before "
                                 f"line {no})")
            p = s.split()
            try:
                times.append(_time(p[0], p[1]))
                rows.append(p[2:])
            except (ValueError, IndexError):
                raise ValueError(f"{path}: line {no}: cannot read the time {' '.join(p[:2])!r}") from None
    if labels is None or not rows:
        raise ValueError(f"{path}: no solution rows (an RTKLIB .pos file needs a header and data lines)")
    names = labels[1:]
    pos_kind = names[0]
    width = 3 if pos_kind.startswith("latitude(d'") else 1
    ncol = len(names) + (4 if width == 3 else 0)  # d m s: two more tokens each for latitude and longitude
    if any(len(r) < ncol for r in rows):
        bad = next(i for i, r in enumerate(rows) if len(r) < ncol)
        raise ValueError(f"{path}: solution row {bad + 1} has {len(rows[bad])} columns after the time, "
                         f"expected {ncol} (truncated file?)")
    try:
        if width == 3:
            a = np.array([[_dms(*r[0:3]), _dms(*r[3:6])] + [float(x) for x in r[6:ncol]] for r in rows])
            cols = ["latitude(deg)", "longitude(deg)"] + names[2:]
        else:
            a = np.array([[float(x) for x in r[:ncol]] for r in rows])
            cols = names
    except ValueError as e:
        raise ValueError(f"{path}: a solution row is not numeric ({e})") from None
    c = {n.split("(")[0].lower(): a[:, i] for i, n in enumerate(cols)}
    t = np.array(times)
    q = c["q"].astype(int)
    notes = [f"RTKLIB .pos, {timescale} time"]
    if "latitude" in c:
        lat, lon, h = np.radians(c["latitude"]), np.radians(c["longitude"]), c["height"]
        sd = [c.get("sdn"), c.get("sde"), c.get("sdu")]
    elif "x-ecef" in c:
        lat, lon, h = ecef_to_geodetic(np.column_stack([c["x-ecef"], c["y-ecef"], c["z-ecef"]]))
        sd = [None, None, None]  # ECEF sigmas would need the full covariance rotation: quality defaults used
        if "sdx" in c:
            notes.append("ECEF sigmas: the largest of sdx/sdy/sdz used for every axis")
            m = np.max(np.column_stack([c["sdx"], c["sdy"], c["sdz"]]), axis=1)
            sd = [m, m, m]
    elif "e-baseline" in c:
        if ref is None:
            raise ValueError(f"{path}: ENU baseline solution without a '% ref pos :' header line: the base position "
                             "is needed to convert it to latitude/longitude")
        lat0, lon0, h0 = math.radians(ref[0]), math.radians(ref[1]), ref[2]
        enu = np.column_stack([c["e-baseline"], c["n-baseline"], c["u-baseline"]])
        lat, lon, h = E.ned_to_geodetic(np.column_stack([enu[:, 1], enu[:, 0], -enu[:, 2]]), lat0, lon0, h0)
        sd = [c.get("sdn"), c.get("sde"), c.get("sdu")]
    else:
        raise ValueError(f"{path}: unknown position columns {pos_kind!r}")
    dflt_h = np.array([QUALITY.get(k, ("?", 10.0, 20.0, 0.0))[1] for k in q])
    dflt_v = np.array([QUALITY.get(k, ("?", 10.0, 20.0, 0.0))[2] for k in q])
    sigma = np.column_stack([x if x is not None else np.zeros(len(t)) for x in sd])
    dflt = np.column_stack([dflt_h, dflt_h, dflt_v])
    sigma = np.where(sigma > 0, sigma, dflt)
    weight = np.array([QUALITY.get(k, ("?", 0, 0, 0.0))[3] for k in q])
    vel = sig_v = None
    if "vn" in c:
        vel = np.column_stack([c["vn"], c["ve"], -c["vu"]])
        if "sdvn" in c:
            sig_v = np.column_stack([c["sdvn"], c["sdve"], c["sdvu"]])
    g = Gnss(t=t, lat=np.asarray(lat, float), lon=np.asarray(lon, float), h=np.asarray(h, float), vel_n=vel,
             sigma=sigma, sigma_vel=sig_v, quality=q, weight=weight, quality_kind="rtklib",
             utc=gps_to_utc(t) if timescale == "GPST" else t - _UTC_OFFSET[timescale])
    return Log(source=str(path), format="rtklib-pos", gnss=g, notes=notes)
