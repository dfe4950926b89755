"""NMEA 0183 GNSS logs: GGA (position, fix quality, HDOP, geoid separation), RMC (date, course
and speed over ground), VTG (course and speed) and HDT/THS (true heading of a two-antenna
receiver or a gyrocompass: the ``compass`` stream, ``north="true"``, at the time of the last
GGA/RMC before it), any talker (GP, GN, GL, GA, BD, HE, ...).

Every sentence's checksum is verified; lines that fail it, lack it, or do not parse are counted
and reported in ``Log.notes`` (and the count in ``Log.bad_lines``), never used. Height is
ellipsoidal (GGA altitude + geoid separation). The horizontal sigma is HDOP times a user range
error per fix quality (:data:`UERE`), the vertical twice that. Course and speed give ``vel_n``
north and east; its down component is NaN (unknown). Times are UTC seconds from 1970 when an RMC
date was seen (``gnss.utc`` the same), else seconds of the day (midnight roll-overs unwrapped;
``gnss.utc`` None: no date).
"""
from __future__ import annotations

import calendar
import math
from functools import reduce

import numpy as np

from .log import Compass, Gnss, Log

__all__ = ["read_nmea", "checksum_ok", "UERE"]

#: GGA fix quality -> (name, range error m multiplied by HDOP, weight)
UERE = {1: ("gps", 2.5, 0.1), 2: ("dgps", 1.0, 0.3), 3: ("pps", 2.5, 0.1), 4: ("rtk-fix", 0.02, 1.0),
        5: ("rtk-float", 0.25, 0.5), 6: ("dead-reckoning", 10.0, 0.0), 9: ("sbas", 1.5, 0.2)}
_KNOT = 1852.0 / 3600.0


def checksum_ok(line: str) -> bool:
    """True when ``$...*HH`` carries the right XOR checksum."""
    if not line.startswith(("$", "!")) or "*" not in line:
        return False
    body, _, cs = line[1:].partition("*")
    try:
        return reduce(lambda a, c: a ^ ord(c), body, 0) == int(cs[:2], 16)
    except ValueError:
        return False


def looks_like_nmea(head: str) -> bool:
    return any(line.strip()[:1] == "$" and line.strip()[3:6] in ("GGA", "RMC", "VTG", "GSA", "GSV", "HDT", "THS")
               for line in head.splitlines()[:20])


def _latlon(v, hemi, deg_digits):
    if not v:
        return math.nan
    x = float(v[:deg_digits]) + float(v[deg_digits:]) / 60.0
    return -x if hemi in ("S", "W") else x


def _tod(s):
    return int(s[0:2]) * 3600 + int(s[2:4]) * 60 + float(s[4:])


def read_nmea(path) -> Log:
    """Read GGA/RMC/VTG sentences into a :class:`~quatnav.io.Log` with a ``gnss`` stream (one row
    per GGA with a fix; velocity from the RMC/VTG of the same epoch)."""
    epochs, order, bad, date0, last = {}, [], [], None, None
    headings = []  # (time of day of the epoch, heading deg)
    with open(path, errors="replace") as fh:
        for no, raw in enumerate(fh, 1):
            line = raw.strip()
            if not line:
                continue
            if not checksum_ok(line):
                bad.append(no)
                continue
            f = line[1:line.index("*")].split(",")
            kind = f[0][2:]
            try:
                if kind == "GGA":
                    if not f[1]:
                        continue
                    tod = _tod(f[1])
                    e = epochs.setdefault(tod, {})
                    if tod not in order:
                        order.append(tod)
                    q = int(f[6] or 0)
                    e.update(q=q, lat=_latlon(f[2], f[3], 2), lon=_latlon(f[4], f[5], 3),
                             hdop=float(f[8]) if f[8] else math.nan,
                             h=(float(f[9]) if f[9] else math.nan) + (float(f[11]) if f[11] else 0.0))
                    last = tod
                elif kind == "RMC":
                    if not f[1]:
                        continue
                    tod = _tod(f[1])
                    if f[9] and date0 is None:
                        d = f[9]
                        date0 = calendar.timegm((2000 + int(d[4:6]), int(d[2:4]), int(d[0:2]), 0, 0, 0, 0, 0, 0))
                    e = epochs.setdefault(tod, {})
                    if f[2] == "A" and f[7]:
                        e.update(speed=float(f[7]) * _KNOT, course=float(f[8]) if f[8] else math.nan)
                    last = tod
                elif kind in ("HDT", "THS") and last is not None:
                    # THS: heading, mode (A autonomous, E estimated, M manual, S simulator, V invalid)
                    if f[1] and not (kind == "THS" and len(f) > 2 and f[2] == "V"):
                        headings.append((last, float(f[1])))
                elif kind == "VTG" and last is not None:
                    spd = float(f[7]) / 3.6 if len(f) > 7 and f[7] else (float(f[5]) * _KNOT if f[5] else math.nan)
                    if math.isfinite(spd):
                        epochs[last].setdefault("speed", spd)
                        epochs[last].setdefault("course", float(f[1]) if f[1] else math.nan)
            except (ValueError, IndexError):
                bad.append(no)
    rows = [(tod, epochs[tod]) for tod in order if epochs[tod].get("q", 0) > 0 and math.isfinite(epochs[tod]["lat"])]
    notes = []
    if bad:
        shown = ", ".join(str(b) for b in bad[:5]) + (f" and {len(bad) - 5} more" if len(bad) > 5 else "")
        notes.append(f"{len(bad)} bad NMEA lines (checksum or format) skipped: lines {shown}")
    if not rows:
        raise ValueError(f"{path}: no GGA sentence with a fix (NMEA file with {len(bad)} bad lines)")
    tod = np.array([r[0] for r in rows], float)
    t = tod + 86400.0 * np.concatenate([[0], np.cumsum(np.diff(tod) < -43200)])
    if date0 is not None:
        t = t + date0
    e = [r[1] for r in rows]
    q = np.array([x["q"] for x in e])
    hdop = np.array([x["hdop"] for x in e])
    uere = np.array([UERE.get(k, ("?", 5.0, 0.0))[1] for k in q])
    sh = np.where(np.isfinite(hdop), hdop, 2.0) * uere
    spd = np.array([x.get("speed", math.nan) for x in e])
    crs = np.radians(np.array([x.get("course", math.nan) for x in e]))
    crs = np.where(np.isfinite(crs), crs, np.where(spd == 0, 0.0, np.nan))
    vel = np.column_stack([spd * np.cos(crs), spd * np.sin(crs), np.full(len(t), np.nan)])
    g = Gnss(t=t, lat=np.radians([x["lat"] for x in e]), lon=np.radians([x["lon"] for x in e]),
             h=np.array([x["h"] for x in e]), vel_n=vel if np.isfinite(spd).any() else None,
             sigma=np.column_stack([sh, sh, 2 * sh]), quality=q,
             weight=np.array([UERE.get(k, ("?", 5.0, 0.0))[2] for k in q]), quality_kind="nmea-gga",
             utc=t.copy() if date0 is not None else None)
    compass = None
    if headings:
        # the epoch times as for the fixes (midnight unwrapped over every epoch, the date added)
        every = np.array(order, float)
        wrap = every + 86400.0 * np.concatenate([[0], np.cumsum(np.diff(every) < -43200)])
        at = dict(zip(order, wrap + (date0 or 0.0)))
        th = np.array([at[tod] for tod, _ in headings])
        hd = np.radians([h for _, h in headings])
        keep = np.concatenate([[True], np.diff(th) > 0])  # one heading per epoch (the first)
        compass = Compass(t=th[keep], heading=np.angle(np.exp(1j * hd[keep])), north="true")
        notes.append(f"{int(keep.sum())} true headings (HDT/THS)")
    return Log(source=str(path), format="nmea", gnss=g, compass=compass, notes=notes, bad_lines=len(bad))
